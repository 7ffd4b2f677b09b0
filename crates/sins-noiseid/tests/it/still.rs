//! The stillness detector on synthetic rates with known truth: its false-alarm rate on quiet
//! data, a disturbance found where it is, and still stretches found in an unlabelled run.

use sins_noiseid::still::{StillnessConfig, WindowBuilder, detect};

/// A small deterministic Gaussian generator (xorshift64* and Box-Muller).
struct Gauss(u64);

impl Gauss {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

const H: f64 = 0.01;
/// White noise per sample: a navigation-grade gyro (0.005 deg/sqrt(h) at 100 Hz) and a
/// 10 ug/sqrt(Hz) accelerometer.
const GYRO_SIGMA: f64 = 1.454e-6 / 0.1;
const ACCEL_SIGMA: f64 = 10.0 * 9.80665e-6 / 0.1;
/// Earth rate and gravity on the sensor axes (constant while still).
const LEVEL: [f64; 6] = [0.0, 5.9e-5, 4.3e-5, 0.0, 0.0, 9.79];

/// Rates of `n` samples: still, plus `extra(t)` (rad/s, m/s²).
fn run(seed: u64, n: usize, extra: &dyn Fn(f64) -> [f64; 6]) -> WindowBuilder {
    let cfg = StillnessConfig::default();
    let mut b = WindowBuilder::new(H, &cfg);
    let mut g = Gauss(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    for k in 0..n {
        let t = (k + 1) as f64 * H;
        let e = extra(t);
        let r: [f64; 6] = std::array::from_fn(|c| {
            let s = if c < 3 { GYRO_SIGMA } else { ACCEL_SIGMA };
            LEVEL[c] + s * g.normal() + e[c]
        });
        b.push(t, r, true);
    }
    b.close();
    b
}

#[test]
fn quiet_data_raise_about_the_stated_false_alarms() {
    // 100 seeds of one hour: 100 hours at 0.01 false alarms per hour and test gives about 2
    // expected flags (two tests); more than 8 has a Poisson probability below 1e-4.
    let mut flags = 0usize;
    let mut windows = 0usize;
    for seed in 0..100 {
        let b = run(seed, 360_000, &|_| [0.0; 6]);
        let s = detect("quiet", &b.windows, &StillnessConfig::default());
        assert!(s.judged);
        flags += s.motion.len();
        windows += b.windows.len();
        // The white-noise floor is the sensor's own, within a few percent.
        assert!(
            (s.sigma2[0].sqrt() / GYRO_SIGMA - 1.0).abs() < 0.05,
            "{}",
            s.sigma2[0].sqrt()
        );
        assert!((s.sigma2[5].sqrt() / ACCEL_SIGMA - 1.0).abs() < 0.05);
    }
    assert_eq!(windows, 100 * 3600);
    assert!(flags <= 8, "{flags} false alarms in 100 h of still data");
}

#[test]
fn a_disturbance_inside_a_still_stretch_is_found_where_it_is() {
    // 5 s of a 0.2 deg/s rotation about y at 600 s (a vehicle rocking), in one hour.
    let rate = 0.2f64.to_radians();
    let b = run(7, 360_000, &|t| {
        let on = (600.0..605.0).contains(&t);
        [0.0, if on { rate } else { 0.0 }, 0.0, 0.0, 0.0, 0.0]
    });
    let s = detect("rocking", &b.windows, &StillnessConfig::default());
    assert_eq!(s.motion.len(), 1, "{:?}", s.motion);
    let m = &s.motion[0];
    assert_eq!(m.channel, "gyro_y");
    // Within two windows: the sample at 600.00 s closes the window that starts at 599 s.
    assert!(
        (m.start_s - 600.0).abs() <= 2.0 && (m.end_s - 605.0).abs() <= 2.0,
        "{m:?}"
    );
    // Not back and forth: it turned through 5 s x 0.2 deg/s = 1 deg.
    assert!((m.excursion.to_degrees() - 1.0).abs() < 0.05, "{m:?}");
    assert!((m.size / rate - 1.0).abs() < 0.05, "size {}", m.size);
    // The windows around it are not still; the rest are.
    let still: usize = s.still.iter().filter(|x| **x).count();
    assert!((3600 - 5 - 2 * 2 - 4..3600 - 5).contains(&still), "{still}");
    // A shock on the accelerometer (vibration without a mean change) is found too.
    let b = run(8, 360_000, &|t| {
        let on = (1800.0..1801.0).contains(&t);
        let v = if on {
            0.05 * (2.0 * std::f64::consts::PI * 30.0 * t).sin()
        } else {
            0.0
        };
        [0.0, 0.0, 0.0, v, 0.0, 0.0]
    });
    let s = detect("shock", &b.windows, &StillnessConfig::default());
    assert_eq!(s.motion.len(), 1, "{:?}", s.motion);
    assert_eq!(s.motion[0].channel, "accel_x");
    // A vibration, not a rotation or acceleration: its RMS, not a mean offset.
    let rms = 0.05 / 2f64.sqrt();
    assert!(
        (s.motion[0].vibration / rms - 1.0).abs() < 0.05,
        "{:?}",
        s.motion[0]
    );
    assert!(s.motion[0].size < 0.1 * rms, "{:?}", s.motion[0]);
}

#[test]
fn still_stretches_are_found_in_an_unlabelled_run() {
    // Still 0-300 s, driving 300-900 s (turns and accelerations), still 900-1500 s.
    let b = run(11, 150_000, &|t| {
        if (300.0..900.0).contains(&t) {
            [
                0.01 * (0.3 * t).sin(),
                0.0,
                0.1 * (0.05 * t).sin(),
                0.5 * (0.2 * t).cos(),
                0.0,
                0.0,
            ]
        } else {
            [0.0; 6]
        }
    });
    let s = detect("drive", &b.windows, &StillnessConfig::default());
    let still_s: Vec<f64> = b
        .windows
        .iter()
        .zip(&s.still)
        .filter(|(_, st)| **st)
        .map(|(w, _)| w.start_s)
        .collect();
    assert!(
        still_s.iter().all(|t| *t < 300.0 || *t >= 900.0),
        "still inside the drive"
    );
    let early = still_s.iter().filter(|t| **t < 300.0).count();
    let late = still_s.iter().filter(|t| **t >= 900.0).count();
    assert!(early >= 295 && late >= 595, "{early} {late}");
}

/// Rates of `n` samples of the paper's gyro (0.0005 deg/sqrt(h)) whose angle increments are
/// quantised at 1 arcsec (the angle accumulated and rounded, the remainder carried), plus
/// `extra(t)`; the accelerometers as in [`run`].
fn quantised_run(seed: u64, n: usize, extra: &dyn Fn(f64) -> [f64; 6]) -> WindowBuilder {
    const QUANTUM_RAD: f64 = 4.848_136_811e-6;
    let arw_sigma = 1.454e-7 / 0.1;
    let cfg = StillnessConfig::default();
    let mut b = WindowBuilder::new(H, &cfg);
    let mut g = Gauss(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let mut angle = [0.0f64; 3];
    let mut counted = [0.0f64; 3];
    for k in 0..n {
        let t = (k + 1) as f64 * H;
        let e = extra(t);
        let r: [f64; 6] = std::array::from_fn(|c| {
            if c < 3 {
                angle[c] += (LEVEL[c] + arw_sigma * g.normal() + e[c]) * H;
                let total = (angle[c] / QUANTUM_RAD).round() * QUANTUM_RAD;
                let inc = total - counted[c];
                counted[c] = total;
                inc / H
            } else {
                LEVEL[c] + ACCEL_SIGMA * g.normal() + e[c]
            }
        });
        b.push(t, r, true);
    }
    b.close();
    b
}

#[test]
fn a_quantised_gyro_at_rest_is_still_and_its_motion_is_still_found() {
    // The paper's gyro at rest turns less than one quantum per sample (0.12 arcsec on y), so
    // most increments are 0 and a window's scatter is a pulse or two. Before the detector's
    // floor included the quantisation (step^2/12), its quiet floor was ~0 and every pulse
    // read as motion (125 "motions" of 1 deg/h in one 4.2 h calibration run).
    let mut flags = 0usize;
    for seed in 0..5 {
        let b = quantised_run(seed, 360_000, &|_| [0.0; 6]);
        let s = detect("quantised", &b.windows, &StillnessConfig::default());
        flags += s.motion.len();
        // Gyro x, level 0, has mostly empty windows: its floor is the quantisation's, one
        // arcsec per 10 ms over sqrt(12). Gyro y's pulses (p = 0.12 per sample) scatter more
        // (p (1 - p) = 0.106 > 1/12 of a step squared), so its floor is its own.
        let floor = 4.848e-6 / H / 12f64.sqrt();
        assert!(
            (s.sigma2[0].sqrt() / floor - 1.0).abs() < 0.01,
            "gyro x floor {} against {floor}",
            s.sigma2[0].sqrt()
        );
        assert!(s.sigma2[1].sqrt() >= floor);
    }
    // 5 h at 0.02 expected flags per hour: more than 2 has a Poisson probability below 1e-3.
    assert!(
        flags <= 2,
        "{flags} motions in 5 h of a quantised gyro at rest"
    );
    // A 0.2 deg/s rotation for 5 s (4.3 quanta per sample) is found.
    let rate = 0.2f64.to_radians();
    let b = quantised_run(7, 360_000, &|t| {
        let on = (600.0..605.0).contains(&t);
        [0.0, if on { rate } else { 0.0 }, 0.0, 0.0, 0.0, 0.0]
    });
    let s = detect("rocking", &b.windows, &StillnessConfig::default());
    assert_eq!(s.motion.len(), 1, "{:?}", s.motion);
    assert_eq!(s.motion[0].channel, "gyro_y");
    assert!(
        (s.motion[0].start_s - 600.0).abs() <= 2.0,
        "{:?}",
        s.motion[0]
    );
    // A slow turn, 0.02 deg/s for a minute, is found. The floor makes the change test white
    // with the quantisation's variance, which puts its single-axis limit near 28 deg/h here
    // (sqrt(chi2 threshold 38 x 2 sigma^2 / n) with sigma^2 = 0.1 steps^2 of 100 deg/h).
    let slow = 0.02f64.to_radians();
    let b = quantised_run(9, 360_000, &|t| {
        let on = (1200.0..1260.0).contains(&t);
        [0.0, 0.0, if on { slow } else { 0.0 }, 0.0, 0.0, 0.0]
    });
    let s = detect("slow turn", &b.windows, &StillnessConfig::default());
    assert!(
        s.motion
            .iter()
            .any(|m| m.channel == "gyro_z" && (m.start_s - 1200.0).abs() <= 2.0),
        "{:?}",
        s.motion
    );
}
