//! The self-alignment's time checks: an alignment time shorter than its coarse stage is refused
//! at the first sample with a message that says so (it used to run out and report "needs 30.0 s
//! of data but only 30.0 s were given"), and data that end early are reported with times that differ
//! (to the microsecond).

use sins_nav::alignment::{AlignmentConfig, AlignmentError, SelfAlignment};
use sins_nav::earth::EarthAt;
use sins_nav::*;

const H_S: f64 = 0.005;

fn site() -> Geodetic {
    Geodetic::from_deg(28.22, 112.99, 60.0)
}

fn config() -> StrapdownConfig {
    StrapdownConfig {
        sample_interval_s: H_S,
        coning: ConingOrder::TwoSample,
        vertical: VerticalChannel::Hold {
            height_m: site().height_m,
        },
    }
}

/// Exact increments of a level IMU at rest.
fn at_rest() -> Increment {
    let e = EarthAt::new(site().lat_rad, site().height_m);
    Increment {
        dtheta_rad: e.earth_rate_ned_radps * H_S,
        dv_mps: Vec3::new(0.0, 0.0, -e.gravity_mps2) * H_S,
    }
}

fn alignment(duration_s: f64) -> SelfAlignment {
    let c = AlignmentConfig {
        duration_s,
        ..AlignmentConfig::default()
    };
    SelfAlignment::new(c, config(), site(), 0.0)
}

#[test]
fn an_alignment_shorter_than_its_coarse_stage_is_refused_clearly() {
    for duration_s in [30.0, 2.0, 0.001] {
        let mut a = alignment(duration_s);
        let err = a.push(&at_rest()).expect_err("cannot complete");
        assert!(
            matches!(err, AlignmentError::ShorterThanCoarse { coarse_s, .. } if coarse_s == 60.0),
            "{err:?}"
        );
        let msg = err.to_string();
        for part in [
            &format!("alignment time of {duration_s} s"),
            "shorter than the 60 s of coarse alignment",
            "at least 60 s",
        ] {
            assert!(msg.contains(part), "{part:?} missing from: {msg}");
        }
        assert!(!msg.contains("were given"), "{msg}");
        // finish() without data says the same, not "needs x s but x s were given".
        let msg = alignment(duration_s)
            .finish()
            .expect_err("no data")
            .to_string();
        assert!(msg.contains("shorter than the 60 s"), "{msg}");
    }
}

#[test]
fn an_alignment_of_exactly_the_coarse_stage_completes() {
    let mut a = alignment(60.0);
    let mut n = 1;
    while !a.push(&at_rest()).expect("valid") {
        n += 1;
    }
    assert_eq!(n, 12_000);
    let r = a.finish().expect("complete");
    assert!((r.state.t_s - 60.0).abs() < 1e-9);
}

#[test]
fn data_that_end_one_sample_early_report_distinct_times() {
    let mut a = alignment(120.0);
    for _ in 0..23_999 {
        assert!(!a.push(&at_rest()).expect("valid"));
    }
    let err = a.finish().expect_err("one sample short");
    let msg = err.to_string();
    assert!(
        msg.contains("needs 120 s") && msg.contains("end after 119.995 s"),
        "{msg}"
    );
}
