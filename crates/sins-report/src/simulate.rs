//! Simulating a scenario into a dataset file in the project's format (used by `simulate` and by
//! the blind suite).

use crate::{Progress, ReportError};
use sins_data::{ColumnSet, DatasetMeta, DatasetWriter, ReferenceRow, SampleBatch, WriteSummary};
use sins_imu::ImuSample;
use sins_nav::attitude::euler_from_ned_from_body;
use sins_sim::{Scenario, SimBatch, Simulator};
use std::path::Path;

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
