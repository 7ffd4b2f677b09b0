//! The study end to end on shortened runs (alignment + one pass of the 18-step scheme, 3 Monte
//! Carlo seeds): the 42-state filter is consistent with its own covariance, the 30-state filter
//! leaves the temperature terms in its constants, the least-squares baseline recovers the truth's
//! slopes, and the result does not depend on the thread count.

use sins_calstudy::stats::nees_mean_interval;
use sins_calstudy::{Study, StudyConfig, render_markdown, run_study};
use std::path::PathBuf;

fn config(seeds: usize, threads: usize, cut_s: f64) -> StudyConfig {
    let d = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments");
    let mut c = StudyConfig::paper(d);
    c.seeds = seeds;
    c.threads = threads;
    c.max_duration_s = Some(cut_s);
    c
}

/// Alignment (1200 s) + one pass of the 18-step scheme (18 × 193.3 s).
const ONE_PASS_S: f64 = 4680.5;

#[test]
fn shortened_study_is_consistent() {
    let s = run_study(&config(3, 2, ONE_PASS_S)).expect("study runs");
    let t = &s.table1;
    assert_eq!(t.seeds, vec![1, 2, 3], "seeds from the run's own seed");
    assert_eq!(t.entries.len(), 33);
    // Errors within 4 sigma for all 33 × 3 (a consistent filter exceeds 4σ with p = 6e-5 each).
    let mut worst = (0.0f64, String::new());
    for seed in &t.per_seed {
        for (k, (e, sg)) in seed.error.iter().zip(&seed.sigma).enumerate() {
            let z = (e / sg).abs();
            assert!(z.is_finite(), "seed {} coefficient {k}", seed.seed);
            if z > worst.0 {
                worst = (
                    z,
                    format!("seed {} {}", seed.seed, sins_kf::STATE_NAMES[9 + k]),
                );
            }
        }
    }
    eprintln!(
        "largest |error|/σ {:.2} ({}); NEES {:?}",
        worst.0, worst.1, t.nees
    );
    assert!(worst.0 <= 4.0, "{worst:?}");
    // NEES of the 33-coefficient block: the mean over 3 seeds inside χ²(99)/3 at 99.9 %.
    let [lo, hi] = nees_mean_interval(33, 3, 0.999);
    assert!(
        (lo..=hi).contains(&t.nees_mean),
        "NEES {} not in [{lo}, {hi}]",
        t.nees_mean
    );
    assert_eq!(t.nees_interval_95, nees_mean_interval(33, 3, 0.95));
    // Without noise the method itself reaches the paper's residuals almost everywhere, even on
    // one pass of the scheme.
    assert!(
        t.count_noise_free_at_or_below_paper >= 30,
        "{}",
        t.count_noise_free_at_or_below_paper
    );

    // The 30-state filter: scale factors shifted by TK (T̄ − T_ref) far beyond their sigma, at an
    // effective temperature inside the accelerometers' range over the run; the 42-state filter
    // on the same data is not.
    let th = &s.thirty_state;
    for e in th.entries.iter().filter(|e| e.name.starts_with("dK")) {
        assert!(
            e.error_30.abs() > 5.0 * e.sigma_30,
            "{}: {} ± {}",
            e.name,
            e.error_30,
            e.sigma_30
        );
        assert!(
            e.error_42.abs() < 4.0 * e.sigma_42,
            "{}: {}",
            e.name,
            e.error_42
        );
        let ratio = e.error_30 / e.expected_shift;
        assert!(
            (0.6..1.4).contains(&ratio),
            "{}: shift ratio {ratio}",
            e.name
        );
    }

    // The least-squares baseline: 4 points at chamber + offset, slopes within 4σ of the truth.
    let ls = &s.ls_baseline;
    let chambers: Vec<f64> = ls.points.iter().map(|p| p.chamber_degc).collect();
    assert_eq!(chambers, vec![10.0, 20.0, 30.0, 40.0]);
    for p in &ls.points {
        for (m, off) in p.mean_temp_degc.iter().zip([0.5, -0.3, 0.8]) {
            assert!((m - p.chamber_degc - off).abs() < 0.01, "{}: {m}", p.run);
        }
        assert!(p.max_abs_z < 4.5, "{}: {}", p.run, p.max_abs_z);
    }
    assert!((ls.total_h - (ls.calibrated_h + 4.0 * 3.0)).abs() < 1e-12);
    for e in &s.table3.entries {
        assert!(
            e.ls_error.abs() < 4.0 * e.ls_sigma,
            "LS {}: {} ± {}",
            e.name,
            e.ls_error,
            e.ls_sigma
        );
        assert!(
            e.proposed_error.abs() < 4.0 * e.proposed_sigma,
            "proposed {}: {} ± {}",
            e.name,
            e.proposed_error,
            e.proposed_sigma
        );
        assert!((e.truth - e.paper_proposed).abs() < 1e-9, "{}", e.name);
    }
    assert!(s.table3.ls_time_h > 4.0 * s.table3.proposed_time_h);

    let md = render_markdown(&s);
    for needle in [
        "## 1. Table 1",
        "NEES",
        "## 3. Observability",
        "TM_ayz",
        "Table 3",
        "## 6. Timing",
    ] {
        assert!(md.contains(needle), "report lacks {needle}");
    }
    assert!(serde_json::to_string(&s).is_ok());
}

fn without_timing(mut s: Study) -> String {
    s.timing = sins_calstudy::Timing {
        single_42_state_wall_s: 0.0,
        single_42_state_filter_s: 0.0,
        single_42_state_samples: 0,
        study_wall_s: 0.0,
        threads: 0,
        calibrations: s.timing.calibrations,
    };
    serde_json::to_string(&s).expect("serialises")
}

#[test]
fn study_is_bit_identical_for_any_thread_count() {
    // Alignment + the first rotation and dwell: every calibration of the study, briefly.
    let one = run_study(&config(2, 1, 1400.0)).expect("study runs");
    let three = run_study(&config(2, 3, 1400.0)).expect("study runs");
    assert_eq!(one.timing.calibrations, 2 + 1 + 1 + 4 + 1);
    assert_eq!(without_timing(one), without_timing(three));
}

#[test]
fn least_squares_points_must_hold_the_chamber() {
    // The Table 1 experiment ramps its chamber: not a least-squares temperature point.
    let mut c = config(1, 1, 1400.0);
    c.ls_experiment = c.table1_experiment.clone();
    let e = run_study(&c).expect_err("ramping chamber refused");
    let msg = e.to_string();
    assert!(
        msg.contains("cal1") && msg.contains("must hold one temperature"),
        "{msg}"
    );
}
