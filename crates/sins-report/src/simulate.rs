//! Simulating a scenario into a dataset file in the project's format (used by `simulate` and by
//! the blind suite).

use crate::{Progress, ReportError};
use sins_data::{ColumnSet, DatasetMeta, DatasetWriter, ReferenceRow, SampleBatch, WriteSummary};
use sins_imu::ImuSample;
use sins_nav::attitude::euler_from_ned_from_body;
use sins_sim::{Scenario, SimBatch, Simulator};
use std::path::Path;

/// Upper bound of the bytes per row of a simulated Parquet dataset beyond its Float64 columns:
/// the dictionary index of the segment label (at most 2 bytes) plus page and row-group overhead.
const PARQUET_ROW_EXTRA_BYTES: u64 = 3;
/// Upper bound of the bytes of one Float64 value in a CSV dataset: a comma and up to 24
/// characters of shortest round-trip decimal (`-1.2345678901234567e-10`).
const CSV_VALUE_BYTES: u64 = 25;
/// Upper bound of the bytes per CSV row beyond its Float64 values: the segment label (up to 40
/// characters in practice) and the line end.
const CSV_ROW_EXTRA_BYTES: u64 = 42;
/// Bytes of file-level metadata, footer and header, whatever the row count.
const FILE_EXTRA_BYTES: u64 = 1 << 20;

/// Upper bound of the size (bytes) of a simulated dataset of `n_rows` rows with the temperature
/// and segment columns and, when `reference`, the nine truth columns; `csv` for the CSV format.
/// Parquet counts every Float64 at its raw 8 bytes (LZ4 pages never grow noisy data; the paper's
/// 15 h / 200 Hz navigation run, estimated at 886 MB, is 572 MB), so the estimate errs on the
/// safe side.
pub fn estimated_dataset_bytes(n_rows: u64, reference: bool, csv: bool) -> u64 {
    let floats: u64 = 7 + 3 + if reference { 9 } else { 0 };
    let per_row = if csv {
        floats * CSV_VALUE_BYTES + CSV_ROW_EXTRA_BYTES
    } else {
        floats * 8 + PARQUET_ROW_EXTRA_BYTES
    };
    n_rows
        .saturating_mul(per_row)
        .saturating_add(FILE_EXTRA_BYTES)
}

/// True when `file` is written as CSV (its extension is `.csv`, any case).
fn is_csv(file: &Path) -> bool {
    file.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
}

/// Refuse to write `needed_bytes` at `path` (a file or directory, existing or not) when they
/// exceed the space available to this user on its file system, or `limit_bytes` when given,
/// before anything is written. The error names the path, the estimate and the free space (or the
/// limit).
pub fn check_output_space(
    path: &Path,
    needed_bytes: u64,
    limit_bytes: Option<u64>,
) -> Result<(), ReportError> {
    let refuse = |kind: std::io::ErrorKind, msg: String| {
        Err(ReportError::io(path, std::io::Error::new(kind, msg)))
    };
    if let Some(limit) = limit_bytes
        && needed_bytes > limit
    {
        return refuse(
            std::io::ErrorKind::InvalidInput,
            format!(
                "refused before writing anything: the output is estimated at up to {}, above \
                 the configured limit of {}",
                human_bytes(needed_bytes),
                human_bytes(limit)
            ),
        );
    }
    // The nearest existing ancestor tells the file system the output will land on.
    let Some(existing) = path.ancestors().find(|a| {
        let a = if a.as_os_str().is_empty() {
            Path::new(".")
        } else {
            a
        };
        a.exists()
    }) else {
        return Ok(());
    };
    let existing = if existing.as_os_str().is_empty() {
        Path::new(".")
    } else {
        existing
    };
    let free = fs4::available_space(existing).map_err(|e| ReportError::io(existing, e))?;
    if needed_bytes > free {
        return refuse(
            std::io::ErrorKind::StorageFull,
            format!(
                "refused before writing anything: the output is estimated at up to {} but only \
                 {} are free on the file system of {}",
                human_bytes(needed_bytes),
                human_bytes(free),
                existing.display()
            ),
        );
    }
    Ok(())
}

/// `bytes` as "886.0 MB" / "2.31 TB" (decimal units).
pub fn human_bytes(bytes: u64) -> String {
    let b = bytes as f64;
    match b {
        b if b >= 1e12 => format!("{:.2} TB", b / 1e12),
        b if b >= 1e9 => format!("{:.2} GB", b / 1e9),
        b if b >= 1e6 => format!("{:.1} MB", b / 1e6),
        b if b >= 1e3 => format!("{:.1} kB", b / 1e3),
        _ => format!("{bytes} B"),
    }
}

/// Dataset metadata for a simulated scenario: site, rate, description, and the experiment,
/// run, seed and initial attitude as extra keys.
pub fn dataset_meta(experiment: &str, scenario: &Scenario) -> DatasetMeta {
    let mut meta = DatasetMeta::new(
        scenario.rate_hz,
        scenario.site,
        scenario.description.clone(),
    );
    let e = euler_from_ned_from_body(&scenario.motion.initial_ned_from_body);
    for (k, v) in [
        ("experiment", experiment.to_string()),
        ("run", scenario.name.clone()),
        ("seed", scenario.seed.to_string()),
        ("initial_pitch_deg", e.pitch_rad.to_degrees().to_string()),
        ("initial_roll_deg", e.roll_rad.to_degrees().to_string()),
        ("initial_yaw_deg", e.yaw_rad.to_degrees().to_string()),
    ] {
        meta.extra.insert(k.to_string(), v);
    }
    meta
}

/// Simulate `scenario` of `experiment` into `file` (Parquet or CSV by extension; written aside
/// and renamed when complete).
pub fn simulate_to_dataset(
    experiment: &str,
    scenario: &Scenario,
    file: &Path,
    progress: &mut dyn Progress,
) -> Result<WriteSummary, ReportError> {
    simulate_to_dataset_with(experiment, scenario, file, progress, &mut |_| Ok(()))
}

/// [`simulate_to_dataset`], also handing every batch of samples to `also` as it is written
/// (e.g. a calibration filter, so that a run is simulated once for both).
pub fn simulate_to_dataset_with(
    experiment: &str,
    scenario: &Scenario,
    file: &Path,
    progress: &mut dyn Progress,
    also: &mut dyn FnMut(&[ImuSample]) -> Result<(), ReportError>,
) -> Result<WriteSummary, ReportError> {
    let mut sim = Simulator::from_scenario(scenario).map_err(|source| {
        ReportError::Harness(sins_harness::HarnessError::Simulation {
            run: scenario.name.clone(),
            source,
        })
    })?;
    let n_rows = sim.n_samples() as u64;
    let needed = estimated_dataset_bytes(n_rows, scenario.with_reference, is_csv(file));
    check_output_space(file, needed, None)?;
    let labels = sim.segment_labels().to_vec();
    let label_of_segment = sim.segment_label_indices().to_vec();
    let columns = ColumnSet {
        temperature: true,
        segment: true,
        reference: scenario.with_reference,
    };
    let mut writer =
        DatasetWriter::create(file, &dataset_meta(experiment, scenario), columns, &labels)?;
    progress.begin(&scenario.name, sim.n_samples() as u64);
    let mut batch = SampleBatch {
        first_row: 0,
        samples: Vec::new(),
        segment_index: Some(Vec::new()),
        reference: None,
    };
    sim.run(65_536, |b: &SimBatch| -> Result<(), ReportError> {
        to_sample_batch(b, &label_of_segment, &mut batch);
        writer.write_batch(&batch)?;
        also(&b.samples)?;
        progress.advance(b.samples.len() as u64);
        Ok(())
    })?;
    progress.end();
    Ok(writer.finish()?)
}

fn to_sample_batch(b: &SimBatch, label_of_segment: &[u16], out: &mut SampleBatch) {
    out.samples.clear();
    out.samples.extend_from_slice(&b.samples);
    let seg = out.segment_index.get_or_insert_with(Vec::new);
    seg.clear();
    seg.extend(
        b.segment_index
            .iter()
            .map(|&s| label_of_segment.get(s as usize).copied().unwrap_or(0)),
    );
    out.reference = b.reference.as_ref().map(|refs| {
        refs.iter()
            .map(|r| {
                let e = euler_from_ned_from_body(&r.ned_from_body);
                ReferenceRow {
                    lat_rad: r.position.lat_rad,
                    lon_rad: r.position.lon_rad,
                    height_m: r.position.height_m,
                    vel_n_mps: r.vel_ned_mps.x,
                    vel_e_mps: r.vel_ned_mps.y,
                    vel_d_mps: r.vel_ned_mps.z,
                    pitch_rad: e.pitch_rad,
                    roll_rad: e.roll_rad,
                    yaw_rad: e.yaw_rad,
                }
            })
            .collect()
    });
}
