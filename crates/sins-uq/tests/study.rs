//! End to end on a shortened replica (the paper's files with the runs cut to minutes): draws are
//! deterministic, the assumptions reach the scenarios with the right physics, the point job is
//! the harness pipeline itself, and the summary is bit-identical whatever the thread count, the
//! sharding or the order in which samples finish.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test or an example is its failure message

use sins_harness::pipeline::{NamedParams, simulate_and_calibrate, simulate_and_replay};
use sins_imu::{EffectKind, ParamModel};
use sins_sim::scenario::{ChamberSegment, MotionSegment, Scenario};
use sins_uq::apply::{ReplicaBase, build};
use sins_uq::assumptions::{
    Assumption, AssumptionSet, Candidate, CandidateEffect, Distribution, Knob,
};
use sins_uq::draw::{Slot, draw};
use sins_uq::sample::{Job, all_jobs, run_jobs};
use sins_uq::summary::{CellId, CellKind, PaperCell, PaperData, all_cells, summarize};
use std::path::PathBuf;

fn experiments() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments")
}

/// Keeps the first `keep` segments, each at most `max_s` long (the alignment stays whole).
fn shorten(sc: &mut Scenario, keep: usize, max_s: f64) {
    sc.motion.segments.truncate(keep);
    for seg in sc.motion.segments.iter_mut().skip(1) {
        match seg {
            MotionSegment::Dwell { duration_s, .. } | MotionSegment::Vibrate { duration_s, .. } => {
                *duration_s = duration_s.min(max_s)
            }
            MotionSegment::Rotate { .. } => {}
        }
    }
}

fn base() -> ReplicaBase {
    let e = experiments();
    let mut cal = sins_config::load_experiment(e.join("paper_truth_calibration.toml"))
        .unwrap()
        .scenarios[0]
        .clone();
    shorten(&mut cal, 25, 120.0);
    let mut nav = sins_config::load_experiment(e.join("paper_navigation.toml"))
        .unwrap()
        .scenarios[0]
        .clone();
    shorten(&mut nav, 3, 240.0);
    ReplicaBase {
        calibration: cal,
        navigation: vec![nav],
        reference_temperature_degc: 20.0,
        replay: Default::default(),
    }
}

fn assumption(name: &str, knob: Knob, distribution: Distribution) -> Assumption {
    Assumption {
        name: name.into(),
        knob,
        distribution,
        group: name.into(),
        unit: String::new(),
        unit_si: 1.0,
        justification: "test".into(),
    }
}

fn set() -> AssumptionSet {
    let ug = sins_nav::UG;
    AssumptionSet {
        assumptions: vec![
            assumption(
                "cal30",
                Knob::Cal30Chamber,
                Distribution::Choice {
                    labels: vec!["ramp".into(), "stable".into()],
                    weights: vec![0.5, 0.5],
                },
            ),
            assumption(
                "drop",
                Knob::NavTemperatureDropDegc,
                Distribution::Uniform {
                    low: 10.0,
                    high: 30.0,
                },
            ),
            assumption(
                "tb_z",
                Knob::TruthCoefficient(23),
                Distribution::Normal {
                    mean: -25.45 * ug,
                    sd: 2.0 * ug,
                },
            ),
            assumption(
                "mount",
                Knob::NavMounting,
                Distribution::Choice {
                    labels: vec!["z_up".into(), "y_up".into(), "x_up".into()],
                    weights: vec![1.0, 0.0, 0.0],
                },
            ),
            assumption(
                "phase",
                Knob::VibrationPhaseRad,
                Distribution::Uniform {
                    low: 0.0,
                    high: std::f64::consts::TAU,
                },
            ),
        ],
        candidates: vec![
            Candidate {
                name: "as_built".into(),
                justification: "t".into(),
                overrides: vec![(0, Distribution::Fixed(0.0))],
                effects: vec![],
                samples: 2,
            },
            Candidate {
                name: "side".into(),
                justification: "t".into(),
                overrides: vec![(0, Distribution::Fixed(1.0)), (3, Distribution::Fixed(1.0))],
                effects: vec![CandidateEffect {
                    kind: EffectKind::GyroBiasTemp,
                    magnitude: Distribution::Fixed(5e-4 * sins_nav::DEG_PER_H),
                    random_sign: true,
                }],
                samples: 2,
            },
        ],
        samples: 4,
        pick_freeze_samples: 0,
        seed: 7,
        choose_on: vec![CellId {
            experiment: 1,
            kind: CellKind::Without,
        }],
    }
}

#[test]
fn draws_are_deterministic_and_follow_their_distributions() {
    let s = set();
    s.validate().unwrap();
    // Bit for bit (NaN marks the per-element knob, so compare the printed form).
    assert_eq!(
        format!("{:?}", draw(&s, Slot::Main, 3)),
        format!("{:?}", draw(&s, Slot::Main, 3))
    );
    assert_ne!(
        draw(&s, Slot::Main, 3).values,
        draw(&s, Slot::Main, 4).values
    );
    // A 50/50 choice over 4000 draws: binomial sd 31.6, so within 5 sd of 2000.
    let stable = (0..4000)
        .filter(|i| draw(&s, Slot::Main, *i).values[0] == 1.0)
        .count();
    assert!(
        (stable as f64 - 2000.0).abs() < 5.0 * 31.63,
        "stable {stable}"
    );
    // Normal truth coefficient: mean and sd within 5 standard errors.
    let v: Vec<f64> = (0..4000)
        .map(|i| draw(&s, Slot::Main, i).values[2] / sins_nav::UG)
        .collect();
    let (m, sd) = sins_uq::stats::mean_sd(&v);
    assert!((m + 25.45).abs() < 5.0 * 2.0 / 63.2, "mean {m}");
    assert!(
        (sd - 2.0).abs() < 5.0 * 2.0 / (2.0f64 * 4000.0).sqrt(),
        "sd {sd}"
    );
    // Candidate overrides.
    let d = draw(&s, Slot::Candidate(1), 0);
    assert_eq!((d.values[0], d.values[3]), (1.0, 1.0));
    assert_eq!(d.effects.len(), 1);
    assert!(
        d.effects[0]
            .magnitudes_si()
            .iter()
            .all(|m| (m.abs() / (5e-4 * sins_nav::DEG_PER_H) - 1.0).abs() < 1e-12)
    );
}

#[test]
fn pick_freeze_rows_take_exactly_their_group_from_the_resample() {
    let s = set();
    let names = sins_uq::sobol::groups(&s);
    // "mount" never varies (weights 1, 0, 0): no group of its own; the noise realisation last.
    assert_eq!(
        names,
        ["cal30", "drop", "tb_z", "phase", "noise realisation"]
    );
    let a = draw(&s, Slot::Main, 1);
    let b = draw(&s, Slot::Resample, 1);
    assert_ne!(a.cal_seed, b.cal_seed);
    for (g, name) in names.iter().enumerate() {
        let m = sins_uq::sobol::mixed_draw(&s, g, 1);
        for (i, asm) in s.assumptions.iter().enumerate() {
            let want = if &asm.group == name {
                b.values[i]
            } else {
                a.values[i]
            };
            assert_eq!(
                m.values[i].to_bits(),
                want.to_bits(),
                "group {name} value {i}"
            );
        }
        let noise = name == "noise realisation";
        let seeds = |d: &sins_uq::draw::Draw| (d.cal_seed, d.cal30_seed, d.nav_seeds.clone());
        assert_eq!(
            seeds(&m),
            if noise { seeds(&b) } else { seeds(&a) },
            "{name}"
        );
        let phase = name == "phase";
        assert_eq!(
            m.element_seed,
            if phase {
                b.element_seed
            } else {
                a.element_seed
            }
        );
    }
    // The design's jobs: one B row and one row per group for each pick-freeze index.
    let mut s2 = s.clone();
    s2.pick_freeze_samples = 3;
    assert_eq!(
        all_jobs(&s2).len(),
        all_jobs(&s).len() + 3 * (1 + names.len())
    );
    s2.pick_freeze_samples = 5;
    assert!(s2.validate().is_err(), "more rows than main samples");
}

#[test]
fn assumptions_reach_the_scenarios() {
    let (b, s) = (base(), set());
    let d = draw(&s, Slot::Candidate(1), 1);
    let sc = build(&b, &s, &d);
    // Stable 30-state run: one hold at the drawn (default reference) temperature.
    let cal30 = sc.cal30.as_ref().expect("stable run");
    assert!(
        matches!(cal30.thermal.chamber[..], [ChamberSegment::Hold { temp_degc, .. }] if temp_degc == 20.0)
    );
    // The navigation chamber drops by exactly the drawn amount over its trend segments.
    let drop: f64 = -sc.navigation[0]
        .thermal
        .chamber
        .iter()
        .map(|c| match c {
            ChamberSegment::Fluctuating {
                duration_s,
                rate_degc_per_s,
                ..
            }
            | ChamberSegment::Ramp {
                duration_s,
                rate_degc_per_s,
            } => duration_s * rate_degc_per_s,
            ChamberSegment::Hold { .. } => 0.0,
        })
        .sum::<f64>();
    assert!(
        (drop - d.values[1]).abs() < 1e-9,
        "drop {drop} drawn {}",
        d.values[1]
    );
    // On its side: body y points up (NED -z) to the base attitude's 0.5 deg tilt.
    let up = sc.navigation[0].motion.initial_ned_from_body * sins_nav::Vec3::y();
    assert!(up.z < -0.999, "body y in NED {up:?}");
    // The truth coefficient and the effect reach both runs.
    let tb = sins_kf::params_to_vec(&sc.cal42.truth, ParamModel::States42)[23];
    assert_eq!(tb, d.values[2]);
    assert_eq!(sc.navigation[0].truth, sc.cal42.truth);
    assert_eq!(sc.cal42.effects.len(), 1);
    assert_eq!(sc.navigation[0].effects.len(), 1);
    // Phases drawn per pattern axis within [0, 2 pi).
    let phases: Vec<f64> = sc.navigation[0]
        .motion
        .segments
        .iter()
        .filter_map(|s| match s {
            MotionSegment::Vibrate { phase_rad, .. } => Some(phase_rad.x),
            _ => None,
        })
        .collect();
    assert!(
        !phases.is_empty()
            && phases
                .iter()
                .all(|p| (0.0..std::f64::consts::TAU).contains(p))
    );
}

#[test]
fn point_job_is_the_harness_pipeline_and_summaries_do_not_depend_on_threads_or_shards() {
    let (b, mut s) = (base(), set());
    s.pick_freeze_samples = 2;
    let jobs = all_jobs(&s);
    let serial: Vec<_> = run_jobs(&b, &s, &jobs, 1, &|_| {}, &|_, _| {})
        .into_iter()
        .map(|r| r.unwrap())
        .collect();
    let parallel: Vec<_> = run_jobs(&b, &s, &jobs, 3, &|_| {}, &|_, _| {})
        .into_iter()
        .map(|r| r.unwrap())
        .collect();
    assert_eq!(serial, parallel);
    // The point job through the pipeline directly (an independent path: one calibration run,
    // both filters, the replay with two reconstruction threads; the simulator, the filters and
    // the replays on threads of their own, where the study ran them on one).
    let cal = simulate_and_calibrate(
        &b.calibration,
        &[ParamModel::States30, ParamModel::States42],
        20.0,
        3,
        &mut |_| {},
    )
    .unwrap();
    let sets = [
        NamedParams {
            key: "30".into(),
            params: cal[0].params,
        },
        NamedParams {
            key: "42".into(),
            params: cal[1].params,
        },
    ];
    let out = simulate_and_replay(&b.navigation[0], &sets, &b.replay, 2, &mut |_| {}).unwrap();
    let point = &serial[jobs.iter().position(|j| *j == Job::Point).unwrap()];
    assert_eq!(
        point.max_horizontal_m[0],
        [0, 1].map(|k| out.tracks[k].summary.max_horizontal_m)
    );
    // Shards finishing in any order give the same summary, byte for byte.
    let paper = PaperData {
        cells: all_cells(1)
            .iter()
            .map(|_| PaperCell {
                value: 0.01,
                scatter: 0.002,
            })
            .collect(),
        table2: vec![],
    };
    let one = serde_json::to_string(&summarize(&s, &serial, &paper).unwrap()).unwrap();
    let mut shuffled: Vec<_> = serial.iter().cloned().enumerate().collect();
    shuffled.sort_by_key(|(k, _)| (k % 3, usize::MAX - k));
    let shuffled: Vec<_> = shuffled.into_iter().map(|(_, o)| o).collect();
    let summary = summarize(&s, &shuffled, &paper).unwrap();
    let two = serde_json::to_string(&summary).unwrap();
    assert_eq!(one, two);
    // The pick-freeze rows reach the summary: 2 rows, an index per group and cell.
    assert_eq!(summary.pick_freeze_samples, 2);
    let groups = &summary.cells[0].sensitivity.as_ref().unwrap().groups;
    assert_eq!(groups.len(), 5);
    assert!(
        groups
            .iter()
            .all(|g| g.total[0] >= 0.0 && g.total[1] <= g.total[0])
    );
    // Structure the design must reproduce exactly: the 30-state calibration condition cannot
    // move the 42-state cell ("exp1 with": same calibration data and seed either way), so its
    // A and A_B rows agree bit for bit and both indices are 0; the noise realisation moves
    // every cell.
    let with = &summary.cells[1].sensitivity.as_ref().unwrap().groups;
    assert_eq!(with[0].group, "cal30");
    assert_eq!(
        (with[0].total[0], with[0].first_order[0]),
        (0.0, 0.0),
        "{with:?}"
    );
    for c in &summary.cells {
        let g = &c.sensitivity.as_ref().unwrap().groups;
        let noise = g.iter().find(|g| g.group == "noise realisation").unwrap();
        assert!(noise.total[0] > 0.0, "{}: {noise:?}", c.cell);
    }
}
