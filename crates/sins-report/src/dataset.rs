//! Replaying a dataset file under one or more parameter sets. Errors are against the fixed site
//! (turntable data), or against the reference columns when the dataset has them (the truth may
//! then move: the error is the navigated offset from the site minus the reference's).

use crate::ReportError;
use crate::progress::Progress;
use sins_data::{DatasetReader, ReferenceRow};
use sins_harness::pipeline::{MultiReplay, NamedParams, RunOutcome};
use sins_imu::ParamModel;
use sins_nav::attitude::ned_from_body_euler;
use sins_nav::{Euler, Geodetic, Quat};
use sins_replay::setup::ReplayOptions;
use std::path::Path;

/// The reference state at one output time.
struct RefPoint {
    t_s: f64,
    north_m: f64,
    east_m: f64,
    vel_n_mps: f64,
    vel_e_mps: f64,
    ned_from_body: Quat,
}

fn ref_point(t_s: f64, r: &ReferenceRow, site: &Geodetic) -> RefPoint {
    let d = Geodetic {
        lat_rad: r.lat_rad,
        lon_rad: r.lon_rad,
        height_m: r.height_m,
    }
    .ned_offset_from_m(site);
    RefPoint {
        t_s,
        north_m: d.x,
        east_m: d.y,
        vel_n_mps: r.vel_n_mps,
        vel_e_mps: r.vel_e_mps,
        ned_from_body: ned_from_body_euler(&Euler {
            pitch_rad: r.pitch_rad,
            roll_rad: r.roll_rad,
            yaw_rad: r.yaw_rad,
        }),
    }
}

/// Refuse a dataset without the accelerometer temperature columns when any of `sets` is a
/// 42-state set (its temperature terms need them), naming the file and the set.
pub fn require_temperatures(
    path: &Path,
    info: &sins_data::DatasetInfo,
    sets: &[NamedParams],
) -> Result<(), ReportError> {
    match sets.iter().find(|s| s.params.model == ParamModel::States42) {
        Some(s) if !info.has_temperature => Err(ReportError::Mismatch(format!(
            "{}: the dataset has no accelerometer temperature columns (temp_ax_degc, temp_ay_degc, temp_az_degc), \
             but parameter set '{}' is a 42-state set with temperature coefficients",
            path.display(),
            s.key
        ))),
        _ => Ok(()),
    }
}

/// Replay the dataset at `path` (named `name` in results) under every set of `sets`.
pub fn replay_dataset(
    name: &str,
    path: &Path,
    sets: &[NamedParams],
    options: &ReplayOptions,
    progress: &mut dyn Progress,
) -> Result<RunOutcome, ReportError> {
    let mut reader = DatasetReader::open(path)?;
    let info = reader.info().clone();
    require_temperatures(path, &info, sets)?;
    let options = &ReplayOptions {
        stamped_intervals: info.meta.recorded_stamps(),
        ..*options
    };
    let site = info.meta.site;
    let h = info.meta.sample_interval_s();
    let per_output = ((options.output_interval_s / h).round() as usize).max(1);
    let mut refs: Option<Vec<RefPoint>> = info.columns.reference.then(Vec::new);
    let mut row = 0usize;
    let mut multi: Option<MultiReplay> = None;
    progress.begin(&format!("replay {name}"), info.n_rows);
    while let Some(batch) = reader.next_batch()? {
        progress.advance(batch.samples.len() as u64);
        // Samples whose interval starts before `start_s` are not replayed.
        let skip = options.start_s.map_or(0, |t0| {
            batch.samples.partition_point(|s| s.t_s - h < t0 - 1e-9 * h)
        });
        let Some(first) = batch.samples.get(skip) else {
            continue;
        };
        let multi = match &mut multi {
            Some(m) => m,
            None => multi.insert(MultiReplay::new(
                name,
                sets,
                site,
                h,
                first.t_s - h,
                info.segment_labels.clone(),
                options,
            )?),
        };
        let samples = &batch.samples[skip..];
        multi.push_batch(samples, batch.segment_index.as_deref().map(|g| &g[skip..]))?;
        if let (Some(out), Some(rows)) = (&mut refs, &batch.reference) {
            for (s, r) in samples.iter().zip(&rows[skip..]) {
                row += 1;
                if row.is_multiple_of(per_output) {
                    out.push(ref_point(s.t_s, r, &site));
                }
            }
        }
    }
    progress.end();
    let multi = multi.ok_or_else(|| {
        ReportError::Mismatch(format!(
            "{}: no sample at or after the start time {:?} s",
            path.display(),
            options.start_s
        ))
    })?;
    let mut outcome = multi.finish()?;
    if let Some(refs) = refs {
        for track in &mut outcome.tracks {
            subtract_reference(&mut track.points, &refs);
            track.summary =
                sins_replay::ReplaySummary::from_points(&track.points, track.summary.navigated_s);
            track.stretches = sins_harness::segments::stretches(&track.points, &outcome.labels);
        }
        outcome.truth_attitude = Some(refs.iter().map(|r| (r.t_s, r.ned_from_body)).collect());
    }
    Ok(outcome)
}

/// Turn site-relative errors into reference-relative ones (points and references share the
/// output times; a point without a reference at its time is left as it is).
fn subtract_reference(points: &mut [sins_harness::ErrorPoint], refs: &[RefPoint]) {
    let mut k = 0usize;
    for p in points {
        while k + 1 < refs.len() && refs[k].t_s < p.t_s - 1e-6 {
            k += 1;
        }
        if let Some(r) = refs.get(k)
            && (r.t_s - p.t_s).abs() < 1e-6
        {
            p.north_m -= r.north_m;
            p.east_m -= r.east_m;
            p.vel_n_mps -= r.vel_n_mps;
            p.vel_e_mps -= r.vel_e_mps;
        }
    }
}
