//! Linear replica of `sins_nav::SelfAlignment`: how the stationary self-alignment that starts
//! every replay turns a perturbation of the increments into an initial attitude error.
//!
//! The alignment is a deterministic function of the data: a coarse TRIAD on the means of the
//! first `coarse_duration_s`, then a zero-velocity Kalman filter whose gains do not depend on
//! the measurements (its covariance recursion is data-free) and whose estimate is fed back and
//! reset after every update. To first order the navigation error `e = [φ, δv_N, δv_E]` of the
//! aligning strapdown therefore obeys the error dynamics between updates and `e ← (I - K_k H) e`
//! at update `k` (position reset to the site), starting from the coarse error
//! `φ_c = J [mean δf^b; mean δω^b]` with `J` the Jacobian of the TRIAD at the data's own means.
//! This module reproduces the gain sequence exactly (the filter's own Φ, Q, H, R, P0 and
//! covariance step, `sins_nav::alignment::FineFilterModel`, built from
//! `sins_nav::error_model::AlignmentModel`) and the Jacobian by central differences of
//! `sins_nav::alignment::coarse_align`.

use crate::error::DiagError;
use crate::model::{ErrorModel, Mat7, Vec7};
use nalgebra::{Matrix5x2, SMatrix};
use sins_nav::alignment::{AlignmentConfig, FineFilterModel, coarse_align};
use sins_nav::attitude::attitude_error_ned_rad;
use sins_nav::{Geodetic, StrapdownConfig, Vec3};

/// Jacobian of the coarse attitude error φ (rad) with respect to `[mean δf^b (m/s²), mean δω^b
/// (rad/s)]`.
pub type CoarseJacobian = SMatrix<f64, 3, 6>;

/// The alignment's sample counts and its fine-filter gains.
#[derive(Clone, Debug)]
pub struct AlignmentReplica {
    /// Samples of the coarse stage.
    pub n_coarse: usize,
    /// Samples of the whole alignment.
    pub n_total: usize,
    /// Samples between fine-filter updates.
    pub samples_per_update: usize,
    /// Gain `K_k` of each fine update, in order.
    pub gains: Vec<Matrix5x2<f64>>,
    /// Transition of the error model over one update interval.
    pub phi_update: Mat7,
}

impl AlignmentReplica {
    /// Replica of `SelfAlignment::new(config, nav, site, t0)` for data sampled every
    /// `nav.sample_interval_s`.
    pub fn new(
        config: &AlignmentConfig,
        nav: &StrapdownConfig,
        site: &Geodetic,
        model: &ErrorModel,
    ) -> Self {
        let h = nav.sample_interval_s;
        let per = nav.coning.samples_per_update();
        let round_to = |d: f64| (((d / h).round() as usize) / per) * per;
        let n_coarse = round_to(config.coarse_duration_s).max(per);
        let n_total = round_to(config.duration_s);
        let dt = config.update_interval_s;
        let spu = ((dt / h).round() as usize).max(per) / per * per;
        let n_updates = n_total.saturating_sub(n_coarse) / spu;
        Self {
            n_coarse,
            n_total,
            samples_per_update: spu,
            gains: fine_gains(config, site, n_updates),
            phi_update: model.transition(spu as f64 * h),
        }
    }

    /// Closed-loop update `k` applied to a navigation error state (position reset to zero).
    #[inline]
    pub fn update_state(&self, k: usize, x: &mut Vec7) {
        if let Some(kg) = self.gains.get(k) {
            let z = nalgebra::Vector2::new(x[3], x[4]);
            let dx = kg * z;
            for i in 0..5 {
                x[i] -= dx[i];
            }
        }
        x[5] = 0.0;
        x[6] = 0.0;
    }

    /// The closed-loop update `k` as a matrix on the navigation error states.
    pub fn update_matrix(&self, k: usize) -> Mat7 {
        let mut t = Mat7::identity();
        if let Some(kg) = self.gains.get(k) {
            for i in 0..5 {
                t[(i, 3)] -= kg[(i, 0)];
                t[(i, 4)] -= kg[(i, 1)];
            }
        }
        t[(5, 5)] = 0.0;
        t[(6, 6)] = 0.0;
        t
    }

    /// Number of fine updates.
    pub fn n_updates(&self) -> usize {
        self.gains.len()
    }
}

/// The fine filter's gain sequence: `SelfAlignment`'s fine stage's own model and covariance
/// step, run `n_updates` times (a singular innovation covariance gives a zero gain).
fn fine_gains(c: &AlignmentConfig, site: &Geodetic, n_updates: usize) -> Vec<Matrix5x2<f64>> {
    let model = FineFilterModel::new(c, site);
    let mut p = model.p0;
    (0..n_updates)
        .map(|_| {
            model
                .covariance_step(&mut p)
                .unwrap_or_else(Matrix5x2::zeros)
        })
        .collect()
}

/// Jacobian of the coarse alignment's attitude error at the mean specific force `f_body_mps2`
/// and mean rate `w_body_radps` of the coarse window (central differences).
pub fn coarse_jacobian(
    f_body_mps2: &Vec3,
    w_body_radps: &Vec3,
) -> Result<CoarseJacobian, DiagError> {
    let q0 = coarse_align(f_body_mps2, w_body_radps)?;
    let mut j = CoarseJacobian::zeros();
    let step_f = 1e-6 * f_body_mps2.norm();
    let step_w = 1e-4 * w_body_radps.norm();
    for c in 0..6 {
        let (mut fp, mut fm, mut wp, mut wm) =
            (*f_body_mps2, *f_body_mps2, *w_body_radps, *w_body_radps);
        let step = if c < 3 {
            fp[c] += step_f;
            fm[c] -= step_f;
            step_f
        } else {
            wp[c - 3] += step_w;
            wm[c - 3] -= step_w;
            step_w
        };
        let ep = attitude_error_ned_rad(&coarse_align(&fp, &wp)?, &q0);
        let em = attitude_error_ned_rad(&coarse_align(&fm, &wm)?, &q0);
        j.set_column(c, &((ep - em) / (2.0 * step)));
    }
    Ok(j)
}
