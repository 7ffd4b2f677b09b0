//! Slow sensor noise the noise identification could not resolve, counted as twin noise.
//!
//! An Allan fit over stationary stretches of a few hours bounds a bias random walk (or a
//! Gauss-Markov bias whose correlation time is beyond its longest averaging time) only loosely:
//! the paper IMU's gyro bias instability, 0.0005 deg/h, sits below the angle random walk at
//! every averaging time the stretches reach, yet integrated over a 15 h navigation run it moves
//! the position by several hundred metres. A twin that sets such a term to its point estimate
//! (often zero) is too narrow, and the walk candidate then "explains" what is only noise.
//!
//! When the noise was identified, [`NoiseSpec::unresolved_walk_per_sqrt_s`] holds the 95 %
//! upper bound of the rate random walk of each triad. The catalogue is ranked with the twin as
//! identified; then each of the six bias axes in turn gets the walk intensity that maximises the
//! likelihood of the navigation gap less the leading deterministic candidate's fit (a walk
//! fitted on the gap alone would absorb part of a deterministic effect), clamped to that bound,
//! and the walk's covariance `K² V Vᵀ` joins every run's twin covariance before the catalogue
//! is ranked again: the noise terms the stationary data leave open are estimated from the
//! navigation data, inside the range the stationary data allow (one step of a coordinate ascent
//! of the joint likelihood). A walk beyond the bound stays a candidate.

use crate::error::DiagError;
use crate::localise::GapSeries;
use crate::noise::NoiseSpec;
use crate::problem::{Problem, RunFitData};
use crate::rank::Evaluated;
use crate::walk::fit_walk;
use nalgebra::DVector;
use sins_imu::EffectKind;
use sins_imu::MagnitudeUnit;

/// The walk intensities added to the twin, per bias axis (gyro x, y, z in rad/s/√s, then
/// accelerometer x, y, z in m/s²/√s), and the bounds they were held to.
#[derive(Clone, Debug, PartialEq)]
pub struct UnresolvedWalks {
    /// Intensity added on each of the six bias axes.
    pub intensity_per_sqrt_s: [f64; 6],
    /// The identification's bound `[gyro, accelerometer]`.
    pub bound_per_sqrt_s: [f64; 2],
    /// Axes whose fitted walk failed the whiteness test, with its p-value (nothing added).
    pub refused: Vec<(usize, f64)>,
    /// The leading candidate whose fit was taken off the gap before the walks were fitted.
    pub fitted_without: Option<String>,
}

/// Fit and add the unresolved walks to `data`'s twin covariances (nothing when the noise model
/// was given rather than identified). The walks are fitted on the gap less the `leader`'s fit
/// (its name and its contribution per run, on the fit grid: so that a deterministic effect is
/// not taken for noise), or on the gap itself; the gaps are left as they were. A walk whose
/// smoothed increments fail the whiteness test at `level` (an outlier increment, correlated
/// neighbours, increments tied to turn-on: see [`crate::walk`]) is not noise: it is refused and
/// left to the candidates and the time-local scan.
pub(crate) fn add_unresolved_walks(
    data: &mut [RunFitData],
    noise: &NoiseSpec,
    level: f64,
    leader: Option<(String, Vec<DVector<f64>>)>,
) -> Result<Option<UnresolvedWalks>, DiagError> {
    let Some(bound) = noise.unresolved_walk_per_sqrt_s else {
        return Ok(None);
    };
    let gaps: Vec<DVector<f64>> = data.iter().map(|d| d.gap.clone()).collect();
    if let Some((_, explained)) = &leader {
        for (d, c) in data.iter_mut().zip(explained) {
            d.gap -= c;
        }
    }
    let fitted = fit_walks(data, bound, level);
    for (d, g) in data.iter_mut().zip(gaps) {
        d.gap = g;
    }
    let (intensity, refused) = fitted?;
    Ok(Some(UnresolvedWalks {
        intensity_per_sqrt_s: intensity,
        bound_per_sqrt_s: bound,
        refused,
        fitted_without: leader.map(|(kind, _)| kind),
    }))
}

/// The intensity added on each of the six bias axes, and the refused axes with their p-values.
type FittedWalks = ([f64; 6], Vec<(usize, f64)>);

/// Each bias axis in turn: the walk's intensity fitted on `data`, clamped to its triad's bound
/// and added to the covariances (the stacked problem is rebuilt only after a change); the axes
/// refused by the whiteness test with their p-values.
fn fit_walks(
    data: &mut [RunFitData],
    bound: [f64; 2],
    level: f64,
) -> Result<FittedWalks, DiagError> {
    let mut intensity = [0.0; 6];
    let mut refused = Vec::new();
    let mut problem: Option<Problem> = None;
    for (b, k_out) in intensity.iter_mut().enumerate() {
        let k_max = bound[b / 3];
        if !(k_max > 0.0 && k_max.is_finite()) {
            continue;
        }
        let p = match problem.take() {
            Some(p) => p,
            None => Problem::new(&data.iter().collect::<Vec<_>>())?,
        };
        let fit = fit_walk(&p, &p.walks[b], &p.walk_blocks[b], k_max);
        if let Some(shape) = fit.shape.filter(|s| s.p_value <= level) {
            refused.push((b, shape.p_value));
            problem = Some(p);
            continue;
        }
        let k = fit.intensity.min(k_max);
        if k > 0.0 {
            for d in data.iter_mut() {
                let v = &d.walks[b];
                d.cov += v * v.transpose() * (k * k);
            }
        } else {
            problem = Some(p);
        }
        *k_out = k;
    }
    Ok((intensity, refused))
}

/// The fitted contribution of the leading candidate when it is a passing deterministic one
/// (per run, on the fit grid, m).
pub(crate) fn leader_contribution(
    ranked: &[Evaluated],
    data: &[RunFitData],
) -> Option<(String, Vec<DVector<f64>>)> {
    let leader = ranked.first().filter(|e| e.report.passes)?;
    let (l, rf) = leader.regression.as_ref()?;
    let contributions = data
        .iter()
        .map(|fd| {
            let mut c = DVector::zeros(fd.gap.len());
            for (i, &k) in rf.retained.iter().enumerate() {
                c.axpy(rf.fit.theta[i], &fd.columns.column(l.first + k), 1.0);
            }
            c
        })
        .collect();
    Some((l.kind.name().to_string(), contributions))
}

/// Widen each run's plotted 1-sigma envelope by the walks added to its twin: the walks'
/// position variance `Σ_b K_b² diag(V_b V_bᵀ)` at each fit point, interpolated linearly in
/// variance onto the output grid (held at the first and last fit point's value beyond them).
/// `fit_index[r]` maps run `r`'s fit points into its output grid.
pub(crate) fn widen_envelopes(
    series: &mut [GapSeries],
    data: &[RunFitData],
    fit_index: &[&[usize]],
    walks: &UnresolvedWalks,
) {
    for ((s, fd), index) in series.iter_mut().zip(data).zip(fit_index) {
        let n = fd.points();
        let mut var = vec![[0.0; 2]; n];
        for (b, &k) in walks.intensity_per_sqrt_s.iter().enumerate() {
            let Some(v) = fd.walks.get(b).filter(|_| k > 0.0) else {
                continue;
            };
            for (i, w) in var.iter_mut().enumerate() {
                w[0] += k * k * v.row(2 * i).norm_squared();
                w[1] += k * k * v.row(2 * i + 1).norm_squared();
            }
        }
        if var.iter().all(|w| w == &[0.0, 0.0]) {
            continue;
        }
        for (k, sigma) in s.sigma_m.iter_mut().enumerate() {
            let add = interpolate(index, &var, k);
            for c in 0..2 {
                sigma[c] = (sigma[c] * sigma[c] + add[c]).sqrt();
            }
        }
    }
}

/// `var` (given at output indices `index`, ascending) at output index `k`.
fn interpolate(index: &[usize], var: &[[f64; 2]], k: usize) -> [f64; 2] {
    let after = index.partition_point(|&i| i < k);
    match (after.checked_sub(1), var.get(after)) {
        (_, Some(v)) if index[after] == k => *v,
        (Some(b), Some(a)) => {
            let w = (k - index[b]) as f64 / (index[after] - index[b]) as f64;
            let (vb, va) = (var[b], *a);
            [vb[0] + w * (va[0] - vb[0]), vb[1] + w * (va[1] - vb[1])]
        }
        (None, Some(a)) => *a,
        (Some(b), None) => var[b],
        (None, None) => [0.0; 2],
    }
}

impl UnresolvedWalks {
    /// One line for the diagnosis's notes, in the catalogue's walk units (deg/h/√h, ug/√h).
    pub fn note(&self) -> String {
        let gyro = EffectKind::GyroBiasRandomWalk.unit();
        let accel = EffectKind::AccelBiasRandomWalk.unit();
        let list = |k: &[f64], unit: &MagnitudeUnit| {
            k.iter()
                .map(|&v| format!("{:.2e}", unit.from_si(v)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut line = format!(
            "noise identified from the data: bias random walks the stationary stretches cannot \
             exclude (95 % bounds gyro {:.2e} {}, accelerometer {:.2e} {}) fitted from the \
             navigation gap within those bounds and counted as twin noise: gyro x, y, z {} {}; \
             accelerometer x, y, z {} {}",
            gyro.from_si(self.bound_per_sqrt_s[0]),
            gyro.label,
            accel.from_si(self.bound_per_sqrt_s[1]),
            accel.label,
            list(&self.intensity_per_sqrt_s[..3], &gyro),
            gyro.label,
            list(&self.intensity_per_sqrt_s[3..], &accel),
            accel.label,
        );
        if let Some(kind) = &self.fitted_without {
            line.push_str(&format!(
                " (fitted on the gap less the leading candidate's fit, {kind})"
            ));
        }
        for (b, p) in &self.refused {
            line.push_str(&format!(
                "; {} {}: refused, its increments do not look like a walk's (p = {p:.1e})",
                if *b < 3 { "gyro" } else { "accelerometer" },
                ["x", "y", "z"][b % 3]
            ));
        }
        line
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::test_normals;
    use nalgebra::DMatrix;

    const POINTS: usize = 300;
    const LUMP: usize = 5;

    /// A walk's position factor: lump `j` moves north by 1 and east by 0.3 from point `LUMP j`.
    fn walk_factor() -> DMatrix<f64> {
        DMatrix::from_fn(2 * POINTS, POINTS / LUMP, |r, j| {
            let on = r / 2 >= LUMP * j;
            match (on, r % 2) {
                (false, _) => 0.0,
                (true, 0) => 1.0,
                (true, _) => 0.3,
            }
        })
    }

    /// Two runs: unit white twin noise, a walk of intensity `k` on gyro y (axis 1), and `step`
    /// added to run 0's north gap from its middle on. Only gyro y's walk moves the position (the
    /// other axes' factors are zero, so that the axes can be told apart).
    fn runs(k: f64, step: f64, seed: u64) -> Vec<RunFitData> {
        (0..2)
            .map(|r| {
                let v = walk_factor();
                let w = DVector::from_vec(test_normals(v.ncols(), seed + 10 * r));
                let e = DVector::from_vec(test_normals(2 * POINTS, seed + 10 * r + 1));
                let mut gap = e + &v * w * k;
                if r == 0 {
                    for i in POINTS / 2..POINTS {
                        gap[2 * i] += step;
                    }
                }
                RunFitData {
                    run: format!("run{r}"),
                    gap,
                    cov: DMatrix::identity(2 * POINTS, 2 * POINTS),
                    params: DMatrix::zeros(2 * POINTS, 0),
                    columns: DMatrix::zeros(2 * POINTS, 0),
                    walks: (0..6)
                        .map(|b| if b == 1 { v.clone() } else { v.scale(0.0) })
                        .collect(),
                }
            })
            .collect()
    }

    fn noise(bound: Option<[f64; 2]>) -> NoiseSpec {
        NoiseSpec {
            unresolved_walk_per_sqrt_s: bound,
            ..NoiseSpec::NONE
        }
    }

    #[test]
    fn envelopes_widen_by_the_walks_variance_interpolated_between_fit_points() {
        let data = runs(0.0, 0.0, 1);
        let walks = UnresolvedWalks {
            intensity_per_sqrt_s: [0.0, 2.0, 0.0, 0.0, 0.0, 0.0],
            bound_per_sqrt_s: [10.0, 0.0],
            refused: Vec::new(),
            fitted_without: None,
        };
        // Fit point i at output index 2i: odd outputs lie halfway between two fit points.
        let index: Vec<usize> = (0..POINTS).map(|i| 2 * i).collect();
        let mut series = vec![GapSeries {
            run: "r".into(),
            nav_start_s: 0.0,
            t_s: (0..2 * POINTS).map(|k| k as f64).collect(),
            segment: vec![0; 2 * POINTS],
            gap_m: vec![[0.0; 2]; 2 * POINTS],
            twin_m: vec![[0.0; 2]; 2 * POINTS],
            sigma_m: vec![[3.0, 4.0]; 2 * POINTS],
        }];
        widen_envelopes(&mut series, &data[..1], &[&index], &walks);
        let v = &data[0].walks[1];
        let walk_var = |i: usize, c: usize| 4.0 * v.row(2 * i + c).norm_squared();
        for i in [0, 17, POINTS - 1] {
            let s = series[0].sigma_m[2 * i];
            assert!(
                (s[0] * s[0] - 9.0 - walk_var(i, 0)).abs() < 1e-9,
                "{i}: {s:?}"
            );
            assert!(
                (s[1] * s[1] - 16.0 - walk_var(i, 1)).abs() < 1e-9,
                "{i}: {s:?}"
            );
        }
        let mid = series[0].sigma_m[2 * 17 + 1][0].powi(2) - 9.0;
        assert!((mid - 0.5 * (walk_var(17, 0) + walk_var(18, 0))).abs() < 1e-9);
        let last = series[0].sigma_m[2 * POINTS - 1][0].powi(2) - 9.0;
        assert!((last - walk_var(POINTS - 1, 0)).abs() < 1e-9);
        // The walk grows with time: the envelope at the end is wider than at the start.
        assert!(walk_var(POINTS - 1, 0) > walk_var(1, 0) + 1.0);
    }

    #[test]
    fn a_walk_within_the_bound_is_fitted_and_joins_the_twin() {
        let k_true = 0.5;
        let mut data = runs(k_true, 0.0, 3);
        let u = add_unresolved_walks(&mut data, &noise(Some([10.0, 0.0])), 1e-3, None)
            .expect("fit")
            .expect("identified noise");
        // 120 unit increments: the intensity's relative 1-sigma is about 1/sqrt(2 * 120).
        let k = u.intensity_per_sqrt_s;
        assert!(
            (k[1] - k_true).abs() < 3.0 * k_true / 240f64.sqrt(),
            "{u:?}"
        );
        assert_eq!(&k[3..], &[0.0; 3], "bound 0: nothing on the accelerometers");
        assert!(u.refused.is_empty(), "{u:?}");
        // The covariance grew by exactly K^2 V V^T summed over the axes fitted.
        let v = walk_factor();
        assert_eq!([k[0], k[2]], [0.0; 2], "{u:?}");
        let expect = DMatrix::identity(2 * POINTS, 2 * POINTS) + &v * v.transpose() * k[1].powi(2);
        assert!((&data[1].cov - expect).amax() < 1e-9);
    }

    #[test]
    fn the_walk_is_held_to_the_bound_and_absent_for_a_given_noise_model() {
        let mut data = runs(0.5, 0.0, 3);
        let u = add_unresolved_walks(&mut data, &noise(Some([0.1, 0.0])), 1e-3, None)
            .expect("fit")
            .expect("identified noise");
        assert_eq!(u.intensity_per_sqrt_s[1], 0.1, "{u:?}");
        let mut given = runs(0.5, 0.0, 3);
        assert!(
            add_unresolved_walks(&mut given, &noise(None), 1e-3, None)
                .expect("fit")
                .is_none()
        );
        assert_eq!(given[0].cov, DMatrix::identity(2 * POINTS, 2 * POINTS));
    }

    #[test]
    fn a_step_is_not_taken_for_unresolved_noise() {
        // A 12-sigma step in one run and no walk: a free walk would absorb it; its one outlier
        // increment fails the whiteness test, so the twin is left as it was.
        let mut data = runs(0.0, 12.0, 5);
        let u = add_unresolved_walks(&mut data, &noise(Some([100.0, 0.0])), 1e-3, None)
            .expect("fit")
            .expect("identified noise");
        assert!(
            u.refused.len() == 1 && u.refused[0].0 == 1 && u.refused[0].1 < 1e-3,
            "{u:?}"
        );
        assert_eq!(u.intensity_per_sqrt_s, [0.0; 6], "{u:?}");
        assert_eq!(data[0].cov, DMatrix::identity(2 * POINTS, 2 * POINTS));
    }
}
