//! High-precision strapdown mechanization on angular and velocity increments in the NED frame.
//!
//! One navigation update consumes `N` consecutive samples (the "N-sample" algorithms of Savage
//! and Ignagni): the body attitude is advanced by the rotation vector
//! `φ = Σθ_i + Σ_{i<j} k_ij θ_i × θ_j` (coning compensation), the specific-force increment in
//! the body frame is `ΔV = Σv_i + ½ Σθ × Σv + ⅙ Σθ × (Σθ × Σv) + Σ_{i<j} k_ij (θ_i × v_j + v_i × θ_j)` (rotation and
//! sculling compensation), the navigation frame is rotated by `ω_in^n T`, and gravity and
//! Coriolis are applied at the midpoint of the update. Position (latitude, longitude, height) is
//! integrated with the trapezoidal velocity. `ConingOrder::OnePlusPrevious` updates every sample
//! using the previous sample for the cross-product terms (coefficient 1/12).

use crate::attitude::quat_from_rotation_vector;
use crate::earth::{EarthAt, Geodetic};
use crate::{Quat, Vec3};

/// One IMU increment pair over a sample interval (rad, m/s), already compensated.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Increment {
    /// Angular increment in the body frame (rad).
    pub dtheta_rad: Vec3,
    /// Velocity (specific-force) increment in the body frame (m/s).
    pub dv_mps: Vec3,
}

/// The coning/sculling algorithm: how many samples one navigation update consumes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConingOrder {
    /// Update every sample; cross products with the previous sample (1/12).
    OnePlusPrevious,
    /// Classic two-sample algorithm (2/3): update every 2 samples.
    TwoSample,
    /// Three-sample algorithm (33/80, 57/80): update every 3 samples.
    ThreeSample,
    /// Four-sample algorithm (Ignagni /945 coefficients): update every 4 samples.
    FourSample,
    /// High-order look-ahead reconstruction of each sample interval ([`crate::reconstruct`]),
    /// one update per sample; replays run it through
    /// [`crate::reconstruct::IncrementReconstructor`] and [`Strapdown::advance_interval`]. Fed
    /// sample by sample through [`Strapdown::push`] (e.g. during self-alignment) it is the
    /// single-sample update `φ = Δθ`, `ΔV = Δv + ½ Δθ × Δv` without coning or sculling terms.
    Reconstruct,
}

impl ConingOrder {
    /// Samples consumed per navigation update.
    pub fn samples_per_update(self) -> usize {
        match self {
            ConingOrder::OnePlusPrevious | ConingOrder::Reconstruct => 1,
            ConingOrder::TwoSample => 2,
            ConingOrder::ThreeSample => 3,
            ConingOrder::FourSample => 4,
        }
    }

    /// Cross-product coefficients `k_ij` (i < j, 0-based sample indices) of this algorithm.
    fn coefficients(self) -> &'static [(usize, usize, f64)] {
        const K2: [(usize, usize, f64); 1] = [(0, 1, 2.0 / 3.0)];
        const K3: [(usize, usize, f64); 3] = [
            (0, 1, 57.0 / 80.0),
            (1, 2, 57.0 / 80.0),
            (0, 2, 33.0 / 80.0),
        ];
        const K4: [(usize, usize, f64); 6] = [
            (0, 1, 736.0 / 945.0),
            (2, 3, 736.0 / 945.0),
            (0, 2, 334.0 / 945.0),
            (1, 3, 334.0 / 945.0),
            (0, 3, 526.0 / 945.0),
            (1, 2, 654.0 / 945.0),
        ];
        match self {
            ConingOrder::OnePlusPrevious | ConingOrder::Reconstruct => &[],
            ConingOrder::TwoSample => &K2,
            ConingOrder::ThreeSample => &K3,
            ConingOrder::FourSample => &K4,
        }
    }
}

/// Body rotation vector φ (rad, coning included) and start-of-update body-frame velocity
/// increment ΔV (m/s, rotation and sculling included) of the `samples` of one update under
/// `order`; `previous` is the sample before them (used by [`ConingOrder::OnePlusPrevious`]).
/// Rotation compensation is kept to second order: for a constant rate over the update,
/// `∫ exp([α(t)×]) f dt = V + ½ Θ×V + ⅙ Θ×(Θ×V) + …`; the last term, often dropped, is a
/// 0.02 ppm scale-factor-like error during 9 deg/s turns at 100 Hz.
pub fn compensated_increments(
    order: ConingOrder,
    samples: &[Increment],
    previous: Option<&Increment>,
) -> (Vec3, Vec3) {
    let theta: Vec3 = samples.iter().map(|i| i.dtheta_rad).sum();
    let v: Vec3 = samples.iter().map(|i| i.dv_mps).sum();
    let mut coning = Vec3::zeros();
    let mut sculling = Vec3::zeros();
    let cross = |a: &Increment, b: &Increment| {
        (
            a.dtheta_rad.cross(&b.dtheta_rad),
            a.dtheta_rad.cross(&b.dv_mps) + a.dv_mps.cross(&b.dtheta_rad),
        )
    };
    if order == ConingOrder::OnePlusPrevious {
        if let (Some(p), Some(cur)) = (previous, samples.first()) {
            let (c, s) = cross(p, cur);
            (coning, sculling) = (c / 12.0, s / 12.0);
        }
    } else {
        for &(i, j, k) in order.coefficients() {
            let (c, s) = cross(&samples[i], &samples[j]);
            coning += k * c;
            sculling += k * s;
        }
    }
    let rotation = 0.5 * theta.cross(&v) + theta.cross(&theta.cross(&v)) / 6.0;
    (theta + coning, v + rotation + sculling)
}

/// Vertical-channel treatment. Pure inertial height is unstable (time constant ≈ 13 min), so
/// turntable experiments hold or damp it to the known site height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VerticalChannel {
    /// Pure inertial (unstable); for filters that observe height themselves.
    Free,
    /// Height fixed at `height_m`, vertical velocity zero.
    Hold {
        /// Reference height (m).
        height_m: f64,
    },
    /// Second-order critically damped loop towards `height_m` with time constant `tau_s`:
    /// `ḣ = -v_D - (2/τ) δh`, `v̇_D = … + (1/τ²) δh`.
    Damped {
        /// Reference height (m).
        height_m: f64,
        /// Loop time constant (s).
        tau_s: f64,
    },
}

/// Mechanization settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrapdownConfig {
    /// Sample interval of the increments (s).
    pub sample_interval_s: f64,
    /// Coning/sculling algorithm.
    pub coning: ConingOrder,
    /// Vertical channel.
    pub vertical: VerticalChannel,
}

/// Navigation state: attitude, NED velocity, geodetic position and time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NavState {
    /// Time of validity (s).
    pub t_s: f64,
    /// Attitude `ned_from_body`.
    pub ned_from_body: Quat,
    /// Velocity over the Earth in NED (m/s).
    pub vel_ned_mps: Vec3,
    /// Position.
    pub position: Geodetic,
}

impl NavState {
    /// State at rest at `position` with attitude `ned_from_body` at time `t_s`.
    pub fn at_rest(t_s: f64, ned_from_body: Quat, position: Geodetic) -> Self {
        Self {
            t_s,
            ned_from_body,
            vel_ned_mps: Vec3::zeros(),
            position,
        }
    }
}

/// Strapdown integrator. Feed compensated increments with [`Strapdown::push`]; the state
/// advances once every `coning.samples_per_update()` samples.
#[derive(Clone, Debug)]
pub struct Strapdown {
    config: StrapdownConfig,
    state: NavState,
    prev_vel_ned_mps: Vec3,
    buffer: [Increment; 4],
    n_buffered: usize,
    /// Sum of the buffered samples' own intervals (s), for [`Strapdown::push_timed`].
    buffered_interval_s: f64,
    previous: Option<Increment>,
    last_specific_force_ned_mps2: Vec3,
}

impl Strapdown {
    /// Integrator starting from `state`.
    pub fn new(config: StrapdownConfig, state: NavState) -> Self {
        Self {
            config,
            prev_vel_ned_mps: state.vel_ned_mps,
            state,
            buffer: [Increment::default(); 4],
            n_buffered: 0,
            buffered_interval_s: 0.0,
            previous: None,
            last_specific_force_ned_mps2: Vec3::zeros(),
        }
    }

    /// Current navigation state (valid at the last completed update).
    pub fn state(&self) -> &NavState {
        &self.state
    }

    /// Mutable state, for closed-loop corrections by a filter.
    pub fn state_mut(&mut self) -> &mut NavState {
        &mut self.state
    }

    /// The configuration.
    pub fn config(&self) -> &StrapdownConfig {
        &self.config
    }

    /// Mean specific force in NED over the last update (m/s^2), for error-state filters.
    pub fn specific_force_ned_mps2(&self) -> Vec3 {
        self.last_specific_force_ned_mps2
    }

    /// Samples waiting for the next update.
    pub fn pending_samples(&self) -> usize {
        self.n_buffered
    }

    /// Add one sample; returns true when it completed a navigation update.
    #[inline]
    pub fn push(&mut self, inc: &Increment) -> bool {
        self.buffer[self.n_buffered] = *inc;
        self.n_buffered += 1;
        if self.n_buffered < self.config.coning.samples_per_update() {
            return false;
        }
        self.n_buffered = 0;
        let (phi, dv_body) = self.compensated_increments();
        self.advance(&phi, &dv_body);
        true
    }

    /// Add one sample that covers its own interval `interval_s` (s), for data whose recorded
    /// time stamps are trusted: the update advances over the sum of its samples' intervals
    /// instead of a multiple of the nominal one. Returns true when it completed an update.
    /// Do not mix with [`Strapdown::push`] within one update.
    #[inline]
    pub fn push_timed(&mut self, inc: &Increment, interval_s: f64) -> bool {
        self.buffer[self.n_buffered] = *inc;
        self.n_buffered += 1;
        self.buffered_interval_s += interval_s;
        if self.n_buffered < self.config.coning.samples_per_update() {
            return false;
        }
        self.n_buffered = 0;
        let t = std::mem::take(&mut self.buffered_interval_s);
        let (phi, dv_body) = self.compensated_increments();
        self.advance_interval(&phi, &dv_body, t);
        true
    }

    /// Coning-compensated rotation vector and rotation/sculling-compensated velocity increment
    /// of the buffered samples (body frame).
    fn compensated_increments(&mut self) -> (Vec3, Vec3) {
        let n = self.config.coning.samples_per_update();
        let s = &self.buffer[..n];
        let out = compensated_increments(self.config.coning, s, self.previous.as_ref());
        if self.config.coning == ConingOrder::OnePlusPrevious {
            self.previous = Some(s[0]);
        }
        out
    }

    /// Advance the state by one update with body rotation vector `phi` and compensated body
    /// velocity increment `dv_body` over the algorithm's update interval.
    fn advance(&mut self, phi: &Vec3, dv_body: &Vec3) {
        let t = self.config.sample_interval_s * self.config.coning.samples_per_update() as f64;
        self.advance_interval(phi, dv_body, t);
    }

    /// Advance the state over `interval_s` with an externally computed body rotation vector
    /// `phi_body_rad` (attitude change `C_b(k-1)_b(k) = exp([φ×])`, coning included) and
    /// body-frame specific-force velocity increment `dv_body_mps` resolved in the body frame at
    /// the start of the interval (rotation and sculling included). Used by algorithms that
    /// compute these increments themselves (e.g. high-order reconstructions); must not be mixed
    /// with [`Strapdown::push`] while samples are pending.
    pub fn advance_interval(&mut self, phi_body_rad: &Vec3, dv_body_mps: &Vec3, interval_s: f64) {
        let (phi, dv_body, t) = (phi_body_rad, dv_body_mps, interval_s);
        let vertical_ref_m = self.vertical_reference(self.state.position.height_m);
        let st = &mut self.state;
        // Midpoint extrapolation of velocity and position for the Earth terms.
        let v_mid = st.vel_ned_mps + 0.5 * (st.vel_ned_mps - self.prev_vel_ned_mps);
        let meridian0_m = EarthAt::meridian_plus_h_at(st.position.lat_rad, st.position.height_m);
        let lat_mid = st.position.lat_rad + 0.5 * t * v_mid.x / meridian0_m;
        let h_mid = st.position.height_m - 0.5 * t * v_mid.z;
        let earth = EarthAt::new(lat_mid, h_mid);
        let w_ie = earth.earth_rate_ned_radps;
        let w_en = earth.transport_rate_ned_radps(&v_mid);
        let zeta = (w_ie + w_en) * t;

        // Specific-force increment in the navigation frame at k-1, rotated to the midpoint.
        let dv_sf_prev = st.ned_from_body * dv_body;
        let dv_sf = dv_sf_prev - 0.5 * zeta.cross(&dv_sf_prev);
        self.last_specific_force_ned_mps2 = dv_sf / t;
        let mut dv_gcor = (earth.gravity_ned_mps2() - (2.0 * w_ie + w_en).cross(&v_mid)) * t;

        let v_old = st.vel_ned_mps;
        let h_err = st.position.height_m - vertical_ref_m;
        if let VerticalChannel::Damped { tau_s, .. } = self.config.vertical {
            dv_gcor.z += h_err / (tau_s * tau_s) * t;
        }
        let mut v_new = v_old + dv_sf + dv_gcor;

        // Attitude: q_n(k)b(k) = q_n(k)n(k-1) ⊗ q_n(k-1)b(k-1) ⊗ q_b(k-1)b(k).
        let q_nn = quat_from_rotation_vector(&(-zeta));
        let q_bb = quat_from_rotation_vector(phi);
        st.ned_from_body = Quat::new_normalize((q_nn * st.ned_from_body * q_bb).into_inner());

        // Position with trapezoidal velocity.
        let v_avg = 0.5 * (v_old + v_new);
        let lat = st.position.lat_rad + t * v_avg.x / earth.meridian_plus_h_m;
        let lon = st.position.lon_rad + t * v_avg.y / (earth.transverse_plus_h_m * earth.cos_lat);
        let mut h = st.position.height_m - t * v_avg.z;
        match self.config.vertical {
            VerticalChannel::Free => {}
            VerticalChannel::Hold { height_m } => {
                v_new.z = 0.0;
                h = height_m;
            }
            VerticalChannel::Damped { tau_s, .. } => h -= 2.0 / tau_s * h_err * t,
        }
        self.prev_vel_ned_mps = v_old;
        st.vel_ned_mps = v_new;
        st.position = Geodetic {
            lat_rad: lat,
            lon_rad: lon,
            height_m: h,
        };
        st.t_s += t;
    }

    fn vertical_reference(&self, current_m: f64) -> f64 {
        match self.config.vertical {
            VerticalChannel::Free => current_m,
            VerticalChannel::Hold { height_m } | VerticalChannel::Damped { height_m, .. } => {
                height_m
            }
        }
    }

    /// Apply a closed-loop correction: attitude error `phi_ned_rad` (defined by
    /// `C_est = (I - [φ×]) C_true`), velocity error and position error (est - true).
    pub fn correct(&mut self, phi_ned_rad: &Vec3, dvel_ned_mps: &Vec3, dpos: Option<&Geodetic>) {
        let st = &mut self.state;
        st.ned_from_body = quat_from_rotation_vector(phi_ned_rad) * st.ned_from_body;
        st.vel_ned_mps -= dvel_ned_mps;
        self.prev_vel_ned_mps -= dvel_ned_mps;
        if let Some(d) = dpos {
            st.position.lat_rad -= d.lat_rad;
            st.position.lon_rad -= d.lon_rad;
            st.position.height_m -= d.height_m;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Constant rate ω and constant body specific force f: the exact velocity increment in the
    /// body frame at the start of the update is `Σ T^{n+1}/(n+1)! [ω×]^n f`. With the second-order
    /// rotation term the two-sample result is exact to O(T^4); without it, off by ⅙ Θ×(Θ×V).
    #[test]
    fn rotation_compensation_is_exact_to_second_order() {
        let h = 0.005;
        let w = Vec3::new(0.1, -0.05, 0.157); // ~9 deg/s turn
        let f = Vec3::new(1.0, 2.0, -9.8);
        let inc = Increment {
            dtheta_rad: w * h,
            dv_mps: f * h,
        };
        let cfg = StrapdownConfig {
            sample_interval_s: h,
            coning: ConingOrder::TwoSample,
            vertical: VerticalChannel::Free,
        };
        let mut sd = Strapdown::new(
            cfg,
            NavState::at_rest(0.0, Quat::identity(), Geodetic::from_deg(28.0, 113.0, 0.0)),
        );
        sd.buffer[0] = inc;
        sd.buffer[1] = inc;
        let (_, dv) = sd.compensated_increments();
        let t = 2.0 * h;
        let (mut exact, mut term) = (Vec3::zeros(), f * t);
        for n in 1..12 {
            exact += term;
            term = w.cross(&term) * t / (n as f64 + 1.0);
        }
        let theta = w * t;
        let second_order = theta.cross(&theta.cross(&(f * t))) / 6.0;
        let err = (dv - exact).norm();
        assert!(
            err < 1e-3 * second_order.norm(),
            "error {err:e} vs second-order term {:e}",
            second_order.norm()
        );
    }

    /// Uniform rotation at 9 deg/s in a constant specific force, increments by an independent
    /// fine quadrature: the exact start-frame increment is `f T`; the classical terms leave
    /// `(1/6)(ωT)² f_⊥`, the full algorithm third order.
    #[test]
    fn uniform_rotation_in_gravity_is_exact_to_second_order() {
        use nalgebra::Rotation3;
        let w = Vec3::new(1.0, 0.2, -0.1).normalize() * 9f64.to_radians();
        let f0 = Vec3::new(0.3, 2.0, 9.5);
        let h = 0.005;
        let sample = |t0: f64| {
            let n = 2000;
            let dt = h / n as f64;
            let v: Vec3 = (0..n)
                .map(|i| {
                    let t = t0 + (i as f64 + 0.5) * dt;
                    Rotation3::from_scaled_axis(w * t).inverse() * f0 * dt
                })
                .sum();
            Increment {
                dtheta_rad: w * h,
                dv_mps: v,
            }
        };
        let (s1, s2) = (sample(0.0), sample(h));
        let (phi, dv) = compensated_increments(ConingOrder::TwoSample, &[s1, s2], None);
        let exact = f0 * (2.0 * h);
        let err = (dv - exact).norm() / exact.norm();
        assert!(err < 1e-11, "relative error {err:e}");
        assert!((phi - w * 2.0 * h).norm() < 1e-15);
        let (th, v) = (s1.dtheta_rad + s2.dtheta_rad, s1.dv_mps + s2.dv_mps);
        let classical = dv - th.cross(&th.cross(&v)) / 6.0;
        let expected = (w.norm() * 2.0 * h).powi(2) / 6.0
            * (f0 - w.normalize() * w.normalize().dot(&f0)).norm()
            * 2.0
            * h;
        let got = (classical - exact).norm();
        assert!(
            (got / expected - 1.0).abs() < 1e-3,
            "{got:e} vs {expected:e}"
        );
    }
}
