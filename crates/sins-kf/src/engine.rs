//! The Kalman filter proper, once the alignment is done: free-inertial navigation on the
//! compensated increments, per-sample transition sums, and once per update interval the
//! covariance propagation, the measurement update and the closed-loop feedback.
//!
//! State vector: the 30/42 states of eq (8), then (if configured) three Gauss-Markov bias
//! wander states per sensor triad, `[w_gx, w_gy, w_gz]` and/or `[w_ax, w_ay, w_az]`, which enter
//! eq (6) exactly like B_g / B_a and decay with their correlation time.

use crate::config::CalibrationConfig;
use crate::covariance::{Covariance, N_MEAS};
use crate::moments::MomentSums;
use crate::states::{NAV_STATES, POS, VEL, n_params};
use faer::Mat;
use sins_imu::ParamModel;
use sins_nav::alignment::AlignmentResult;
use sins_nav::attitude::skew;
use sins_nav::earth::EarthAt;
use sins_nav::error_model::{self, Mat9};
use sins_nav::{
    ConingOrder, Geodetic, Increment, Mat3, Strapdown, StrapdownConfig, Vec3, VerticalChannel,
    compensated_increments,
};

/// Gyro white noise always added to the filter's process noise (rad/sqrt(s)): 1e-5 deg/sqrt(h),
/// 50 times below the paper's IMU. Without any process noise (noise-free data) the navigation
/// block of the covariance becomes so certain that rounding drives it indefinite after a few
/// hours; this floor keeps it regular and moves noise-free estimates by ~1e-6 of Table 1.
pub const ARW_FLOOR_RAD_PER_SQRT_S: f64 = 1e-5 * sins_nav::DEG / 60.0;
/// Accelerometer white noise always added (m/s/sqrt(s)): 0.1 ug/sqrt(Hz), 100 times below the
/// paper's IMU; see [`ARW_FLOOR_RAD_PER_SQRT_S`].
pub const VRW_FLOOR_MPS_PER_SQRT_S: f64 = 0.1 * sins_nav::UG;

/// What one measurement update produced.
pub(crate) struct UpdateOutcome {
    /// Time of the update (s).
    pub(crate) t_s: f64,
    /// Horizontal velocity innovation (m/s).
    pub(crate) horizontal_innovation_mps: f64,
    /// Normalized horizontal velocity innovation `z_N²/S_NN + z_E²/S_EE` (χ² with 2 degrees of
    /// freedom for a consistent filter).
    pub(crate) horizontal_nis: f64,
    /// North and east innovations over the square roots of their predicted variances.
    pub(crate) standardized: [f64; 2],
    /// Corrections of the coefficient estimates (state order); zeros when rejected.
    pub(crate) dparams: Vec<f64>,
    /// True when the innovation exceeded the gate and the measurement was not used.
    pub(crate) rejected: bool,
    /// The gain this update applied, for the filters that follow this one (`None` unless
    /// asked for).
    pub(crate) gain: Option<SharedGain>,
}

/// One measurement update's gain, handed by a leading filter to the filters that follow it
/// (see [`crate::CalibrationFilter::leading`]): `K` (states x 6 measurements, row-major) and the
/// predicted variances of the north and east velocity innovations (m²/s²).
#[derive(Clone, Debug)]
pub struct SharedGain {
    /// `K`, row-major, `None` when the leader rejected the update (innovation gate).
    pub(crate) k: Option<Vec<f64>>,
    /// Predicted variances of the north and east velocity innovations (m²/s²).
    pub(crate) s_h: [f64; 2],
}

/// One modelled bias-wander triad.
struct Wander {
    /// First coefficient index of the triad (0: B_g, 3: B_a).
    first: usize,
    /// `e^{−T/τ}` per update interval.
    decay: f64,
    /// Current estimate (SI), added to the constant bias in the compensation.
    estimate: Vec3,
}

/// Filter state after the alignment.
pub(crate) struct Engine {
    pub(crate) alignment: AlignmentResult,
    pub(crate) nav: Strapdown,
    pub(crate) cov: Covariance,
    sums: MomentSums,
    c_start: Mat3,
    pending: [(Vec3, Vec3, [f64; 3]); 2],
    n_pending: usize,
    h: f64,
    samples_per_update: usize,
    n_params: usize,
    wander: Vec<Wander>,
    decay: Vec<f64>,
    q_params: Vec<f64>,
    r: [f64; N_MEAS],
    qg: f64,
    qa: f64,
    site: Geodetic,
    pub(crate) updates: usize,
    /// Samples since the last update, counted by a following engine (which keeps no sums).
    led_count: usize,
}

/// `exp([a×])` to second order (|a| ≤ a few mrad per sample).
#[inline]
fn small_rotation(a: &Vec3) -> Mat3 {
    let k = skew(a);
    Mat3::identity() + k + 0.5 * k * k
}

impl Engine {
    /// Start after `alignment` with initial 1-sigmas `sigma` of the eq-(8) states.
    pub(crate) fn new(cfg: &CalibrationConfig, alignment: AlignmentResult, sigma: &[f64]) -> Self {
        let h = cfg.sample_interval_s;
        let n = cfg.samples_per_update();
        let t = n as f64 * h;
        let np = n_params(cfg.model);
        let triads = cfg.noise.wander_triads();
        let mut sig = sigma.to_vec();
        let mut decay = vec![1.0; np];
        let mut q_params = vec![0.0; np];
        let mut wander = Vec::new();
        for &(first, s, tau) in &triads {
            let d = (-t / tau).exp();
            sig.extend([s; 3]);
            decay.extend([d; 3]);
            q_params.extend([s * s * (1.0 - d * d); 3]);
            wander.push(Wander {
                first,
                decay: d,
                estimate: Vec3::zeros(),
            });
        }
        let e = EarthAt::new(cfg.site.lat_rad, cfg.site.height_m);
        let sp = cfg.measurement.position_m;
        let sv2 = cfg.measurement.velocity_mps.powi(2);
        let r = [
            sv2,
            sv2,
            sv2,
            (sp / e.meridian_plus_h_m).powi(2),
            (sp / (e.transverse_plus_h_m * e.cos_lat)).powi(2),
            sp * sp,
        ];
        let nav_cfg = StrapdownConfig {
            sample_interval_s: h,
            coning: ConingOrder::TwoSample,
            vertical: VerticalChannel::Free,
        };
        Self {
            alignment,
            nav: Strapdown::new(nav_cfg, alignment.state),
            cov: Covariance::from_sigmas(&sig),
            sums: MomentSums::new(t, h, cfg.model == ParamModel::States42),
            c_start: alignment
                .state
                .ned_from_body
                .to_rotation_matrix()
                .into_inner(),
            pending: [(Vec3::zeros(), Vec3::zeros(), [0.0; 3]); 2],
            n_pending: 0,
            h,
            samples_per_update: n,
            n_params: np,
            wander,
            decay,
            q_params,
            r,
            qg: cfg.noise.gyro_arw_rad_per_sqrt_s.powi(2) + ARW_FLOOR_RAD_PER_SQRT_S.powi(2),
            qa: cfg.noise.accel_vrw_mps_per_sqrt_s.powi(2) + VRW_FLOOR_MPS_PER_SQRT_S.powi(2),
            site: cfg.site,
            updates: 0,
            led_count: 0,
        }
    }

    /// Current bias-wander estimates to add to the constant gyro and accelerometer biases.
    pub(crate) fn wander_bias(&self) -> (Vec3, Vec3) {
        let (mut g, mut a) = (Vec3::zeros(), Vec3::zeros());
        for w in &self.wander {
            if w.first == 0 {
                g = w.estimate
            } else {
                a = w.estimate
            }
        }
        (g, a)
    }

    /// Add one compensated sample with its temperature offsets; returns true when an update
    /// interval is complete (call [`Engine::update`] then).
    #[inline]
    pub(crate) fn push(&mut self, dtheta: Vec3, dv: Vec3, dtemp: [f64; 3]) -> bool {
        if !self.pend(dtheta, dv, dtemp) {
            return false;
        }
        let [(th1, v1, t1), (th2, v2, t2)] = self.pending;
        let c1 = self.c_start * small_rotation(&(0.5 * th1));
        let c2 = self.c_start * small_rotation(&(th1 + 0.5 * th2));
        self.sums.add(&c1, &th1, &v1, &t1);
        self.sums.add(&c2, &th2, &v2, &t2);
        self.refresh_c_start();
        self.sums.count() >= self.samples_per_update
    }

    /// The body-to-NED matrix at the start of the next pair, from the navigation's attitude
    /// (the transition sums rotate each sample with it; a following engine keeps none).
    fn refresh_c_start(&mut self) {
        self.c_start = self
            .nav
            .state()
            .ned_from_body
            .to_rotation_matrix()
            .into_inner();
    }

    /// A following engine's [`Engine::push`]: the navigation only, no transition sums (the
    /// leader's gains stand for its covariance); true when an update interval is complete (call
    /// [`Engine::update_led`] then).
    #[inline]
    pub(crate) fn push_led(&mut self, dtheta: Vec3, dv: Vec3) -> bool {
        if !self.pend(dtheta, dv, [0.0; 3]) {
            return false;
        }
        self.led_count += 2;
        self.led_count >= self.samples_per_update
    }

    /// The samples up to and including the one whose push completes the next update interval
    /// ([`Engine::push`] or, when `led`, [`Engine::push_led`]): the compensation stays the
    /// same until then.
    pub(crate) fn samples_to_update(&self, led: bool) -> usize {
        let count = if led {
            self.led_count
        } else {
            self.sums.count()
        };
        let pairs = self
            .samples_per_update
            .saturating_sub(count)
            .div_ceil(2)
            .max(1);
        2 * pairs - self.n_pending
    }

    /// Hold a sample; with the second of a pair, advance the navigation over the pair and
    /// return true.
    #[inline]
    fn pend(&mut self, dtheta: Vec3, dv: Vec3, dtemp: [f64; 3]) -> bool {
        self.pending[self.n_pending] = (dtheta, dv, dtemp);
        self.n_pending += 1;
        if self.n_pending < 2 {
            return false;
        }
        self.n_pending = 0;
        let [(th1, v1, _), (th2, v2, _)] = self.pending;
        let pair = [
            Increment {
                dtheta_rad: th1,
                dv_mps: v1,
            },
            Increment {
                dtheta_rad: th2,
                dv_mps: v2,
            },
        ];
        let (phi, dv_body) = compensated_increments(ConingOrder::TwoSample, &pair, None);
        self.nav.advance_interval(&phi, &dv_body, 2.0 * self.h);
        true
    }

    /// `Φ_np` for all non-navigation states: the coefficient block, then the wander columns
    /// (copies of the bias columns: the wander enters eq (6) like the bias).
    fn phi_np(&self, f: &Mat9) -> Mat<f64> {
        let base = self.sums.phi_np(f, self.n_params);
        if self.wander.is_empty() {
            return base;
        }
        let m = self.n_params + 3 * self.wander.len();
        Mat::from_fn(NAV_STATES, m, |i, j| {
            if j < self.n_params {
                base[(i, j)]
            } else {
                let w = &self.wander[(j - self.n_params) / 3];
                base[(i, w.first + (j - self.n_params) % 3)]
            }
        })
    }

    /// Propagate over the completed interval, update with velocity and position, feed the
    /// navigation errors back into the strapdown solution and return the rest. A horizontal
    /// velocity innovation above `gate_mps` is not used (innovation gating): motion of the IMU
    /// must not be absorbed into attitude and coefficients. With `share`, the outcome carries the
    /// gain for following filters.
    pub(crate) fn update(
        &mut self,
        gate_mps: f64,
        share: bool,
    ) -> Result<UpdateOutcome, &'static str> {
        let t = self.samples_per_update as f64 * self.h;
        let st = *self.nav.state();
        let pos = st.position;
        self.sums.flush();
        let f_ned = self.sums.mean_specific_force_ned();
        let f = error_model::f_matrix(pos.lat_rad, pos.height_m, &st.vel_ned_mps, &f_ned);
        let phi_nn = error_model::transition(&f, t);
        let phi_np = self.phi_np(&f);
        let q_nn = error_model::process_noise(&f, t, self.qg, self.qa);
        self.cov
            .propagate(&phi_nn, &phi_np, &q_nn, &self.decay, &self.q_params);
        self.sums.clear();
        let s_h = [
            self.cov.variance(VEL) + self.r[0],
            self.cov.variance(VEL + 1) + self.r[1],
        ];
        let z = self.innovation();
        if z[0].hypot(z[1]) > gate_mps {
            let mut out = self.outcome(&z, s_h, None);
            out.gain = share.then_some(SharedGain { k: None, s_h });
            return Ok(out);
        }
        let (x, k) = self
            .cov
            .update(&z, &self.r)
            .ok_or("innovation covariance")?;
        if !(x.iter().all(|v| v.is_finite()) && self.cov.is_healthy()) {
            return Err("non-finite state or covariance");
        }
        let mut out = self.outcome(&z, s_h, Some(&x));
        self.refresh_c_start();
        out.gain = share.then(|| SharedGain {
            k: Some(
                (0..k.nrows())
                    .flat_map(|i| (0..N_MEAS).map(move |j| (i, j)))
                    .map(|(i, j)| k[(i, j)])
                    .collect(),
            ),
            s_h,
        });
        Ok(out)
    }

    /// A following engine's [`Engine::update`]: the leader's `gain` applied to this engine's own
    /// innovation, no covariance of its own. The update is rejected when the innovation exceeds
    /// `gate_mps` or the leader rejected its own (then it has no gain to give).
    pub(crate) fn update_led(
        &mut self,
        gain: &SharedGain,
        gate_mps: f64,
    ) -> Result<UpdateOutcome, &'static str> {
        self.led_count = 0;
        let z = self.innovation();
        let Some(k) = gain.k.as_ref().filter(|_| z[0].hypot(z[1]) <= gate_mps) else {
            return Ok(self.outcome(&z, gain.s_h, None));
        };
        let n = self.cov.n();
        if k.len() != n * N_MEAS {
            return Err("the leader's gain has another number of states");
        }
        let x: Vec<f64> = k
            .chunks_exact(N_MEAS)
            .map(|row| row.iter().zip(&z).map(|(a, b)| a * b).sum())
            .collect();
        if !x.iter().all(|v| v.is_finite()) {
            return Err("non-finite state");
        }
        Ok(self.outcome(&z, gain.s_h, Some(&x)))
    }

    /// The measurement of eqs (9)-(11) at the end of an interval (velocity, then latitude,
    /// longitude and height against the site), after the wander estimates decayed over it.
    fn innovation(&mut self) -> [f64; N_MEAS] {
        for w in &mut self.wander {
            w.estimate *= w.decay;
        }
        let st = self.nav.state();
        let (v, pos) = (st.vel_ned_mps, st.position);
        [
            v.x,
            v.y,
            v.z,
            pos.lat_rad - self.site.lat_rad,
            pos.lon_rad - self.site.lon_rad,
            pos.height_m - self.site.height_m,
        ]
    }

    /// Apply the state estimate `x` (none: the update was rejected), feeding the navigation
    /// errors back into the strapdown solution, and describe the update.
    fn outcome(&mut self, z: &[f64; N_MEAS], s_h: [f64; 2], x: Option<&[f64]>) -> UpdateOutcome {
        let t_s = self.nav.state().t_s;
        let nis = z[0] * z[0] / s_h[0] + z[1] * z[1] / s_h[1];
        let mut out = UpdateOutcome {
            t_s,
            horizontal_innovation_mps: z[0].hypot(z[1]),
            horizontal_nis: nis,
            standardized: [z[0] / s_h[0].sqrt(), z[1] / s_h[1].sqrt()],
            dparams: vec![0.0; self.n_params],
            rejected: x.is_none(),
            gain: None,
        };
        let Some(x) = x else {
            return out;
        };
        let phi = Vec3::new(x[0], x[1], x[2]);
        let dvel = Vec3::new(x[VEL], x[VEL + 1], x[VEL + 2]);
        let dpos = Geodetic {
            lat_rad: x[POS],
            lon_rad: x[POS + 1],
            height_m: x[POS + 2],
        };
        self.nav.correct(&phi, &dvel, Some(&dpos));
        let first_wander = NAV_STATES + self.n_params;
        for (k, w) in self.wander.iter_mut().enumerate() {
            let i = first_wander + 3 * k;
            w.estimate += Vec3::new(x[i], x[i + 1], x[i + 2]);
        }
        self.updates += 1;
        out.dparams = x[NAV_STATES..first_wander].to_vec();
        out
    }

    /// Length of one update interval (s).
    pub(crate) fn interval_s(&self) -> f64 {
        self.samples_per_update as f64 * self.h
    }

    /// Covariance of the coefficient states of eq (8) (without the navigation and wander
    /// states), row-major `n_params × n_params`, SI, state order.
    pub(crate) fn param_covariance(&self) -> Vec<f64> {
        let np = self.n_params;
        (0..np * np)
            .map(|k| self.cov.entry(NAV_STATES + k / np, NAV_STATES + k % np))
            .collect()
    }

    /// 1-sigma of the eq-(8) states (without the wander states).
    pub(crate) fn sigmas(&self) -> Vec<f64> {
        (0..NAV_STATES + self.n_params)
            .map(|i| self.cov.sigma(i))
            .collect()
    }
}
