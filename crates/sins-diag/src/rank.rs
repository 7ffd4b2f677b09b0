//! Evaluate every candidate on the stacked problem, rank them, and conclude.

use crate::candidates::{RegressionFit, detectable, fit_regression, select};
use crate::input::DiagnoseConfig;
use crate::problem::Problem;
use crate::report::{
    CandidateModel, CandidateReport, ChiSquareTest, ComponentEstimate, Verdict, WhitenessTest,
};
use crate::stats::chi2_sf;
use crate::walk::fit_walk;
use sins_imu::EffectKind;

/// Standard deviation of the plausibility prior on a candidate's magnitude, in multiples of the
/// kind's typical navigation-grade magnitude (`EffectKind::typical_magnitude`): a fit a hundred
/// times larger than typical costs one unit of chi-square, a thousand times larger a hundred.
/// It separates look-alike signatures by physical plausibility (a g-sensitivity of several
/// deg/h/g mimicking a temperature-rate term) and never makes a candidate pass.
pub const PRIOR_TIMES_TYPICAL: f64 = 100.0;

/// The plausibility penalty of a report's retained components.
fn plausibility_penalty(kind: EffectKind, components: &[ComponentEstimate]) -> f64 {
    let sd = PRIOR_TIMES_TYPICAL * kind.typical_magnitude();
    if sd <= 0.0 {
        return 0.0;
    }
    components
        .iter()
        .filter(|c| c.retained)
        .map(|c| (c.value / sd).powi(2))
        .sum()
}

/// Where a deterministic candidate's columns sit in the fit data.
#[derive(Clone, Copy, Debug)]
pub struct Layout {
    /// The kind.
    pub kind: EffectKind,
    /// First column.
    pub first: usize,
    /// Number of components.
    pub n: usize,
}

/// A candidate's evaluation.
pub struct Evaluated {
    /// The kind.
    pub kind: EffectKind,
    /// The report.
    pub report: CandidateReport,
    /// Deterministic candidates: their layout and fit.
    pub regression: Option<(Layout, RegressionFit)>,
}

/// The null distribution of `gᵀ S⁻¹ g`, `scale · χ²(dof)` (Satterthwaite: same mean and
/// variance as the exact quadratic form of a Gaussian, see `Problem::null_moments`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NullDist {
    /// Scale `c = Var / (2 E)`.
    pub scale: f64,
    /// Effective degrees of freedom `ν = 2 E² / Var`.
    pub dof: f64,
}

impl NullDist {
    /// From the mean and variance of the quadratic form.
    pub fn from_moments(mean: f64, var: f64) -> Self {
        if mean > 0.0 && var > 0.0 {
            Self {
                scale: var / (2.0 * mean),
                dof: 2.0 * mean * mean / var,
            }
        } else {
            Self {
                scale: 1.0,
                dof: mean.max(1.0),
            }
        }
    }

    /// Test `chi2` once `removed` parameters have been fitted (reported `dof` is the expected
    /// value of the statistic, `scale × ν`).
    pub fn test(&self, chi2: f64, removed: usize, level: f64) -> ChiSquareTest {
        let nu = (self.dof - removed as f64).max(1.0);
        let p_value = chi2_sf(chi2 / self.scale, nu);
        ChiSquareTest {
            chi2,
            dof: nu * self.scale,
            p_value,
            consistent: p_value > level,
        }
    }
}

/// What every candidate's test shares: the number of data, the chi-square of the twin alone,
/// the number of tests of the Bonferroni correction.
#[derive(Clone, Copy, Debug)]
pub struct TestContext {
    /// Number of data.
    pub n: f64,
    /// `gᵀ S⁻¹ g` of the twin alone.
    pub chi0: f64,
    /// Components and walk axes tested over the catalogue.
    pub n_tests: f64,
}

impl TestContext {
    /// The context of problem `p` for `layouts` and `walks`.
    pub fn new(p: &Problem, layouts: &[Layout], walks: &[(EffectKind, usize)]) -> Self {
        Self {
            n: p.gls.n as f64,
            chi0: p.gls.chi2(),
            n_tests: (layouts.iter().map(|l| l.n).sum::<usize>() + 3 * walks.len()).max(1) as f64,
        }
    }
}

/// The evaluation of deterministic candidate `l` from its fit `rf` (whose `fit.dchi2` is the
/// drop from the twin alone, `ctx.chi0`).
pub fn regression_evaluated(
    l: &Layout,
    rf: RegressionFit,
    ctx: &TestContext,
    null: &NullDist,
    cfg: &DiagnoseConfig,
) -> Evaluated {
    let p_single = cfg.alpha / ctx.n_tests;
    let k = rf.retained.len();
    let dchi2 = rf.fit.dchi2.max(0.0);
    let p_value = (chi2_sf(dchi2, k as f64) * ctx.n_tests).min(1.0);
    let delta_bic = dchi2 - k as f64 * ctx.n.ln();
    let labels = l.kind.component_labels();
    let unit = l.kind.unit();
    let components = (0..l.n)
        .map(|c| {
            let alone = rf.sigma_alone[c];
            let pos = rf.retained.iter().position(|&r| r == c);
            let (value, sigma) = match pos {
                Some(i) => (rf.fit.theta[i], Some(rf.fit.cov[(i, i)].max(0.0).sqrt())),
                None => (0.0, alone.is_finite().then_some(alone)),
            };
            ComponentEstimate {
                label: labels.get(c).copied().unwrap_or("?").to_string(),
                value,
                sigma,
                retained: pos.is_some(),
                detectable: alone.is_finite().then(|| detectable(alone, p_single)),
            }
        })
        .collect();
    Evaluated {
        kind: l.kind,
        report: CandidateReport {
            kind: l.kind.name().to_string(),
            description: l.kind.description().to_string(),
            unit: unit.label.to_string(),
            model: CandidateModel::Regression,
            components,
            dchi2,
            dof: k,
            p_value,
            delta_bic,
            plausibility_penalty: 0.0,
            evidence: 0.0,
            passes: false,
            residual: null.test(ctx.chi0 - dchi2, k, cfg.null_alpha),
            whiteness: None,
            constancy: None,
        },
        regression: Some((*l, rf)),
    }
}

/// Evaluate the deterministic candidates `layouts` and the random-walk `walks` (kind and the
/// bias-axis offset: 0 for the gyros, 3 for the accelerometers), best first.
pub fn evaluate(
    p: &Problem,
    layouts: &[Layout],
    walks: &[(EffectKind, usize)],
    null: &NullDist,
    cfg: &DiagnoseConfig,
) -> Vec<Evaluated> {
    let ctx = TestContext::new(p, layouts, walks);
    let p_single = cfg.alpha / ctx.n_tests;
    let mut out: Vec<Evaluated> = layouts
        .iter()
        .map(|l| {
            regression_evaluated(
                l,
                fit_regression(p, l.first, l.n, cfg.z_keep),
                &ctx,
                null,
                cfg,
            )
        })
        .collect();
    for &(kind, offset) in walks {
        let unit = kind.unit();
        let fits: Vec<_> = (0..3)
            .map(|a| {
                let b = offset + a;
                fit_walk(
                    p,
                    &p.walks[b],
                    &p.walk_blocks[b],
                    kind.typical_magnitude_si(),
                )
            })
            .collect();
        let best = (0..3)
            .max_by(|&a, &b| fits[a].dchi2.total_cmp(&fits[b].dchi2))
            .unwrap_or(0);
        let f = &fits[best];
        let dchi2 = f.dchi2;
        let p_value = (0.5 * chi2_sf(dchi2, 1.0) * ctx.n_tests).min(1.0);
        let delta_bic = dchi2 - ctx.n.ln();
        let labels = kind.component_labels();
        let components = fits
            .iter()
            .enumerate()
            .map(|(a, w)| ComponentEstimate {
                label: labels.get(a).copied().unwrap_or("?").to_string(),
                value: unit.from_si(w.intensity),
                sigma: Some(unit.from_si(w.sigma)),
                retained: a == best && dchi2 > 0.0,
                // The likelihood's one-sigma of the intensity, taken as the resolution of the
                // test near zero (an approximation: the intensity is a variance parameter).
                detectable: (w.sigma.is_finite() && w.sigma > 0.0)
                    .then(|| unit.from_si(detectable(w.sigma, p_single))),
            })
            .collect();
        out.push(Evaluated {
            kind,
            report: CandidateReport {
                kind: kind.name().to_string(),
                description: kind.description().to_string(),
                unit: unit.label.to_string(),
                model: CandidateModel::NoiseTerm,
                components,
                dchi2,
                dof: 1,
                p_value,
                delta_bic,
                plausibility_penalty: 0.0,
                evidence: 0.0,
                passes: false,
                residual: null.test(f.residual_chi2, 1, cfg.null_alpha),
                constancy: None,
                whiteness: f.shape.map(|w| WhitenessTest {
                    max_abs_z: w.max_abs_z,
                    increments: w.increments,
                    lag1_z: w.lag1_z,
                    stationarity_z: w.stationarity_z,
                    aligned_z: w.aligned_z,
                    p_value: w.p_value,
                    consistent: w.p_value > cfg.null_alpha,
                    without_events_dchi2: None,
                }),
            },
            regression: None,
        });
    }
    finish_ranking(&mut out, ctx.n, cfg);
    out
}

/// Evidence, pass flags and order of evaluated candidates (called again after any of them is
/// replaced, e.g. by its nonlinear refinement). Evidence is the chi-square drop over the
/// quasi-likelihood inflation (the best residual's chi-square over its expectation, at least
/// 1), minus the BIC penalty and the plausibility penalty; a candidate passes when its
/// Bonferroni p-value is below `alpha`, its ΔBIC and its evidence are positive, and (noise
/// terms) its increments pass the whiteness test.
pub fn finish_ranking(out: &mut [Evaluated], n: f64, cfg: &DiagnoseConfig) {
    let inflation = out
        .iter()
        .map(|e| e.report.residual.chi2 / e.report.residual.dof.max(1.0))
        .fold(f64::INFINITY, f64::min)
        .max(1.0);
    for e in out.iter_mut() {
        let r = &mut e.report;
        r.plausibility_penalty = plausibility_penalty(e.kind, &r.components);
        r.evidence = r.dchi2 / inflation - r.dof as f64 * n.ln() - r.plausibility_penalty;
        r.passes =
            passes_but_for_shape(r, cfg) && r.whiteness.as_ref().is_none_or(|w| w.consistent);
    }
    out.sort_by(|a, b| {
        b.report
            .passes
            .cmp(&a.report.passes)
            .then(b.report.evidence.total_cmp(&a.report.evidence))
    });
}

/// Whether a report passes every test of [`finish_ranking`] but a noise term's shape test: its
/// Bonferroni p-value below `alpha`, its ΔBIC and its evidence positive.
pub(crate) fn passes_but_for_shape(r: &CandidateReport, cfg: &DiagnoseConfig) -> bool {
    r.p_value < cfg.alpha && r.delta_bic > 0.0 && r.evidence > 0.0
}

/// When the null test finds no significant gap, a candidate named as a cause must also survive
/// the multiplicity of the time-local scan (`scan_tests` more tests): each p-value is corrected
/// over the catalogue's `n_tests` and the scan's together, as the events' are. (A chi-square
/// drop of 10 among a few dozen catalogue tests is not a cause on data the global test calls
/// consistent with the twin.) The ranking is finished again.
pub fn with_scan_multiplicity(
    ranked: &mut [Evaluated],
    ctx: &TestContext,
    scan_tests: usize,
    cfg: &DiagnoseConfig,
) {
    let family = ctx.n_tests + scan_tests as f64;
    for e in ranked.iter_mut() {
        let r = &mut e.report;
        let raw = match r.model {
            CandidateModel::NoiseTerm => 0.5 * chi2_sf(r.dchi2, 1.0),
            _ => chi2_sf(r.dchi2, r.dof.max(1) as f64),
        };
        r.p_value = (raw * family).min(1.0);
    }
    finish_ranking(ranked, ctx.n, cfg);
}

/// Fraction of `a`'s fitted signature that `b`'s columns explain, in the twin's metric.
fn explained(p: &Problem, a: &(Layout, RegressionFit), b: &(Layout, RegressionFit)) -> f64 {
    let sa = select(&p.a, a.0.first, &a.1.retained) * &a.1.fit.theta;
    let sa = nalgebra::DMatrix::from_column_slice(sa.len(), 1, sa.as_slice());
    let norm = p.gls.gram(&sa, &sa)[(0, 0)];
    if norm <= 0.0 {
        return 0.0;
    }
    let fb = p.gls.fit_to(
        &select(&p.a, b.0.first, &(0..b.0.n).collect::<Vec<_>>()),
        &sa,
    );
    fb / norm
}

/// The conclusion from the ranked candidates and the null test.
pub fn verdict(
    p: &Problem,
    ranked: &[Evaluated],
    null: &ChiSquareTest,
    cfg: &DiagnoseConfig,
) -> Verdict {
    let passing: Vec<&Evaluated> = ranked.iter().filter(|e| e.report.passes).collect();
    let Some(best) = passing.first() else {
        return if null.consistent {
            Verdict::NoSignificantGap
        } else {
            Verdict::Unexplained
        };
    };
    if let Some(second) = passing.get(1) {
        let close = best.report.evidence - second.report.evidence < cfg.separability_dchi2;
        let alike = match (&best.regression, &second.regression) {
            (Some(a), Some(b)) => explained(p, a, b).max(explained(p, b, a)) > cfg.separability_r2,
            _ => true,
        };
        if close && alike {
            return Verdict::NotSeparable {
                candidates: vec![best.report.kind.clone(), second.report.kind.clone()],
                time_local: Vec::new(),
            };
        }
    }
    let constant = best.report.constancy.as_ref().is_none_or(|c| c.consistent);
    if best.report.residual.consistent && constant {
        Verdict::Explained {
            by: best.report.kind.clone(),
        }
    } else {
        Verdict::PartlyExplained {
            by: best.report.kind.clone(),
        }
    }
}
