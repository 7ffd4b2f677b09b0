//! Identification against known noise. Each identified term must lie within 3 of its own
//! stated 1-sigma of the truth (or, when it fitted to zero, the truth below its 95 % upper
//! bound). If the stated sigmas are right, one assertion fails by chance about 0.3 % of the
//! time for a fresh seed; the seeds here are fixed, so the tests are deterministic.

use sins_diag::DiagError;
use sins_diag::source::{BatchSink, SampleSource, SimSource};
use sins_imu::{EffectKind, EffectSpec, ForwardModel, ImuErrorParams, ImuSample, ParamModel};
use sins_nav::{DEG, Euler, Geodetic, Vec3, ned_from_body_euler};
use sins_noiseid::{Estimate, NoiseIdConfig, RunStationary, identify_noise};
use sins_sim::noise::gauss_markov_sigma_from_allan;
use sins_sim::{
    ChamberSegment, GaussMarkov, GaussianStream, MotionProgram, MotionSegment, NoiseModel,
    Scenario, Simulator, ThermalModel,
};

fn within(name: &str, est: &Estimate, truth: f64, k: f64) {
    if est.value == 0.0 {
        let ub = est.upper_95.unwrap_or(0.0);
        assert!(
            truth <= ub,
            "{name}: fitted 0, upper bound {ub:e} below the truth {truth:e}"
        );
        return;
    }
    let z = (est.value - truth) / est.sigma;
    assert!(
        z.abs() <= k,
        "{name}: {:e} ± {:e} vs truth {truth:e} (z = {z:.2})",
        est.value,
        est.sigma
    );
}

/// White rate noise plus a Gauss-Markov bias on every channel, generated on the fly.
struct Synth {
    n: usize,
    h_s: f64,
    seed: u64,
    white: f64,
    gm: (f64, f64),
    /// A change of one channel's bias: (channel, first sample after it, rate change).
    step: Option<(usize, usize, f64)>,
    /// The accelerometers' output quantum (m/s) and whether the remainder is carried (pulse
    /// counting) or each sample rounded.
    accel_quantum: Option<(f64, bool)>,
}

impl SampleSource for Synth {
    fn sample_interval_s(&self) -> f64 {
        self.h_s
    }
    fn visit(&mut self, sink: &mut BatchSink<'_>) -> Result<(), DiagError> {
        let h = self.h_s;
        let mut w = GaussianStream::new(self.seed, 1);
        let mut gb = GaussianStream::new(self.seed, 2);
        let mut gm: Vec<GaussMarkov> = (0..6)
            .map(|_| GaussMarkov::new(self.gm.0, self.gm.1, h, &mut gb))
            .collect();
        // A constant Earth rate and gravity (cancel in the Allan variance).
        let base = [1e-5, 5e-5, -3e-5, 0.1, 0.2, 9.8];
        let mut batch = Vec::with_capacity(4096);
        let seg = vec![0u16; 4096];
        let mut carried = [0.0f64; 3];
        for k in 0..self.n {
            let mut v = [0.0; 6];
            for c in 0..6 {
                let jump = match self.step {
                    Some((ch, at, size)) if ch == c && k >= at => size,
                    _ => 0.0,
                };
                v[c] = (base[c] + gm[c].value() + jump) * h
                    + self.white * h.sqrt() * w.next_standard();
                gm[c].step(&mut gb);
            }
            if let Some((q, carry)) = self.accel_quantum {
                for (a, r) in carried.iter_mut().enumerate() {
                    let x = v[3 + a] + if carry { *r } else { 0.0 };
                    let out = (x / q).round() * q;
                    *r = x - out;
                    v[3 + a] = out;
                }
            }
            batch.push(ImuSample {
                t_s: (k + 1) as f64 * h,
                dtheta_rad: Vec3::new(v[0], v[1], v[2]),
                dv_mps: Vec3::new(v[3], v[4], v[5]),
                temp_degc: [20.0; 3],
            });
            if batch.len() == 4096 {
                sink(&batch, &seg)?;
                batch.clear();
            }
        }
        sink(&batch, &seg[..batch.len()])
    }
}

/// Three 20 000 s runs at 20 Hz of white noise and a Gauss-Markov bias on every channel;
/// `step` (channel, sample, rate change) on the second run only.
fn three_runs(white: f64, gm: (f64, f64), step: Option<(usize, usize, f64)>) -> Vec<Synth> {
    (0..3)
        .map(|i| Synth {
            n: 400_000,
            h_s: 0.05,
            seed: 40 + i,
            white,
            gm,
            step: step.filter(|_| i == 1),
            accel_quantum: None,
        })
        .collect()
}

/// Identify the noise of `sources` with the defaults: run `i` is named `run{i}` and labelled by
/// `labels`.
fn identify_all<S: SampleSource>(
    sources: &mut [S],
    labels: impl Fn(&S) -> Vec<String>,
) -> sins_noiseid::IdentifiedNoise {
    let mut runs: Vec<RunStationary<'_>> = sources
        .iter_mut()
        .enumerate()
        .map(|(i, s)| RunStationary {
            name: format!("run{i}"),
            segment_labels: labels(s),
            source: s,
            site: Geodetic::from_deg(28.22, 112.99, 60.0),
            compensation: None,
        })
        .collect();
    identify_noise(&mut runs, &NoiseIdConfig::default()).expect("identified")
}

/// Synthetic runs, each one stationary segment.
fn identify_synth(sources: &mut [Synth]) -> sins_noiseid::IdentifiedNoise {
    identify_all(sources, |_| vec!["stationary".into()])
}

#[test]
fn white_plus_gauss_markov_is_identified_within_its_sigma() {
    let (white, sigma, tc) = (2e-3, 1e-3, 300.0);
    let mut sources = three_runs(white, (sigma, tc), None);
    let id = identify_synth(&mut sources);
    for (name, s) in [("gyro", &id.gyro), ("accel", &id.accel)] {
        eprintln!("{name}: {s:#?}");
        within(&format!("{name} white"), &s.white_per_sqrt_s, white, 3.0);
        within(&format!("{name} GM sigma"), &s.bias_sigma, sigma, 3.0);
        within(
            &format!("{name} GM correlation"),
            &s.bias_correlation_s,
            tc,
            3.0,
        );
        // Not vacuous: the correlation time is identified to better than 30 %.
        assert!(
            s.bias_correlation_s.sigma < 0.3 * tc,
            "{name}: {:?}",
            s.bias_correlation_s
        );
        within(
            &format!("{name} rate random walk"),
            &s.rate_random_walk_per_sqrt_s,
            0.0,
            3.0,
        );
    }
    // Continuous data: no lattice, and the free quantization term is compatible with zero.
    assert!(!id.gyro.quantum_from_lattice);
    within("gyro quantum", &id.gyro.quantum, 0.0, 3.0);
    assert_eq!(id.runs.len(), 3);
    assert!((id.stationary_s() - 3.0 * 400_000.0 * 0.05).abs() < 1e-6);
    // Stationary noise: no change of a bias found in any stretch.
    assert!(
        id.stretches.iter().all(|s| s.changes.is_empty()),
        "{:?}",
        id.stretches
    );
}

/// Quantised accelerometers (0.6 mm/s, 1.3 times a sample's white-noise sigma, so that a
/// carried quantisation is 31 % of the Allan variance at the shortest τ; coarser, a rounded
/// sample is no longer the input plus an independent uniform error, and gravity is 817 quanta
/// per sample, within the lattice detector's 1000). The quantum is read off the
/// lattice exactly; it never passes for velocity random walk when the remainder is carried
/// (white phase: the free white-velocity term holds it, √12·Q within 10 % of the quantum), and
/// it adds its white-rate `q²/12h` to the random walk when each sample is rounded (where the
/// white-velocity term stays compatible with zero).
#[test]
fn a_quantised_accelerometer_gives_its_quantum_and_an_unbiased_velocity_random_walk() {
    let (white, sigma, tc, q, h) = (2e-3, 1e-3, 300.0, 6e-4, 0.05);
    for carry in [true, false] {
        let mut sources: Vec<Synth> = three_runs(white, (sigma, tc), None)
            .into_iter()
            .map(|s| Synth {
                accel_quantum: Some((q, carry)),
                ..s
            })
            .collect();
        let id = identify_synth(&mut sources);
        eprintln!("carry {carry}: {:#?}", id.accel);
        assert!(id.accel.quantum_from_lattice, "carry {carry}");
        assert!((id.accel.quantum.value / q - 1.0).abs() < 1e-9);
        let name = format!("accel VRW (carry {carry})");
        if carry {
            within(&name, &id.accel.white_per_sqrt_s, white, 3.0);
            let wp = id.accel.white_phase.value / q;
            assert!((wp - 1.0).abs() < 0.1, "white phase {wp} quanta");
        } else {
            let rounded = (white * white + q * q / (12.0 * h)).sqrt();
            within(&name, &id.accel.white_per_sqrt_s, rounded, 3.0);
            within("accel white phase", &id.accel.white_phase, 0.0, 3.0);
        }
        // The gyros are continuous: no lattice, and their estimates are those of the truth.
        assert!(!id.gyro.quantum_from_lattice);
        within("gyro white", &id.gyro.white_per_sqrt_s, white, 3.0);
    }
}

/// A bias that jumps in the middle of a stationary stretch is not noise: it is found where it
/// is, its size within 3 sigma of its windows' noise, and the data around it left out, so that
/// the identified terms stay those of the noise (with the scan switched off, the gyro's
/// Gauss-Markov σ came out at 2.08e-3 ± 0.17e-3 against the true 1e-3: 6.2 sigma off).
#[test]
fn a_bias_change_inside_a_stretch_is_left_out_of_the_noise() {
    let (white, sigma, tc, jump) = (2e-3, 1e-3, 300.0, 1e-2);
    let at_sample = 160_123;
    let mut sources = three_runs(white, (sigma, tc), Some((2, at_sample, jump)));
    let id = identify_synth(&mut sources);
    let changes: Vec<_> = id.stretches.iter().flat_map(|s| &s.changes).collect();
    assert_eq!(changes.len(), 1, "{changes:?}");
    let c = changes[0];
    assert_eq!(c.channel, "gyro_z");
    let at_s = at_sample as f64 * 0.05;
    assert!(
        (c.at_s - at_s).abs() <= 0.5 * c.left_out_s,
        "{c:?} vs {at_s} s"
    );
    // Size from two windows of half the left-out length: white plus Gauss-Markov noise of the
    // mean over each window (at most σ), so a bound of 3 × √2 × (white/√w + σ).
    let w = 0.5 * c.left_out_s;
    let noise = std::f64::consts::SQRT_2 * (white / w.sqrt() + sigma);
    assert!((c.size - jump).abs() < 3.0 * noise, "{c:?}");
    assert!(
        id.notes
            .iter()
            .any(|n| n.contains("gyro_z: the bias changes"))
    );
    // A diagnosis gets it typed: the change's own run, channel and figures (paper units).
    let typed: Vec<_> = id
        .diagnosis_notes()
        .into_iter()
        .filter(|n| n.subject.as_deref() == Some("gyro_z"))
        .collect();
    assert_eq!(typed.len(), 1, "{typed:?}");
    let figure = |name: &str| {
        typed[0]
            .figures
            .iter()
            .find(|f| f.name == name)
            .map(|f| f.value)
    };
    assert_eq!(
        typed[0].kind,
        sins_diag::report::NoteKind::NoiseIdentification
    );
    let run = id
        .stretches
        .iter()
        .find(|s| s.changes.contains(c))
        .map(|s| s.run.clone());
    assert_eq!(typed[0].run, run);
    assert_eq!(figure("at_s"), Some(c.at_s));
    assert_eq!(figure("size"), Some(c.size / sins_nav::DEG_PER_H));
    assert_eq!(figure("z"), Some(c.z));
    within("gyro GM sigma", &id.gyro.bias_sigma, sigma, 3.0);
    within("gyro GM correlation", &id.gyro.bias_correlation_s, tc, 3.0);
    within(
        "gyro rate random walk",
        &id.gyro.rate_random_walk_per_sqrt_s,
        0.0,
        3.0,
    );
}

fn paper_noise() -> NoiseModel {
    let deg_per_h = DEG / 3600.0;
    NoiseModel {
        gyro_arw_rad_per_sqrt_s: 0.0005 * DEG / 60.0,
        gyro_bias_instability_radps: gauss_markov_sigma_from_allan(0.0005 * deg_per_h),
        gyro_bias_correlation_s: 3600.0,
        gyro_quantum_rad: DEG / 3600.0,
        accel_vrw_mps_per_sqrt_s: 10e-6 * 9.80665,
        accel_bias_instability_mps2: gauss_markov_sigma_from_allan(5e-6 * 9.80665),
        accel_bias_correlation_s: 3600.0,
    }
}

/// A stationary run of `hours` on an ideal IMU with the paper's noise at 200 Hz.
fn stationary_run(hours: f64, seed: u64) -> SimSource {
    stationary_run_with(hours, seed, Vec::new())
}

/// [`stationary_run`] with effects added to the truth.
fn stationary_run_with(hours: f64, seed: u64, effects: Vec<EffectSpec>) -> SimSource {
    let mut truth = ImuErrorParams::ideal(ParamModel::States42);
    truth.reference_temperature_degc = 20.0;
    let sc = Scenario {
        name: "noise-id".into(),
        description: "stationary".into(),
        site: Geodetic::from_deg(28.22, 112.99, 60.0),
        rate_hz: 200.0,
        quadrature_nodes: 1,
        motion: MotionProgram {
            initial_ned_from_body: ned_from_body_euler(&Euler::from_deg(0.5, -0.3, 30.0)),
            segments: vec![
                MotionSegment::Dwell {
                    duration_s: 1200.0,
                    label: "alignment".into(),
                },
                MotionSegment::Dwell {
                    duration_s: hours * 3600.0 - 1200.0,
                    label: "stationary".into(),
                },
            ],
        },
        thermal: ThermalModel {
            chamber_start_degc: 20.0,
            chamber: vec![ChamberSegment::Hold {
                duration_s: hours * 3600.0,
                temp_degc: 20.0,
            }],
            accel_time_constant_s: [720.0, 1200.0, 1680.0],
            accel_offset_degc: [0.0; 3],
            accel_initial_degc: None,
            thermometer_noise_degc: 0.0,
        },
        noise: paper_noise(),
        truth,
        effects,
        seed,
        with_reference: false,
    };
    let fwd = sc.effects.iter().fold(ForwardModel::new(truth), |f, e| {
        f.with_effect(e.build(&truth))
    });
    SimSource::new(Simulator::new(&sc, fwd).expect("valid scenario"))
}

#[test]
fn paper_noise_from_a_simulated_stationary_run() {
    let truth = paper_noise();
    let id = identify_runs(&mut [stationary_run(2.0, 5)]);
    eprintln!("{:#?}\n{:#?}\n{:?}", id.gyro, id.accel, id.notes);
    // The quantum is read off the increments exactly.
    assert!(id.gyro.quantum_from_lattice);
    quantum_exact_and_arw_within_3_sigma(&id, &truth);
    within(
        "VRW",
        &id.accel.white_per_sqrt_s,
        truth.accel_vrw_mps_per_sqrt_s,
        3.0,
    );
    // Not vacuous: both white terms to better than 20 %.
    assert!(id.gyro.white_per_sqrt_s.sigma < 0.2 * truth.gyro_arw_rad_per_sqrt_s);
    assert!(id.accel.white_per_sqrt_s.sigma < 0.2 * truth.accel_vrw_mps_per_sqrt_s);
    // Two hours cannot separate the Gauss-Markov σ from its hour-long correlation time; what
    // they identify is the rising slope K² = 2σ²/T (the rate random walk the bias looks like at
    // τ < T), and the truth's slope must lie within 3 sigma of it.
    for (name, s, sigma, t) in [
        (
            "gyro",
            &id.gyro,
            truth.gyro_bias_instability_radps,
            truth.gyro_bias_correlation_s,
        ),
        (
            "accel",
            &id.accel,
            truth.accel_bias_instability_mps2,
            truth.accel_bias_correlation_s,
        ),
    ] {
        let est_t = s.bias_correlation_s.value;
        if s.bias_correlation_s.sigma.is_finite() && s.bias_correlation_s.sigma > 0.0 {
            within(&format!("{name} GM sigma"), &s.bias_sigma, sigma, 3.0);
            within(
                &format!("{name} GM correlation"),
                &s.bias_correlation_s,
                t,
                3.0,
            );
        } else {
            let slope = Estimate {
                value: 2.0 * s.bias_sigma.value.powi(2) / est_t,
                sigma: 4.0 * s.bias_sigma.value * s.bias_sigma.sigma / est_t,
                upper_95: s.bias_sigma.upper_95.map(|u| 2.0 * u * u / est_t),
            };
            within(
                &format!("{name} GM slope"),
                &slope,
                2.0 * sigma * sigma / t,
                3.0,
            );
        }
    }
    // The stretch means match the Earth rate and gravity to the bias level.
    let s = &id.stretches[0];
    let g = s.accel_residual_mps2.expect("aligned");
    assert!(g.iter().all(|v| v.abs() < 1e-3), "{g:?}");
    // Conversions carry the identified figures.
    let m = id.to_noise_model();
    assert_eq!(m.gyro_quantum_rad, id.gyro.quantum.value);
    assert_eq!(
        id.to_noise_spec().accel_vrw_mps_per_sqrt_s,
        m.accel_vrw_mps_per_sqrt_s
    );
}

/// Paper-noise stationary runs, labelled by the simulator.
fn identify_runs(sources: &mut [SimSource]) -> sins_noiseid::IdentifiedNoise {
    identify_all(sources, SimSource::segment_labels)
}

#[test]
fn a_turn_on_transient_is_named_and_left_out_and_the_clean_twin_is_consistent() {
    // The same two 3 h runs with and without a gyro z bias that starts 0.2 deg/h high and
    // decays with a 20 min time constant after turn-on. Taken for noise, it triples the gyro
    // bias instability (0.0018 against the truth's 0.0005 deg/h, as in the external suite).
    let transient = EffectSpec::BiasEvent {
        kind: EffectKind::GyroBiasTransient,
        magnitude_si: Vec3::new(0.0, 0.0, 0.2 * DEG / 3600.0),
        onset_s: 0.0,
        time_constant_s: 1200.0,
    };
    let clean = identify_runs(&mut [stationary_run(3.0, 11), stationary_run(3.0, 12)]);
    assert!(clean.inconsistent.is_empty(), "{:?}", clean.inconsistent);
    assert_eq!(clean.turn_on_left_out_s, 0.0);
    let with = identify_runs(&mut [
        stationary_run_with(3.0, 11, vec![transient.clone()]),
        stationary_run_with(3.0, 12, vec![transient]),
    ]);
    eprintln!("{:?}\n{:?}\n{:?}", with.inconsistent, with.notes, with.gyro);
    let note = with.turn_on_note().expect("a turn-on note");
    assert!(
        note.contains("gyro_z") && note.contains("start of a run"),
        "{note}"
    );
    assert_eq!(clean.turn_on_note(), None);
    // The first hour of each run (the chunk that stood out) is left out, and what remains
    // gives the truth's bias instability back within 3 sigma.
    assert!(
        (3590.0..3610.0).contains(&with.turn_on_left_out_s),
        "{}",
        with.turn_on_left_out_s
    );
    // The paper's 0.0005 deg/h Allan floor (paper_noise builds its sigma from it).
    let truth = 0.0005 * DEG / 3600.0;
    within(
        "gyro bias instability",
        &with.gyro.bias_instability,
        truth,
        3.0,
    );
    assert!(with.inconsistent.is_empty(), "{:?}", with.inconsistent);
}

#[test]
fn quiet_data_raise_no_alarm_over_a_hundred_seeds() {
    // 100 runs of 4 h of white noise and a Gauss-Markov bias (20 Hz), one still stretch each:
    // the whole identification (stillness, bias changes, lattice, model check, agreement of
    // the stretches) against its stated false-alarm rates.
    let (mut motion_h, mut inconsistent, mut changes) = (0usize, 0usize, 0usize);
    for seed in 0..100 {
        let mut s = [Synth {
            n: 288_000,
            h_s: 0.05,
            seed: 1000 + seed,
            white: 2e-3,
            gm: (1e-3, 300.0),
            step: None,
            accel_quantum: None,
        }];
        let id = identify_synth(&mut s);
        motion_h += id.motion.len();
        inconsistent += usize::from(!id.inconsistent.is_empty());
        changes += id.stretches.iter().map(|s| s.changes.len()).sum::<usize>();
        if !id.inconsistent.is_empty() {
            eprintln!("seed {seed}: {:?}", id.inconsistent);
        }
    }
    eprintln!("motion {motion_h}, inconsistent {inconsistent}, changes {changes}");
    assert!(motion_h <= 12, "{motion_h}");
    assert!(inconsistent <= 2, "{inconsistent}");
    assert!(changes <= 2, "{changes}");
}

/// A source whose gyro increments leave the lattice after sample `from`: an output corrected
/// in floating point (a 20 ppm scale factor) from some point on.
struct LeavesLattice {
    inner: SimSource,
    from: u64,
}

impl SampleSource for LeavesLattice {
    fn sample_interval_s(&self) -> f64 {
        self.inner.sample_interval_s()
    }
    fn visit(&mut self, sink: &mut BatchSink<'_>) -> Result<(), DiagError> {
        let mut k = 0u64;
        let mut out = Vec::new();
        let from = self.from;
        self.inner.visit(&mut |samples, segs| {
            out.clear();
            for s in samples {
                let mut s = *s;
                if k >= from {
                    s.dtheta_rad *= 1.0 + 20e-6;
                }
                k += 1;
                out.push(s);
            }
            sink(&out, segs)
        })
    }
}

#[test]
fn a_gyro_that_leaves_its_lattice_halfway_is_flagged_and_its_quantum_still_sizes_the_rounding() {
    let truth = paper_noise();
    let mut src = [LeavesLattice {
        inner: stationary_run(2.0, 5),
        from: 720_000,
    }];
    let id = identify_all(&mut src, |s| s.inner.segment_labels());
    eprintln!("{:?}\n{:#?}", id.inconsistent, id.gyro);
    assert!(
        id.inconsistent
            .iter()
            .any(|r| r.contains("quantised for only part")),
        "{:?}",
        id.inconsistent
    );
    // The lattice's quantum still sizes the quantization, and the angle random walk stays
    // within 3 sigma of the truth (fitted from the Allan curve instead, the quantum came out at
    // 0.18 arcsec and the angle random walk at 88 times the truth, as in the external suite).
    quantum_exact_and_arw_within_3_sigma(&id, &truth);
}

/// The gyro quantum equals the truth's and the angle random walk lies within 3 sigma of it.
fn quantum_exact_and_arw_within_3_sigma(id: &sins_noiseid::IdentifiedNoise, truth: &NoiseModel) {
    assert!((id.gyro.quantum.value / truth.gyro_quantum_rad - 1.0).abs() < 1e-9);
    within(
        "ARW",
        &id.gyro.white_per_sqrt_s,
        truth.gyro_arw_rad_per_sqrt_s,
        3.0,
    );
}

/// Two 3 h paper-noise runs with the same gyro z turn-on transient (`size` deg/h at the first
/// sample, time constant `tau_s`), identified; the turn-on note must name gyro z.
fn with_gyro_z_turn_on(tau_s: f64, size_deg_per_h: f64) -> sins_noiseid::IdentifiedNoise {
    let transient = EffectSpec::BiasEvent {
        kind: EffectKind::GyroBiasTransient,
        magnitude_si: Vec3::new(0.0, 0.0, size_deg_per_h * DEG / 3600.0),
        onset_s: 0.0,
        time_constant_s: tau_s,
    };
    let with = identify_runs(&mut [
        stationary_run_with(3.0, 11, vec![transient.clone()]),
        stationary_run_with(3.0, 12, vec![transient]),
    ]);
    let note = with.turn_on_note().expect("a turn-on note");
    assert!(note.contains("gyro_z"), "tau {tau_s}: {note}");
    with
}

#[test]
fn faster_turn_on_transients_are_named_and_left_out_too() {
    // The hour-long chunks of the agreement test also catch transients of 5 and 10 min time
    // constant (1 and 0.2 deg/h at turn-on). Left in, the 5 min one would lift the gyro bias
    // instability 1.5 to 5 times; left out, it comes back within 3 sigma.
    let truth = 0.0005 * DEG / 3600.0;
    for (tau_s, size_deg_per_h) in [(300.0, 1.0), (600.0, 0.2)] {
        let with = with_gyro_z_turn_on(tau_s, size_deg_per_h);
        assert!(
            (3590.0..3610.0).contains(&with.turn_on_left_out_s),
            "tau {tau_s}: {}",
            with.turn_on_left_out_s
        );
        within(
            &format!("gyro bias instability, tau {tau_s} s"),
            &with.gyro.bias_instability,
            truth,
            3.0,
        );
    }
}

/// Transients the hour-long chunks miss, found by the direct test of a decay from each run's
/// first sample (`turnon`): 2.5 min at 1 deg/h (left in: bias instability 4.6x the truth), 40
/// min at 0.05 deg/h (10x, and nothing flagged it) and 90 min at 0.1 deg/h (12x). Each is
/// named, left out, and the bias instability comes back within 3 sigma with nothing flagged.
#[test]
fn transients_shorter_or_longer_than_the_chunks_are_named_and_left_out() {
    let truth = 0.0005 * DEG / 3600.0;
    for (tau_s, size_deg_per_h, min_left_out_s) in [
        (150.0, 1.0, 300.0),
        (2400.0, 0.05, 2400.0),
        (5400.0, 0.1, 5400.0),
    ] {
        let with = with_gyro_z_turn_on(tau_s, size_deg_per_h);
        assert!(
            with.turn_on_left_out_s >= min_left_out_s,
            "tau {tau_s}: {}",
            with.turn_on_left_out_s
        );
        within(
            &format!("gyro bias instability, tau {tau_s} s"),
            &with.gyro.bias_instability,
            truth,
            3.0,
        );
        assert!(
            with.inconsistent.is_empty(),
            "tau {tau_s}: {:?}",
            with.inconsistent
        );
    }
}
