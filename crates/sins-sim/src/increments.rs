//! Exact IMU increments over a sample interval for a turntable at a fixed site:
//! `Δθ = ∫ ω_ib^b dt` with `ω_ib^b = ω_nb^b + C_n^b ω_ie^n`, and `Δv = ∫ f^b dt` with
//! `f^b = C_n^b (−g^n)` (the IMU centre does not move and normal gravity already contains the
//! centrifugal term). Intervals are split at segment boundaries; dwells are integrated in closed
//! form, rotations and vibrations by Gauss-Legendre quadrature on each piece.
//!
//! Phases are computed from each piece's own start time with `trig::reduced_phase` and advanced to
//! the nodes by the angle-addition formulas, so that neither the absolute time (hours) nor the
//! node count perturbs the integrand: the quadrature error is the only approximation.

use crate::error::SimError;
use crate::motion::{MotionTimeline, SegmentKind};
use crate::quadrature::{MAX_NODES, gauss_legendre_unit};
use crate::trig::{reduced_phase, sin_cos, sin_cos_small};
use crate::vibration::{VibrationAxis, vibration_body_rate};
use sins_nav::earth::EarthAt;
use sins_nav::{Geodetic, Vec3};

/// A vector split about a unit axis u: `v = par + perp`, and `u × v`.
#[derive(Clone, Copy, Debug)]
struct AxisSplit {
    par: Vec3,
    perp: Vec3,
    cross: Vec3,
}

impl AxisSplit {
    fn new(axis: &Vec3, v: &Vec3) -> Self {
        let par = axis * axis.dot(v);
        Self {
            par,
            perp: v - par,
            cross: axis.cross(v),
        }
    }

    /// `exp(−[u×] φ) v` given `(sin φ, cos φ)`.
    #[inline]
    fn rotate_back(&self, s: f64, c: f64) -> Vec3 {
        self.par + self.perp * c - self.cross * s
    }
}

#[derive(Clone, Debug)]
enum PieceKind {
    Dwell,
    Rotate {
        omega_nb_body_radps: Vec3,
        rate_radps: f64,
        earth: AxisSplit,
        force: AxisSplit,
    },
    Vibrate(Box<VibrationPiece>),
}

/// Vibration channels and their precomputed node phase offsets.
#[derive(Clone, Debug)]
struct VibrationPiece {
    axes: [VibrationAxis; 3],
    /// `(sin, cos)` of `ω_j u_i h_nominal` for node i and axis j.
    nominal_offsets: [[(f64, f64); 3]; MAX_NODES],
    /// Every Euler angle stays within ±π/4 (|θ| <= 2|A|), so no argument reduction is needed.
    small_angles: bool,
}

/// One segment as the integrator sees it.
#[derive(Clone, Debug)]
struct Piece {
    start_s: f64,
    end_s: f64,
    /// `C_n^b(start) ω_ie^n` (rad/s).
    earth_rate_body_radps: Vec3,
    /// `C_n^b(start) (−g^n)` (m/s^2).
    specific_force_body_mps2: Vec3,
    kind: PieceKind,
}

/// Computes exact angular and velocity increments over arbitrary intervals of a
/// [`MotionTimeline`] at a fixed site.
#[derive(Clone, Debug)]
pub struct IncrementIntegrator {
    /// A dwell before t = 0, the timeline's segments, and a dwell after the end.
    pieces: Vec<Piece>,
    rule: &'static [(f64, f64)],
    nominal_interval_s: f64,
    /// The widest instruction set of this CPU, detected once: the vibration quadrature is
    /// compiled for it (the same IEEE operations in the same order, so the same bits).
    arch: pulp::Arch,
}

/// `Rz(θ)ᵀ v`, `Ry(θ)ᵀ v`, `Rx(θ)ᵀ v` given `(sin θ, cos θ)`.
#[inline]
fn rz_t(v: Vec3, (s, c): (f64, f64)) -> Vec3 {
    Vec3::new(c * v.x + s * v.y, c * v.y - s * v.x, v.z)
}
#[inline]
fn ry_t(v: Vec3, (s, c): (f64, f64)) -> Vec3 {
    Vec3::new(c * v.x - s * v.z, v.y, s * v.x + c * v.z)
}
#[inline]
fn rx_t(v: Vec3, (s, c): (f64, f64)) -> Vec3 {
    Vec3::new(v.x, c * v.y + s * v.z, c * v.z - s * v.y)
}

impl IncrementIntegrator {
    /// Integrator for `timeline` at `site` with `quadrature_nodes` (1..=8) Gauss-Legendre nodes
    /// per piece. `nominal_interval_s` is the usual interval length (the sample interval); pieces
    /// of that length reuse precomputed node phases, others are computed directly.
    pub fn new(
        timeline: &MotionTimeline,
        site: &Geodetic,
        quadrature_nodes: usize,
        nominal_interval_s: f64,
    ) -> Result<Self, SimError> {
        let rule = gauss_legendre_unit(quadrature_nodes).ok_or_else(|| SimError::Field {
            field: "quadrature_nodes",
            reason: format!("must be in 1..=8, got {quadrature_nodes}"),
        })?;
        if !(nominal_interval_s.is_finite() && nominal_interval_s > 0.0) {
            return Err(SimError::Field {
                field: "rate_hz",
                reason: format!("gives a sample interval of {nominal_interval_s} s"),
            });
        }
        let earth = EarthAt::new(site.lat_rad, site.height_m);
        let omega_ie_ned = earth.earth_rate_ned_radps;
        let minus_g_ned = -earth.gravity_ned_mps2();
        let hold = |start_s: f64, end_s: f64, c: &sins_nav::Mat3| Piece {
            start_s,
            end_s,
            earth_rate_body_radps: c.transpose() * omega_ie_ned,
            specific_force_body_mps2: c.transpose() * minus_g_ned,
            kind: PieceKind::Dwell,
        };
        let segs = timeline.segments();
        let mut pieces = Vec::with_capacity(segs.len() + 2);
        pieces.push(hold(
            f64::NEG_INFINITY,
            0.0,
            &segs[0].start_ned_from_body_mat,
        ));
        for seg in segs {
            let mut piece = hold(seg.start_s, seg.end_s, &seg.start_ned_from_body_mat);
            piece.kind = match &seg.kind {
                SegmentKind::Dwell => PieceKind::Dwell,
                SegmentKind::Rotate {
                    axis_body,
                    rate_radps,
                    ..
                } => PieceKind::Rotate {
                    omega_nb_body_radps: axis_body * *rate_radps,
                    rate_radps: *rate_radps,
                    earth: AxisSplit::new(axis_body, &piece.earth_rate_body_radps),
                    force: AxisSplit::new(axis_body, &piece.specific_force_body_mps2),
                },
                SegmentKind::Vibrate { axes } => {
                    let mut nominal_offsets = [[(0.0, 1.0); 3]; MAX_NODES];
                    for (row, &(u, _)) in nominal_offsets.iter_mut().zip(rule) {
                        for (sc, a) in row.iter_mut().zip(axes) {
                            *sc = (a.omega_radps * (u * nominal_interval_s)).sin_cos();
                        }
                    }
                    let max_amp = axes.iter().map(|a| a.amp_rad.abs()).fold(0.0, f64::max);
                    PieceKind::Vibrate(Box::new(VibrationPiece {
                        axes: *axes,
                        nominal_offsets,
                        small_angles: 2.0 * max_amp <= std::f64::consts::FRAC_PI_4,
                    }))
                }
            };
            pieces.push(piece);
        }
        let end = timeline
            .end_ned_from_body()
            .to_rotation_matrix()
            .into_inner();
        pieces.push(hold(timeline.total_duration_s(), f64::INFINITY, &end));
        Ok(Self {
            pieces,
            rule,
            nominal_interval_s,
            arch: pulp::Arch::new(),
        })
    }

    /// Number of quadrature nodes per piece.
    pub fn quadrature_nodes(&self) -> usize {
        self.rule.len()
    }

    /// `(Δθ (rad), Δv (m/s))` in body axes over `(t0_s, t1_s]`, `t0_s <= t1_s`. Before t = 0 and
    /// after the end of the program the attitude is held.
    pub fn increments(&self, t0_s: f64, t1_s: f64) -> (Vec3, Vec3) {
        let mut cursor = self.pieces.partition_point(|p| p.end_s <= t0_s);
        self.increments_from(t0_s, t1_s, &mut cursor)
    }

    /// As [`Self::increments`], starting the segment search at `*cursor` (an index into the
    /// internal piece list, 0 initially) and leaving it at the piece containing `t1_s`; for
    /// intervals visited in increasing time order this costs O(1) per interval.
    pub(crate) fn increments_from(&self, t0_s: f64, t1_s: f64, cursor: &mut usize) -> (Vec3, Vec3) {
        let last = self.pieces.len() - 1;
        while *cursor > 0 && self.pieces[*cursor].start_s > t0_s {
            *cursor -= 1;
        }
        while *cursor < last && self.pieces[*cursor].end_s <= t0_s {
            *cursor += 1;
        }
        let mut dtheta = Vec3::zeros();
        let mut dv = Vec3::zeros();
        let mut a = t0_s;
        loop {
            let piece = &self.pieces[*cursor];
            let b = t1_s.min(piece.end_s);
            if b > a {
                let (th, v) = self.integrate_piece(piece, a - piece.start_s, b - a);
                dtheta += th;
                dv += v;
            }
            if t1_s <= piece.end_s || *cursor == last {
                break;
            }
            a = piece.end_s;
            *cursor += 1;
        }
        (dtheta, dv)
    }

    /// Increments over `[start + tau_s, start + tau_s + len_s]` inside one piece.
    #[inline]
    fn integrate_piece(&self, piece: &Piece, tau_s: f64, len_s: f64) -> (Vec3, Vec3) {
        let e = piece.earth_rate_body_radps;
        let g = piece.specific_force_body_mps2;
        match &piece.kind {
            PieceKind::Dwell => (e * len_s, g * len_s),
            PieceKind::Rotate {
                omega_nb_body_radps,
                rate_radps,
                earth,
                force,
            } => {
                let (sa, ca) = sin_cos(reduced_phase(*rate_radps, tau_s, 0.0));
                let mut se = Vec3::zeros();
                let mut sg = Vec3::zeros();
                for &(u, w) in self.rule {
                    let (sd, cd) = sin_cos(rate_radps * (u * len_s));
                    let (s, c) = (sa * cd + ca * sd, ca * cd - sa * sd);
                    se += earth.rotate_back(s, c) * w;
                    sg += force.rotate_back(s, c) * w;
                }
                ((omega_nb_body_radps + se) * len_s, sg * len_s)
            }
            PieceKind::Vibrate(v) => self.arch.dispatch(VibrationQuadrature {
                integrator: self,
                piece: v,
                e,
                g,
                tau_s,
                len_s,
            }),
        }
    }

    /// Quadrature of the vibration integrands over `[tau_s, tau_s + len_s]` of the segment.
    #[inline(always)]
    fn integrate_vibration(
        &self,
        piece: &VibrationPiece,
        e: Vec3,
        g: Vec3,
        tau_s: f64,
        len_s: f64,
    ) -> (Vec3, Vec3) {
        let axes = &piece.axes;
        let nominal_offsets = &piece.nominal_offsets;
        let mut anchor = [(0.0, 1.0); 3];
        for (sc, a) in anchor.iter_mut().zip(axes) {
            *sc = sin_cos(reduced_phase(a.omega_radps, tau_s, a.phase_rad));
        }
        let dlen = len_s - self.nominal_interval_s;
        let n = self.rule.len();
        // Euler angles and rates at every node (index 3 i + j for node i, axis j).
        let mut theta = [0.0; 3 * MAX_NODES];
        let mut rate = [0.0; 3 * MAX_NODES];
        for (i, &(u, _)) in self.rule.iter().enumerate() {
            for (j, a) in axes.iter().enumerate() {
                let eps = a.omega_radps * (u * dlen);
                let (sd, cd) = if eps.abs() <= 1e-6 {
                    // sin/cos of ω u (h + dlen) from those of ω u h; error below ε³/6 < 2e-19.
                    let (s0, c0) = nominal_offsets[i][j];
                    let h2 = 0.5 * eps * eps;
                    (s0 - s0 * h2 + c0 * eps, c0 - c0 * h2 - s0 * eps)
                } else {
                    sin_cos(a.omega_radps * (u * len_s))
                };
                let (sa, ca) = anchor[j];
                let s = sa * cd + ca * sd;
                let c = ca * cd - sa * sd;
                theta[3 * i + j] = a.amp_rad * s - a.offset_rad;
                rate[3 * i + j] = a.amp_rad * a.omega_radps * c;
            }
        }
        // Their sines and cosines, in one independent batch.
        let mut sin_t = [0.0; 3 * MAX_NODES];
        let mut cos_t = [0.0; 3 * MAX_NODES];
        if piece.small_angles {
            for k in 0..3 * n {
                (sin_t[k], cos_t[k]) = sin_cos_small(theta[k]);
            }
        } else {
            for k in 0..3 * n {
                (sin_t[k], cos_t[k]) = sin_cos(theta[k]);
            }
        }
        let mut sw = Vec3::zeros();
        let mut sg = Vec3::zeros();
        for (i, &(_, w)) in self.rule.iter().enumerate() {
            let k = 3 * i;
            let scx = (sin_t[k], cos_t[k]);
            let scy = (sin_t[k + 1], cos_t[k + 1]);
            let scz = (sin_t[k + 2], cos_t[k + 2]);
            let omega_nb = vibration_body_rate(scx, scy, [rate[k], rate[k + 1], rate[k + 2]]);
            let e_b = rx_t(ry_t(rz_t(e, scz), scy), scx);
            let g_b = rx_t(ry_t(rz_t(g, scz), scy), scx);
            sw += (omega_nb + e_b) * w;
            sg += g_b * w;
        }
        (sw * len_s, sg * len_s)
    }
}

/// [`IncrementIntegrator::integrate_vibration`] as an operation that pulp compiles for the
/// CPU's instruction set (AVX2 where there is one: the compiler may then use wider vectors for
/// the independent node and axis loops).
struct VibrationQuadrature<'a> {
    integrator: &'a IncrementIntegrator,
    piece: &'a VibrationPiece,
    e: Vec3,
    g: Vec3,
    tau_s: f64,
    len_s: f64,
}

impl pulp::WithSimd for VibrationQuadrature<'_> {
    type Output = (Vec3, Vec3);

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> (Vec3, Vec3) {
        self.integrator
            .integrate_vibration(self.piece, self.e, self.g, self.tau_s, self.len_s)
    }
}
