//! Running a report configuration: parameter sets (calibrated here or read from files), then
//! every navigation experiment (simulated in memory, or read from datasets) replayed under every
//! set in one pass over its samples.

use crate::ReportError;
use crate::dataset::replay_dataset;
use sins_config::{load_experiment, load_params, load_table5, model_name};
use sins_harness::config::{NavigationSource, ParamOrigin, ReportConfig};
use sins_harness::parallel::map_with_progress;
use sins_harness::pipeline::{
    NamedParams, RunOutcome, scenario_samples, simulate_and_calibrate, simulate_and_replay,
};
use sins_harness::reference::PaperRow;
use sins_harness::summary::{ExperimentSummary, ParamSetInfo, SUMMARY_SCHEMA, Summary};
use sins_imu::{ImuErrorParams, ParamModel};
use std::time::Instant;

use crate::progress::Progress;

/// A parameter set ready to replay with.
#[derive(Clone, Debug)]
pub struct ResolvedSet {
    /// Key.
    pub key: String,
    /// Human label.
    pub label: String,
    /// Coefficients.
    pub params: ImuErrorParams,
    /// 1-sigma of each coefficient, when known.
    pub sigma: Option<ImuErrorParams>,
    /// Where it came from.
    pub source: String,
    /// True when this report calibrated it (it is then written beside the report).
    pub calibrated: bool,
}

/// A report that ran: everything [`crate::write_report`] writes.
#[derive(Clone, Debug)]
pub struct ReportRun {
    /// The configuration.
    pub config: ReportConfig,
    /// The parameter sets.
    pub sets: Vec<ResolvedSet>,
    /// One outcome per experiment.
    pub outcomes: Vec<RunOutcome>,
    /// The machine-readable results.
    pub summary: Summary,
    /// The paper's Table 5, when configured.
    pub paper: Vec<PaperRow>,
    /// Wall time of each step (name, seconds).
    pub timings: Vec<(String, f64)>,
    /// A section placed after Table 5 in `report.md` (e.g. the replica's UQ intervals and
    /// V&V verdicts of `report --uq DIR`).
    pub appendix: Option<String>,
}

/// Run `config`, the simulated calibration runs and then the simulated navigation runs each on
/// up to `threads` threads (the results do not depend on it; datasets are replayed one after
/// the other).
pub fn run_report(
    config: &ReportConfig,
    threads: usize,
    progress: &mut dyn Progress,
) -> Result<ReportRun, ReportError> {
    let mut timings = Vec::new();
    let started = Instant::now();
    let sets = resolve_sets(config, threads, progress)?;
    timings.push((
        "parameter sets".to_string(),
        started.elapsed().as_secs_f64(),
    ));
    let named: Vec<NamedParams> = sets
        .iter()
        .map(|s| NamedParams {
            key: s.key.clone(),
            params: s.params,
        })
        .collect();
    let mut outcomes = Vec::new();
    let mut sources = Vec::new();
    match &config.navigation {
        NavigationSource::Experiment(path) => {
            let mut exp = load_experiment(path)?;
            for sc in &mut exp.scenarios {
                apply_noise_seed(sc, config.noise_seed);
            }
            let total = exp
                .scenarios
                .iter()
                .map(scenario_samples)
                .sum::<Result<u64, _>>()?;
            let names: Vec<&str> = exp.scenarios.iter().map(|s| s.name.as_str()).collect();
            let phase = Instant::now();
            progress.begin(&format!("simulate + replay {}", names.join(", ")), total);
            // Each run is simulated from its own seed and replayed alone: the outcomes do not
            // depend on the thread count.
            let results = map_with_progress(
                exp.scenarios.len(),
                threads,
                |i, done| {
                    let t = Instant::now();
                    simulate_and_replay(
                        &exp.scenarios[i],
                        &named,
                        &config.replay,
                        threads,
                        &mut |n| done(n),
                    )
                    .map(|o| (o, t.elapsed().as_secs_f64()))
                },
                &mut |n| progress.advance(n),
            );
            progress.end();
            for (sc, result) in exp.scenarios.iter().zip(results) {
                let (outcome, secs) = result?;
                timings.push((format!("{} (simulate + replay)", sc.name), secs));
                sources.push(format!(
                    "simulated: {} run '{}' (seed {})",
                    path.display(),
                    sc.name,
                    sc.seed
                ));
                outcomes.push(outcome);
            }
            timings.push((
                format!("all navigation runs, side by side on {threads} threads"),
                phase.elapsed().as_secs_f64(),
            ));
        }
        NavigationSource::Datasets(list) => {
            for (name, path) in list {
                let t = Instant::now();
                outcomes.push(replay_dataset(
                    name,
                    path,
                    &named,
                    &config.replay,
                    progress,
                )?);
                timings.push((format!("{name} (replay)"), t.elapsed().as_secs_f64()));
                sources.push(format!("dataset: {}", path.display()));
            }
        }
    }
    let paper = match &config.paper_table5 {
        Some(p) => load_table5(p)?,
        None => Vec::new(),
    };
    let experiments = outcomes
        .iter()
        .zip(&sources)
        .enumerate()
        .map(|(i, (o, src))| {
            ExperimentSummary::from_outcome(
                o,
                src,
                config.comparison.as_ref(),
                paper.get(i).copied(),
            )
        })
        .collect();
    let summary = Summary {
        schema: SUMMARY_SCHEMA,
        name: config.name.clone(),
        description: config.description.clone(),
        generated_by: format!("sinsbench {}", env!("CARGO_PKG_VERSION")),
        parameter_sets: sets
            .iter()
            .map(|s| ParamSetInfo {
                key: s.key.clone(),
                label: s.label.clone(),
                model: model_name(s.params.model).to_string(),
                source: s.source.clone(),
            })
            .collect(),
        comparison: config.comparison.clone(),
        experiments,
        noise_seed: config.noise_seed,
    };
    Ok(ReportRun {
        config: config.clone(),
        sets,
        outcomes,
        summary,
        paper,
        timings,
        appendix: None,
    })
}

/// The run `name` of the calibration experiment (its first run when `None`).
fn calibration_scenario<'a>(
    config: &ReportConfig,
    scenarios: &'a [sins_sim::Scenario],
    cal: &sins_harness::config::CalibrationSource,
    name: Option<&str>,
) -> Result<&'a sins_sim::Scenario, ReportError> {
    match name {
        Some(r) => scenarios.iter().find(|s| s.name == r).ok_or_else(|| {
            ReportError::Mismatch(format!(
                "{}: calibration run '{r}' is not a run of {}",
                config.source_path.display(),
                cal.experiment.display()
            ))
        }),
        None => scenarios.first().ok_or_else(|| {
            ReportError::Mismatch(format!("{}: no [[run]]", cal.experiment.display()))
        }),
    }
}

/// Draw a simulated run's noise with `noise_seed` ([`sins_harness::config::reseed`]).
fn apply_noise_seed(sc: &mut sins_sim::Scenario, noise_seed: Option<u64>) {
    if let Some(n) = noise_seed {
        sc.seed = sins_harness::config::reseed(sc.seed, n);
    }
}

/// Load the file sets and calibrate the others (one simulation per calibration run feeds
/// every filter calibrated on it).
fn resolve_sets(
    config: &ReportConfig,
    threads: usize,
    progress: &mut dyn Progress,
) -> Result<Vec<ResolvedSet>, ReportError> {
    // Per calibrated set, in order: its run (None: the section's) and its filter.
    let wanted: Vec<(Option<&str>, ParamModel)> = config
        .parameter_sets
        .iter()
        .filter_map(|s| match s.origin {
            ParamOrigin::Calibrate(m) => Some((s.calibration_run.as_deref(), m)),
            ParamOrigin::File(_) => None,
        })
        .collect();
    let mut calibrated = Vec::new();
    if let (false, Some(cal)) = (wanted.is_empty(), &config.calibration) {
        calibrated = wanted.iter().map(|_| None).collect();
        let mut exp = load_experiment(&cal.experiment)?;
        for sc in &mut exp.scenarios {
            apply_noise_seed(sc, config.noise_seed);
        }
        // The run each set names, else the section's (None: the experiment's first).
        let run_of = |i: usize| wanted[i].0.or(cal.run.as_deref());
        let mut runs: Vec<Option<&str>> = Vec::new();
        for i in 0..wanted.len() {
            if !runs.contains(&run_of(i)) {
                runs.push(run_of(i));
            }
        }
        let scenarios = runs
            .iter()
            .map(|&name| calibration_scenario(config, &exp.scenarios, cal, name))
            .collect::<Result<Vec<_>, _>>()?;
        let slots_of = |name: Option<&str>| -> Vec<usize> {
            (0..wanted.len()).filter(|&i| run_of(i) == name).collect()
        };
        let total = scenarios
            .iter()
            .map(|sc| scenario_samples(sc))
            .sum::<Result<u64, _>>()?;
        let names: Vec<&str> = scenarios.iter().map(|s| s.name.as_str()).collect();
        progress.begin(
            &format!("calibrate {} ({} filters)", names.join(", "), wanted.len()),
            total,
        );
        // One simulation per run feeds every filter calibrated on it; runs in parallel.
        let results = map_with_progress(
            runs.len(),
            threads,
            |r, done| {
                let models: Vec<ParamModel> =
                    slots_of(runs[r]).iter().map(|&i| wanted[i].1).collect();
                simulate_and_calibrate(
                    scenarios[r],
                    &models,
                    cal.reference_temperature_degc,
                    threads,
                    &mut |n| done(n),
                )
            },
            &mut |n| progress.advance(n),
        );
        progress.end();
        for ((name, scenario), result) in runs.iter().zip(&scenarios).zip(results) {
            let source = format!(
                "calibrated by this report on the simulated run '{}' of {} ({:.1} h)",
                scenario.name,
                cal.experiment.display(),
                sins_config::motion_duration_s(&scenario.motion) / 3600.0
            );
            for (slot, r) in slots_of(*name).into_iter().zip(result?) {
                calibrated[slot] = Some((r, source.clone()));
            }
        }
    }
    let mut cal_iter = calibrated.into_iter();
    let mut out = Vec::new();
    for s in &config.parameter_sets {
        let set = match &s.origin {
            ParamOrigin::File(path) => {
                let p = load_params(path)?;
                ResolvedSet {
                    key: s.key.clone(),
                    label: s.label.clone(),
                    params: p.params,
                    sigma: p.sigma,
                    source: path.display().to_string(),
                    calibrated: false,
                }
            }
            ParamOrigin::Calibrate(m) => {
                let (r, cal_source) = cal_iter.next().flatten().ok_or_else(|| {
                    ReportError::Mismatch("internal: a calibration result is missing".into())
                })?;
                ResolvedSet {
                    key: s.key.clone(),
                    label: s.label.clone(),
                    params: r.params,
                    sigma: Some(r.sigma),
                    source: format!("{}-state filter, {cal_source}", m.n_states()),
                    calibrated: true,
                }
            }
        };
        out.push(set);
    }
    Ok(out)
}
