//! Time-local rivals of a catalogue verdict. Before a catalogue effect is named, the gap of the
//! twin alone is fitted with time courses outside the catalogue: steps, ramps and transients
//! with a free onset, turn-on transients and oscillations from the start of navigation, on
//! any of the six channels, in one run or common to every run (one time course on every run's
//! time axis, as an effect of the chamber's history would be); pulses and ramps to a plateau
//! of the scan's durations. Signals are taken greedily, strongest first, while each is
//! significant against the Bonferroni threshold of the whole family (`alpha` of the event
//! scan), up to [`MAX_RIVAL_SIGNALS`]; other durations and slow oscillations are fitted as two
//! or more of them.
//!
//! The two explanations are then tested on top of each other (nested models, joint fits on
//! the stacked whitened runs):
//! - the leader is *needed* beside the rivals when its chi-square gain over them is
//!   significant with the Bonferroni factor of the catalogue's and the rivals' tests together
//!   and exceeds its BIC penalty `k ln n`;
//! - the rivals are needed beside the leader when one of them keeps a gain above the family's
//!   threshold with the leader and the others fitted, and together they exceed their BIC
//!   penalty (two parameters a signal, three for a transient with a free onset);
//! - leader needed, rivals not: the verdict stands; both: an "explained" becomes "partly
//!   explained" and the rivals are cited; rivals only: the catalogue gets no credit
//!   ("unexplained", the rivals cited); neither: the leader stands if its BIC beats the
//!   rivals' by `separability_dchi2` (it explains the same with fewer parameters), else
//!   "not separable", naming both.
//!
//! A random-walk leader fits any time course more freely: it is kept beside the rivals only
//! when it still passes on the gap less their joint fit.

use crate::error::DiagError;
use crate::events::{AXES, EventScanConfig, EventSignal, Prepared, Shape, signals_per_axis};
use crate::input::DiagnoseConfig;
use crate::parallel::par_map;
use crate::problem::RunFitData;
use crate::rank::{Evaluated, Layout, NullDist, evaluate};
use crate::report::{Note, NoteKind, TimeCourseAlternative, Verdict};
use crate::stacked::Stacked;
use crate::stats::chi2_isf;
use crate::timelocal::without_events;
use crate::whiten::Nuisance;
use nalgebra::{DMatrix, DVector};
use sins_imu::EffectKind;

/// Signals the rival fit takes at most.
pub const MAX_RIVAL_SIGNALS: usize = 10;

/// Periods of the oscillations tried (s): 1 to 6 h, the scale of a chamber's fluctuations.
pub const OSCILLATION_PERIODS_S: [f64; 6] = [3600.0, 5400.0, 7200.0, 10800.0, 14400.0, 21600.0];

/// The form of a rival signal.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Form {
    /// A shape of the event scan.
    Event(Shape),
    /// `sin` or `cos` of `2π t / period` from the start of navigation.
    Sine { period_s: f64, cosine: bool },
}

/// One signal of the family: axis, form, onset index, run (`None`: every run).
#[derive(Clone, Copy, Debug)]
struct Pick {
    axis: usize,
    form: Form,
    m: usize,
    run: Option<usize>,
    t: f64,
}

/// Visit every signal of one axis of a run: the scan's shapes, then the oscillations.
fn visit_axis(
    p: &Prepared,
    axis: usize,
    cfg: &EventScanConfig,
    f: &mut dyn FnMut(Form, usize, &DVector<f64>),
) {
    let ax = &p.axes[axis];
    ax.visit(&p.onset_s, p.start_s, cfg, &mut |shape, m, sig| {
        f(Form::Event(shape), m, sig)
    });
    let k = p.onset_s.len();
    if k == 0 {
        return;
    }
    for period_s in OSCILLATION_PERIODS_S {
        for cosine in [false, true] {
            // The bias profile as a staircase of steps at the onsets.
            let w = 2.0 * std::f64::consts::PI / period_s;
            let value = |m: usize| {
                let t = p.onset_s[m] - p.onset_s[0];
                if cosine { (w * t).cos() } else { (w * t).sin() }
            };
            let weights =
                DVector::from_fn(k, |m, _| value(m) - if m > 0 { value(m - 1) } else { 0.0 });
            f(Form::Sine { period_s, cosine }, 0, &(&ax.steps * weights));
        }
    }
}

/// The index of every form in the stats table, worked out once per fill (the visit hands out
/// every signal of every run, so nothing here may allocate per signal).
struct Forms<'a> {
    taus: &'a [f64],
    pulses: Vec<usize>,
    rises: Vec<usize>,
    dt: f64,
}

impl<'a> Forms<'a> {
    fn new(cfg: &'a EventScanConfig) -> Self {
        Self {
            taus: &cfg.time_constants_s,
            pulses: cfg.pulse_steps(),
            rises: cfg.plateau_steps(),
            dt: cfg.onset_every_s.max(1) as f64,
        }
    }

    /// The forms of the event scan's shapes (steps, ramps, transients and turn-on
    /// transients, pulses, plateaus); the oscillations come after them.
    fn events(&self) -> usize {
        2 + 2 * self.taus.len() + self.pulses.len() + self.rises.len()
    }

    /// Every form, oscillations included.
    fn count(&self) -> usize {
        self.events() + 2 * OSCILLATION_PERIODS_S.len()
    }

    /// Index of `form`.
    fn index(&self, form: Form) -> usize {
        let n = self.taus.len();
        let grid = |steps: &[usize], t: f64| {
            let k = (t / self.dt).round() as usize;
            steps.iter().position(|&s| s == k).unwrap_or(0)
        };
        match form {
            Form::Event(Shape::Step) => 0,
            Form::Event(Shape::Ramp) => 1,
            Form::Event(Shape::Transient { tau_s, turn_on }) => {
                let i = self.taus.iter().position(|&x| x == tau_s).unwrap_or(0);
                2 + i + if turn_on { n } else { 0 }
            }
            Form::Event(Shape::Pulse { duration_s }) => 2 + 2 * n + grid(&self.pulses, duration_s),
            Form::Event(Shape::Plateau { rise_s }) => {
                2 + 2 * n + self.pulses.len() + grid(&self.rises, rise_s)
            }
            Form::Sine { period_s, cosine } => {
                let j = OSCILLATION_PERIODS_S
                    .iter()
                    .position(|&x| x == period_s)
                    .unwrap_or(0);
                self.events() + 2 * j + usize::from(cosine)
            }
        }
    }
}

/// Per run and signal: `sᵀr`, `sᵀs` and `sᵀq_j` for the current nuisance directions.
struct Table {
    keys: usize,
    stride: usize,
    kmax: usize,
    forms: usize,
    /// One slab per run, `keys × stride`; `NaN` where the run has no such signal.
    runs: Vec<Vec<f64>>,
    /// The form of every form index.
    form_of: Vec<Option<Form>>,
}

impl Table {
    fn key(&self, axis: usize, form: usize, m: usize) -> usize {
        (axis * self.forms + form) * self.kmax + m
    }
}

/// The table of every run's signals against the residual `r` and the nuisance directions
/// `q`, one job per run and axis on up to `threads` threads (each fills its own part of its
/// run's slab: the table does not depend on the thread count).
fn fill(
    st: &Stacked,
    q: &[DVector<f64>],
    r: &DVector<f64>,
    cfg: &EventScanConfig,
    threads: usize,
) -> Result<Table, DiagError> {
    let index = Forms::new(cfg);
    let forms = index.count();
    let kmax = st
        .runs
        .iter()
        .map(|p| p.onset_s.len())
        .max()
        .unwrap_or(0)
        .max(1);
    let stride = 2 + q.len();
    let keys = 6 * forms * kmax;
    let blocks: Vec<(DVector<f64>, Vec<DVector<f64>>)> = (0..st.runs.len())
        .map(|ri| (st.block(ri, r), q.iter().map(|v| st.block(ri, v)).collect()))
        .collect();
    let mut slabs: Vec<Vec<f64>> = st
        .runs
        .iter()
        .map(|_| vec![f64::NAN; keys * stride])
        .collect();
    // An axis's keys are contiguous: (axis · forms + form) · kmax + onset.
    let jobs: Vec<(usize, usize, &mut [f64])> = slabs
        .iter_mut()
        .enumerate()
        .flat_map(|(ri, slab)| {
            slab.chunks_mut(forms * kmax * stride)
                .enumerate()
                .map(move |(axis, part)| (ri, axis, part))
        })
        .collect();
    let seen = par_map(jobs, threads, |(ri, axis, part)| {
        let (rb, qb) = &blocks[ri];
        let mut seen = vec![None; forms];
        visit_axis(&st.runs[ri], axis, cfg, &mut |form, m, sig| {
            let fi = index.index(form);
            seen[fi] = Some(form);
            let k = fi * kmax + m;
            let e = &mut part[k * stride..(k + 1) * stride];
            e[0] = sig.dot(rb);
            e[1] = sig.dot(sig);
            for (j, v) in qb.iter().enumerate() {
                e[2 + j] = sig.dot(v);
            }
        });
        seen
    })?;
    let mut form_of = vec![None; forms];
    for job in seen {
        for (f, s) in form_of.iter_mut().zip(job) {
            if s.is_some() {
                *f = s;
            }
        }
    }
    Ok(Table {
        keys,
        stride,
        kmax,
        forms,
        runs: slabs,
        form_of,
    })
}

/// The strongest signal of the family (per run and common to every run).
fn strongest(t: &Table, common_onsets: usize) -> Option<Pick> {
    let mut best: Option<Pick> = None;
    let mut consider = |p: Pick| {
        if p.t.is_finite() && best.is_none_or(|b| p.t > b.t) {
            best = Some(p);
        }
    };
    let nq = t.stride - 2;
    for axis in 0..6 {
        for fi in 0..t.forms {
            let Some(form) = t.form_of[fi] else { continue };
            for m in 0..t.kmax {
                let k = t.key(axis, fi, m);
                let (mut a_sum, mut n_sum, mut c_sum, mut all) = (0.0, 0.0, vec![0.0; nq], true);
                for (ri, slab) in t.runs.iter().enumerate() {
                    let e = &slab[k * t.stride..(k + 1) * t.stride];
                    if e[1].is_nan() {
                        all = false;
                        continue;
                    }
                    let b = e[1] - e[2..].iter().map(|c| c * c).sum::<f64>();
                    if b > 0.0 {
                        consider(Pick {
                            axis,
                            form,
                            m,
                            run: Some(ri),
                            t: e[0] * e[0] / b,
                        });
                    }
                    a_sum += e[0];
                    n_sum += e[1];
                    for (s, c) in c_sum.iter_mut().zip(&e[2..]) {
                        *s += c;
                    }
                }
                let b = n_sum - c_sum.iter().map(|c| c * c).sum::<f64>();
                if all && t.runs.len() > 1 && m < common_onsets.max(1) && b > 0.0 {
                    consider(Pick {
                        axis,
                        form,
                        m,
                        run: None,
                        t: a_sum * a_sum / b,
                    });
                }
            }
        }
    }
    debug_assert!(t.keys > 0);
    best
}

/// The stacked whitened signal of `pick`.
fn signal(st: &Stacked, pick: &Pick, cfg: &EventScanConfig) -> DVector<f64> {
    let mut out = DVector::zeros(st.rows);
    for (ri, p) in st.runs.iter().enumerate() {
        if pick.run.is_some_and(|r| r != ri) {
            continue;
        }
        visit_axis(p, pick.axis, cfg, &mut |form, m, sig| {
            if form == pick.form && m == pick.m {
                out.rows_mut(st.offsets[ri], sig.len()).copy_from(sig);
            }
        });
    }
    out
}

/// Signals in the family: every run's and the common ones.
fn family(st: &Stacked, cfg: &EventScanConfig) -> usize {
    let per = |k: usize| 6 * (signals_per_axis(k, cfg) + 2 * OSCILLATION_PERIODS_S.len());
    let runs: usize = st.runs.iter().map(|p| per(p.onset_s.len())).sum();
    runs + if st.runs.len() > 1 {
        per(st.common_onsets)
    } else {
        0
    }
}

/// The rival fit of the twin's gap.
pub(crate) struct RivalFit {
    /// The signals, in the order taken, with their joint sizes.
    pub alternatives: Vec<TimeCourseAlternative>,
    /// Their joint fitted contribution to each run's gap (unwhitened).
    pub contributions: Vec<EventSignal>,
    /// Stacked whitened signals.
    signals: Vec<DVector<f64>>,
    /// The family's Bonferroni threshold on `T`.
    pub threshold_chi2: f64,
    /// Signals in the family.
    pub tests: usize,
}

/// Fit the rivals to the stacked residual of `st` (the gap of the twin alone).
pub(crate) fn fit_rivals(
    st: &Stacked,
    cfg: &EventScanConfig,
    threads: usize,
) -> Result<RivalFit, DiagError> {
    let tests = family(st, cfg);
    let thr = chi2_isf(cfg.alpha / tests.max(1) as f64, 1.0);
    let r0 = st.residual();
    let mut nuis = Nuisance::new(r0.clone());
    let mut picks: Vec<(Pick, DVector<f64>)> = Vec::new();
    while picks.len() < MAX_RIVAL_SIGNALS {
        let table = fill(st, &nuis.q, &nuis.r, cfg, threads)?;
        let Some(best) = strongest(&table, st.common_onsets) else {
            break;
        };
        if best.t < thr {
            break;
        }
        let s = signal(st, &best, cfg);
        nuis.add(&s);
        picks.push((best, s));
    }
    let k = picks.len();
    let s = DMatrix::from_fn(st.rows, k, |i, j| picks[j].1[i]);
    let theta = (s.transpose() * &s)
        .cholesky()
        .map(|c| c.solve(&(s.transpose() * &r0)))
        .unwrap_or_else(|| DVector::zeros(k));
    let fitted = &s * &theta;
    let contributions = (0..st.runs.len())
        .map(|ri| EventSignal {
            run: ri,
            contribution: st.runs[ri].whitener.colour(&st.block(ri, &fitted)),
        })
        .collect();
    let alternatives = picks
        .iter()
        .zip(theta.iter())
        .map(|((p, _), &size)| describe(st, p, size))
        .collect();
    Ok(RivalFit {
        alternatives,
        contributions,
        signals: picks.into_iter().map(|(_, s)| s).collect(),
        threshold_chi2: thr,
        tests,
    })
}

fn describe(st: &Stacked, p: &Pick, size_si: f64) -> TimeCourseAlternative {
    let run0 = &st.runs[p.run.unwrap_or(0)];
    let gyro = p.axis < 3;
    let (kind, shape, onset_s, time_s) = match p.form {
        Form::Event(shape) => (
            shape.kind(p.axis).name().to_string(),
            shape.label().to_string(),
            match shape {
                Shape::Transient { turn_on: true, .. } => run0.start_s,
                _ => run0.onset_s[p.m],
            },
            shape.tau_s().or(shape.duration_s()),
        ),
        Form::Sine { period_s, cosine } => (
            if gyro {
                "gyro_bias_oscillation"
            } else {
                "accel_bias_oscillation"
            }
            .to_string(),
            if cosine {
                "oscillation (cosine)"
            } else {
                "oscillation (sine)"
            }
            .to_string(),
            run0.onset_s[0],
            Some(period_s),
        ),
    };
    let unit_kind = match p.form {
        Form::Event(shape) => shape.kind(p.axis),
        Form::Sine { .. } => Shape::Step.kind(p.axis),
    };
    let unit = unit_kind.unit();
    TimeCourseAlternative {
        kind,
        channel: AXES[p.axis].to_string(),
        runs: p
            .run
            .map_or("all runs".to_string(), |r| st.runs[r].run.clone()),
        shape,
        onset_s,
        time_s,
        size: unit.from_si(size_si),
        unit: unit.label.to_string(),
        dchi2: p.t,
    }
}

/// What the nested tests conclude.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Judgement {
    /// The catalogue leader is needed beside the rivals, and they are not needed beside it.
    CatalogueSurvives,
    /// Both are needed: the leader explains part of the gap, a time course the rest.
    BothNeeded,
    /// The leader is not needed beside the rivals, and they are needed beside it.
    RivalsExplain,
    /// Neither is needed beside the other: they explain the same part of the gap.
    NotSeparable,
}

/// What the judgement reads of the diagnosis.
pub(crate) struct JudgeScope<'a> {
    /// Fit data, one per run.
    pub data: &'a [RunFitData],
    /// Deterministic candidates.
    pub layouts: &'a [Layout],
    /// Random-walk candidates.
    pub walks: &'a [(EffectKind, usize)],
    /// The floor's variance.
    pub floor_var: f64,
    /// Tests of the catalogue (its Bonferroni factor).
    pub n_tests: f64,
    /// The calibration run's events through the coefficients (taken off the gap).
    pub absorbed: &'a [EventSignal],
}

/// Parameters of a rival signal: its size and its shape's free parameters (an onset, a time
/// constant or a period).
fn parameters(a: &TimeCourseAlternative) -> f64 {
    match a.shape.as_str() {
        "transient" => 3.0,
        _ => 2.0,
    }
}

/// `|r|²` less the residual's after projecting out `columns`.
fn drop(r0: &DVector<f64>, columns: &[&DVector<f64>]) -> f64 {
    let mut n = Nuisance::new(r0.clone());
    for c in columns {
        n.add(c);
    }
    r0.norm_squared() - n.r.norm_squared()
}

/// Test the catalogue leader and the rivals on top of each other (see the module docs).
pub(crate) fn judge(
    st: &Stacked,
    fit: &RivalFit,
    leader: &Evaluated,
    sc: &JudgeScope<'_>,
    cfg: &DiagnoseConfig,
) -> Result<Judgement, DiagError> {
    if fit.alternatives.is_empty() {
        return Ok(Judgement::CatalogueSurvives);
    }
    let Some((l, rf)) = leader.regression.as_ref() else {
        // A walk fits any time course more freely: it is needed only if it still passes on
        // the gap less the rivals' joint fit; otherwise the rivals took its evidence.
        let p2 = without_events(sc.data, fit.contributions.iter().chain(sc.absorbed))?;
        let (mean, var) = p2.null_moments(sc.floor_var);
        let again = evaluate(
            &p2,
            sc.layouts,
            sc.walks,
            &NullDist::from_moments(mean, var),
            cfg,
        );
        let kept = again
            .iter()
            .any(|e| e.kind == leader.kind && e.report.passes);
        return Ok(if kept {
            Judgement::BothNeeded
        } else {
            Judgement::RivalsExplain
        });
    };
    let columns: Vec<DVector<f64>> = rf
        .retained
        .iter()
        .map(|&c| {
            let mut v = DVector::zeros(st.rows);
            for (ri, p) in st.runs.iter().enumerate() {
                let col = sc.data[ri].columns.column(l.first + c).into_owned();
                v.rows_mut(st.offsets[ri], col.len())
                    .copy_from(&p.whitener.whiten_vec(&col));
            }
            v
        })
        .collect();
    let r0 = st.residual();
    let rivals: Vec<&DVector<f64>> = fit.signals.iter().collect();
    let both: Vec<&DVector<f64>> = rivals.iter().copied().chain(columns.iter()).collect();
    let (d_r, d_cr) = (drop(&r0, &rivals), drop(&r0, &both));
    let d_c = drop(&r0, &columns.iter().collect::<Vec<_>>());
    let ln_n = (st.rows as f64).ln();
    let (k_c, k_r) = (
        columns.len() as f64,
        fit.alternatives.iter().map(parameters).sum::<f64>(),
    );
    // The leader beside the rivals: significant over the catalogue's tests and the rivals',
    // and worth its parameters (BIC).
    let family = sc.n_tests + fit.tests as f64;
    let cat_gain = d_cr - d_r;
    let cat_needed =
        crate::stats::chi2_sf(cat_gain, k_c.max(1.0)) * family < cfg.alpha && cat_gain > k_c * ln_n;
    // The rivals beside the leader: one of them stays significant at the family's threshold,
    // and together they are worth their parameters.
    let rival_gain = d_cr - d_c;
    let rival_needed = rival_gain > k_r * ln_n
        && (0..rivals.len()).any(|i| {
            let others: Vec<&DVector<f64>> = columns
                .iter()
                .chain(
                    rivals
                        .iter()
                        .enumerate()
                        .filter(|(j, _)| *j != i)
                        .map(|(_, s)| *s),
                )
                .collect();
            d_cr - drop(&r0, &others) >= fit.threshold_chi2
        });
    // Each explains what the other does: the one with the better BIC by a clear margin is
    // preferred (a temperature coefficient against a step and a ramp in every run), else
    // the data cannot tell them apart.
    let simpler = (d_c - k_c * ln_n) - (d_r - k_r * ln_n) >= cfg.separability_dchi2;
    Ok(match (cat_needed, rival_needed) {
        (true, false) => Judgement::CatalogueSurvives,
        (true, true) => Judgement::BothNeeded,
        (false, true) => Judgement::RivalsExplain,
        (false, false) if simpler => Judgement::CatalogueSurvives,
        (false, false) => Judgement::NotSeparable,
    })
}

/// The causes a verdict names (empty for no gap and unexplained).
pub(crate) fn named(verdict: &Verdict) -> Vec<String> {
    match verdict {
        Verdict::Explained { by } | Verdict::PartlyExplained { by } => vec![by.clone()],
        Verdict::NotSeparable { candidates, .. } => candidates.clone(),
        _ => Vec::new(),
    }
}

/// A verdict that names a catalogue cause, challenged by the rival time courses: it stands,
/// becomes "unexplained" (the rivals explain the gap, the catalogue gets no credit) or "not
/// separable" naming both. Returns the verdict and the rivals it cites.
pub(crate) fn challenge(
    verdict: Verdict,
    st: &Stacked,
    ranked: &[Evaluated],
    sc: &JudgeScope<'_>,
    cfg: &DiagnoseConfig,
    notes: &mut Vec<Note>,
) -> Result<(Verdict, Vec<TimeCourseAlternative>), DiagError> {
    let causes = named(&verdict);
    let Some(leader) = ranked
        .iter()
        .find(|e| causes.first() == Some(&e.report.kind))
    else {
        return Ok((verdict, Vec::new()));
    };
    let fit = fit_rivals(st, &cfg.events, cfg.threads)?;
    let list = fit
        .alternatives
        .iter()
        .map(|a| {
            format!(
                "{} {} on {} ({}, {:.0} s, chi2 {:.1})",
                a.channel, a.shape, a.runs, a.kind, a.onset_s, a.dchi2
            )
        })
        .collect::<Vec<_>>()
        .join("; ");
    let judgement = judge(st, &fit, leader, sc, cfg)?;
    let text = format!(
        "rival time courses ({} signals tested, threshold chi2 {:.1}): {}; {}",
        fit.tests,
        fit.threshold_chi2,
        if list.is_empty() {
            "none significant".to_string()
        } else {
            list
        },
        match judgement {
            Judgement::CatalogueSurvives => format!("{} survives them", leader.report.kind),
            Judgement::BothNeeded => format!(
                "{} and they are both needed: the catalogue explains part of the gap",
                leader.report.kind
            ),
            Judgement::RivalsExplain => format!(
                "{} does not survive them and they survive it: the catalogue gets no credit",
                leader.report.kind
            ),
            Judgement::NotSeparable => format!(
                "{} and they explain the same part of the gap: not separable",
                leader.report.kind
            ),
        }
    );
    notes.push(
        Note::new(NoteKind::Rivals, text)
            .subject(leader.report.kind.clone())
            .figure("tests", fit.tests as f64)
            .figure("threshold_chi2", fit.threshold_chi2)
            .figure("signals", fit.alternatives.len() as f64),
    );
    Ok(match judgement {
        Judgement::CatalogueSurvives => (verdict, Vec::new()),
        Judgement::BothNeeded => match verdict {
            Verdict::Explained { by } => (Verdict::PartlyExplained { by }, fit.alternatives),
            v => (v, fit.alternatives),
        },
        Judgement::RivalsExplain => (Verdict::Unexplained, fit.alternatives),
        Judgement::NotSeparable => (
            Verdict::NotSeparable {
                candidates: causes,
                time_local: fit.alternatives.clone(),
            },
            fit.alternatives,
        ),
    })
}
