//! `CalibrationFilter::push_batch` compensates each stretch between two updates four samples at
//! a time; `push` and `push_led` compensate one sample at a time. A leader, a follower fed a
//! perturbed run, and a filter that meets a bad sample must give the same results both ways, to
//! the bit.

use crate::common::*;
use sins_imu::{ImuErrorParams, ImuSample};
use sins_kf::{CalibrationConfig, CalibrationError, CalibrationFilter, SharedGain};
use sins_nav::UG;
use sins_sim::Simulator;

/// The samples of [`short_run_setup`]'s run, its filter configuration and initial estimate.
fn short_run() -> (Vec<ImuSample>, CalibrationConfig, ImuErrorParams) {
    let (sc, config, initial) = short_run_setup();
    let mut sim = Simulator::from_scenario(&sc).expect("scenario");
    let mut xs = Vec::new();
    sim.run(65_536, |b| {
        xs.extend_from_slice(&b.samples);
        Ok::<_, ()>(())
    })
    .expect("simulated");
    (xs, config, initial)
}

/// A quadratic term on the z accelerometer (100 ug/g²), outside the paper's model.
fn perturbed(xs: &[ImuSample]) -> Vec<ImuSample> {
    let h = 0.005;
    xs.iter()
        .map(|s| {
            let mut x = *s;
            let f_z = s.dv_mps.z / h;
            x.dv_mps.z += 100.0 * UG / sins_nav::G0_MPS2 * f_z * f_z * h;
            x
        })
        .collect()
}

#[test]
fn batches_calibrate_as_single_samples_do_to_the_bit() {
    let (xs, config, initial) = short_run();
    let ys = perturbed(&xs);
    let new = || CalibrationFilter::new(config, initial).expect("configuration");
    // One sample at a time.
    let (mut leader, mut follower) = (new().leading(), new().following());
    xs.iter().try_for_each(|s| leader.push(s)).expect("leader");
    let gains: Vec<SharedGain> = leader.take_gains();
    let mut led = gains.iter();
    ys.iter()
        .try_for_each(|s| follower.push_led(s, &mut led))
        .expect("follower");
    // Batches of uneven length, so that stretches and quads straddle them.
    let (mut leader_b, mut follower_b) = (new().leading(), new().following());
    let mut led = gains.iter();
    for (x, y) in xs.chunks(4_099).zip(ys.chunks(4_099)) {
        leader_b.push_batch(x, None).expect("leader");
        follower_b.push_batch(y, Some(&mut led)).expect("follower");
    }
    assert!(gains.len() > 500, "{} updates", gains.len());
    assert_eq!(leader_b.take_gains().len(), gains.len());
    let lead = format!("{:?}", leader.finish().expect("leader"));
    let lead_b = format!("{:?}", leader_b.finish().expect("leader"));
    assert_eq!(lead, lead_b);
    let follow = follower.finish_led().expect("follower");
    let follow_b = follower_b.finish_led().expect("follower");
    assert_eq!(format!("{follow:?}"), format!("{follow_b:?}"));
    assert_ne!(
        format!("{follow:?}"),
        lead,
        "the perturbation moves the estimate"
    );
}

#[test]
fn a_batch_stops_at_a_time_gap_as_single_samples_do() {
    let (mut xs, config, initial) = short_run();
    let bad = 150_001;
    xs[bad].t_s += 0.5;
    let new = || CalibrationFilter::new(config, initial).expect("configuration");
    let mut one = new();
    let stopped = xs.iter().position(|s| one.push(s).is_err());
    assert_eq!(stopped, Some(bad));
    let mut batched = new();
    let err = batched.push_batch(&xs, None).expect_err("time gap");
    assert!(
        matches!(err, CalibrationError::TimeGap { t_s, .. } if t_s == xs[bad].t_s),
        "{err}"
    );
    assert_eq!(
        format!("{:?}", one.history()),
        format!("{:?}", batched.history())
    );
    assert_eq!(
        format!("{:?}", one.estimate()),
        format!("{:?}", batched.estimate())
    );
    assert!(one.history().len() > 10);
}
