//! One Monte Carlo sample end to end, and a runner that spreads independent samples over
//! threads. A sample's result depends only on its draw, never on the thread that ran it.

use crate::UqError;
use crate::apply::{ReplicaBase, SampleScenarios, build, point};
use crate::assumptions::AssumptionSet;
use crate::draw::{Draw, Slot, draw};
use serde::{Deserialize, Serialize};
use sins_harness::pipeline::{NamedParams, simulate_and_calibrate, simulate_and_replay};
use sins_imu::{ImuErrorParams, ParamModel};
use sins_kf::params_to_vec;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// What a sample is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Job {
    /// The point replica (the experiment files as they are; `sinsbench report`).
    Point,
    /// Sample `index` of a slot.
    Draw(Slot, usize),
    /// Row `index` of the pick-freeze matrix `A_B^g` of group `g` ([`crate::sobol`]).
    Mix(usize, usize),
}

impl Job {
    /// The sample index within its study.
    pub fn index(self) -> usize {
        match self {
            Job::Point => 0,
            Job::Draw(_, i) | Job::Mix(_, i) => i,
        }
    }

    /// The job's draw (`None` for the point replica).
    pub fn draw(self, set: &AssumptionSet) -> Option<Draw> {
        match self {
            Job::Point => None,
            Job::Draw(slot, i) => Some(draw(set, slot, i)),
            Job::Mix(g, i) => Some(crate::draw::mixed_draw(set, g, i)),
        }
    }
}

/// Study name of the pick-freeze matrix B.
pub const PICK_FREEZE_B: &str = "pickfreeze_b";

/// Study name of the pick-freeze matrix `A_B^g` of group number `g`.
pub fn pick_freeze_study(g: usize) -> String {
    format!("pickfreeze_g{g}")
}

/// The results of one sample.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SampleOutcome {
    /// "point", "replica" (the main Monte Carlo) or the candidate's name.
    pub study: String,
    /// Sample index within the study.
    pub index: usize,
    /// The drawn value of each assumption (SI or choice index; `None` for per-element knobs and
    /// for the point replica).
    pub values: Vec<Option<f64>>,
    /// Maximum horizontal error (m) of each navigation run: `[30-state, 42-state]`.
    pub max_horizontal_m: Vec<[f64; 2]>,
    /// 42-state estimate minus truth, 33 coefficients in state order (SI).
    pub error42: Vec<f64>,
    /// 30-state estimate minus truth, 21 coefficients in state order (SI).
    pub error30: Vec<f64>,
}

/// The study name of a job.
pub fn study_name(set: &AssumptionSet, job: Job) -> String {
    match job {
        Job::Point => "point".to_string(),
        Job::Draw(Slot::Main, _) => "replica".to_string(),
        Job::Draw(Slot::Candidate(c), _) => set.candidates[c].name.clone(),
        Job::Draw(Slot::Resample, _) => PICK_FREEZE_B.to_string(),
        Job::Mix(g, _) => pick_freeze_study(g),
    }
}

/// Every job of a study in a fixed order: the point replica, the main Monte Carlo, each
/// candidate's samples, then the pick-freeze rows (B and every group's `A_B^g`, row by row).
pub fn all_jobs(set: &AssumptionSet) -> Vec<Job> {
    let mut jobs = vec![Job::Point];
    jobs.extend((0..set.samples).map(|i| Job::Draw(Slot::Main, i)));
    for (c, cand) in set.candidates.iter().enumerate() {
        jobs.extend((0..cand.samples).map(|i| Job::Draw(Slot::Candidate(c), i)));
    }
    let groups = crate::draw::groups(set).len();
    for i in 0..set.pick_freeze_samples.min(set.samples) {
        jobs.push(Job::Draw(Slot::Resample, i));
        jobs.extend((0..groups).map(|g| Job::Mix(g, i)));
    }
    jobs
}

/// Runs one job: simulate and calibrate (30 and 42 states), then simulate and replay every
/// navigation run under both sets. `progress` receives sample counts.
pub fn run_job(
    base: &ReplicaBase,
    set: &AssumptionSet,
    job: Job,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<SampleOutcome, UqError> {
    let study = study_name(set, job);
    let index = job.index();
    let (scenarios, values) = match job.draw(set) {
        None => (point(base), vec![None; set.assumptions.len()]),
        Some(d) => {
            let values = set
                .assumptions
                .iter()
                .zip(&d.values)
                .map(|(a, v)| (!a.knob.is_per_element()).then_some(*v))
                .collect();
            (build(base, set, &d), values)
        }
    };
    let fail = |source| UqError::Pipeline {
        candidate: study.clone(),
        sample: index,
        source: Box::new(source),
    };
    let (p30, p42) = calibrate(base, &scenarios, progress).map_err(fail)?;
    let sets = [
        NamedParams {
            key: "30-state".into(),
            params: p30,
        },
        NamedParams {
            key: "42-state".into(),
            params: p42,
        },
    ];
    let mut replay = base.replay;
    replay.reconstruct.threads = 1;
    let mut max_horizontal_m = Vec::with_capacity(scenarios.navigation.len());
    for sc in &scenarios.navigation {
        let out = simulate_and_replay(sc, &sets, &replay, 1, &mut |n| progress(n)).map_err(fail)?;
        max_horizontal_m.push([0, 1].map(|k| out.tracks[k].summary.max_horizontal_m));
    }
    Ok(SampleOutcome {
        study,
        index,
        values,
        max_horizontal_m,
        error42: difference(&p42, &scenarios.truth, ParamModel::States42),
        error30: difference(&p30, &scenarios.truth, ParamModel::States30),
    })
}

fn difference(est: &ImuErrorParams, truth: &ImuErrorParams, model: ParamModel) -> Vec<f64> {
    params_to_vec(est, model)
        .iter()
        .zip(params_to_vec(truth, model))
        .map(|(e, t)| e - t)
        .collect()
}

/// The 30- and 42-state sets of a sample: both filters on the calibration run, or the 30-state
/// filter on its own stable-temperature run.
fn calibrate(
    base: &ReplicaBase,
    sc: &SampleScenarios,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<(ImuErrorParams, ImuErrorParams), sins_harness::HarnessError> {
    let t_ref = base.reference_temperature_degc;
    let mut p = |n| progress(n);
    match &sc.cal30 {
        None => {
            let r = simulate_and_calibrate(
                &sc.cal42,
                &[ParamModel::States30, ParamModel::States42],
                t_ref,
                1,
                &mut p,
            )?;
            Ok((r[0].params, r[1].params))
        }
        Some(cal30) => {
            let r42 = simulate_and_calibrate(&sc.cal42, &[ParamModel::States42], t_ref, 1, &mut p)?;
            let r30 = simulate_and_calibrate(cal30, &[ParamModel::States30], t_ref, 1, &mut p)?;
            Ok((r30[0].params, r42[0].params))
        }
    }
}

/// Samples of data a job simulates (for progress bars): its calibration run(s) and its
/// navigation runs.
pub fn job_work(base: &ReplicaBase, set: &AssumptionSet, job: Job) -> u64 {
    let sc = match job.draw(set) {
        None => point(base),
        Some(d) => build(base, set, &d),
    };
    let n = |sc| sins_harness::pipeline::scenario_samples(sc).unwrap_or(0);
    n(&sc.cal42) + sc.cal30.as_ref().map_or(0, n) + sc.navigation.iter().map(n).sum::<u64>()
}

/// Runs `jobs` on `threads` workers (each takes the next job not yet started); `done` is called
/// from the worker with each finished job's position in `jobs` and its outcome (e.g. to write
/// it to a file at once). Results in the order of `jobs`.
pub fn run_jobs(
    base: &ReplicaBase,
    set: &AssumptionSet,
    jobs: &[Job],
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
    done: &(dyn Fn(usize, &SampleOutcome) + Sync),
) -> Vec<Result<SampleOutcome, UqError>> {
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Result<SampleOutcome, UqError>>>> =
        Mutex::new((0..jobs.len()).map(|_| None).collect());
    std::thread::scope(|scope| {
        for _ in 0..threads.clamp(1, jobs.len().max(1)) {
            scope.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&job) = jobs.get(k) else { break };
                    let r = run_job(base, set, job, progress);
                    if let Ok(o) = &r {
                        done(k, o);
                    }
                    if let Ok(mut guard) = results.lock() {
                        guard[k] = Some(r);
                    }
                }
            });
        }
    });
    results
        .into_inner()
        .unwrap_or_default()
        .into_iter()
        .map(|r| {
            r.unwrap_or_else(|| {
                Err(UqError::TooFewSamples {
                    what: "worker".into(),
                    needed: 1,
                    got: 0,
                })
            })
        })
        .collect()
}
