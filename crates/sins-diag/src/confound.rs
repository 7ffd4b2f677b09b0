//! Confounded designs: how much of a catalogue candidate's information a time course common to
//! every run takes away. When the runs share one chamber history (or one motion), a
//! temperature-driven term acts on each run as a bias with the same time course, and a free
//! time course common to the runs fits it as well: the data cannot tell the two apart, a limit
//! of the experiment and not of the IMU.
//!
//! The time-course basis is, on each of the six channels, a bias from the start of navigation
//! plus ramps starting every [`KNOT_S`] (a continuous piecewise-linear bias profile), the same
//! on every run's time axis. A candidate component's column `c` (whitened, stacked over the
//! runs) loses the share `|P_B c|² / |c|²` of its Fisher information to the basis `B`; the
//! pooled figure is `Σ|P_B c|² / Σ|c|²` over the components.
//!
//! Two extra runs are tried, built from the sensitivities of the longest run: the same run with
//! the chamber held (the temperature terms are silent, the common time course is not) and with its
//! temperature excursion reversed (to first order the temperature terms change sign, the time
//! course does not). The run that cuts the loss most is the suggested experiment.

use crate::problem::RunFitData;
use crate::rank::Layout;
use crate::report::Confound;
use crate::stacked::Stacked;
use crate::whiten::Nuisance;
use nalgebra::DVector;
use sins_imu::EffectKind;

/// One candidate layout's columns: per component, per run.
type RunColumns = Vec<Vec<DVector<f64>>>;

/// Spacing of the ramps of the time-course basis (s).
pub const KNOT_S: f64 = 3600.0;

/// Kinds whose signature follows the chamber's temperature history.
pub fn temperature_driven(kind: EffectKind) -> bool {
    matches!(
        kind,
        EffectKind::AccelBiasQuadraticTemp
            | EffectKind::GyroBiasTemp
            | EffectKind::AccelBiasTempRate
            | EffectKind::GyroBiasTempRate
            | EffectKind::ThermalLag
    )
}

/// The basis of one run, whitened: per axis, the step at the first onset and the ramps at
/// every knot below `common` onsets.
fn run_basis(st: &Stacked, run: usize, every_s: f64, common: usize) -> Vec<DVector<f64>> {
    let p = &st.runs[run];
    let k = p.onset_s.len();
    let knot = ((KNOT_S / every_s).round() as usize).max(1);
    let mut out = Vec::new();
    for ax in &p.axes {
        if k == 0 {
            continue;
        }
        out.push(ax.steps.column(0).into_owned());
        let mut ramp = DVector::zeros(ax.steps.nrows());
        let mut next = DVector::zeros(ax.steps.nrows());
        let mut ramps = Vec::new();
        for m in (0..k).rev() {
            let here = ax.steps.column(m).into_owned();
            ramp += (&here + &next) * (0.5 * every_s);
            if m % knot == 0 && m < common {
                ramps.push(ramp.clone());
            }
            next = here;
        }
        out.extend(ramps);
    }
    out
}

/// A candidate component's whitened columns, run by run.
fn component(st: &Stacked, data: &[RunFitData], col: usize) -> Vec<DVector<f64>> {
    st.runs
        .iter()
        .zip(data)
        .map(|(p, fd)| p.whitener.whiten_vec(&fd.columns.column(col).into_owned()))
        .collect()
}

/// Shares of information lost (pooled, and per component) for blocks of a design.
fn lost(basis: &[Vec<DVector<f64>>], columns: &[Vec<Vec<DVector<f64>>>]) -> Vec<(f64, Vec<f64>)> {
    let stack = |blocks: &[DVector<f64>]| {
        let rows: usize = blocks.iter().map(|b| b.len()).sum();
        let mut v = DVector::zeros(rows);
        let mut o = 0;
        for b in blocks {
            v.rows_mut(o, b.len()).copy_from(b);
            o += b.len();
        }
        v
    };
    let mut n = Nuisance::new(stack(
        &basis
            .iter()
            .map(|b| DVector::zeros(b[0].len()))
            .collect::<Vec<_>>(),
    ));
    let n_basis = basis.first().map_or(0, |b| b.len());
    for j in 0..n_basis {
        let blocks: Vec<DVector<f64>> = basis.iter().map(|b| b[j].clone()).collect();
        n.add(&stack(&blocks));
    }
    columns
        .iter()
        .map(|comps| {
            let (mut kept, mut total) = (0.0, 0.0);
            let per: Vec<f64> = comps
                .iter()
                .map(|blocks| {
                    let c = stack(blocks);
                    let (_, b) = n.stat(c.as_slice());
                    let t = c.norm_squared();
                    kept += b;
                    total += t;
                    if t > 0.0 { 1.0 - b / t } else { 0.0 }
                })
                .collect();
            (if total > 0.0 { 1.0 - kept / total } else { 0.0 }, per)
        })
        .collect()
}

/// The confound of every temperature-driven deterministic candidate, this design and with one
/// extra run like the longest (held chamber, reversed excursion).
pub(crate) fn confounds(
    st: &Stacked,
    data: &[RunFitData],
    layouts: &[Layout],
    every_s: f64,
) -> Vec<Confound> {
    let layouts: Vec<&Layout> = layouts
        .iter()
        .filter(|l| temperature_driven(l.kind))
        .collect();
    if layouts.is_empty() || st.runs.is_empty() {
        return Vec::new();
    }
    let common = st.common_onsets.max(1);
    let basis: Vec<Vec<DVector<f64>>> = (0..st.runs.len())
        .map(|r| run_basis(st, r, every_s, common))
        .collect();
    // columns[layout][component][run]
    // A candidate without information (no temperature record) has nothing to lose.
    let (layouts, columns): (Vec<&Layout>, Vec<RunColumns>) = layouts
        .iter()
        .map(|l| {
            let cols: Vec<Vec<DVector<f64>>> =
                (0..l.n).map(|c| component(st, data, l.first + c)).collect();
            (*l, cols)
        })
        .filter(|(_, cols)| cols.iter().flatten().any(|v| v.norm_squared() > 0.0))
        .unzip();
    if layouts.is_empty() {
        return Vec::new();
    }
    let here = lost(&basis, &columns);
    let like = (0..st.runs.len())
        .max_by_key(|&r| st.runs[r].residual.len())
        .unwrap_or(0);
    let with_run = |sign: f64| {
        let mut b = basis.clone();
        b.push(basis[like].clone());
        let cols: Vec<Vec<Vec<DVector<f64>>>> = columns
            .iter()
            .map(|comps| {
                comps
                    .iter()
                    .map(|blocks| {
                        let mut v = blocks.clone();
                        v.push(&blocks[like] * sign);
                        v
                    })
                    .collect()
            })
            .collect();
        lost(&b, &cols)
    };
    let held = with_run(0.0);
    let reversed = with_run(-1.0);
    layouts
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let labels = l.kind.component_labels();
            let (worst, worst_lost) = here[i]
                .1
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(b.1))
                .map_or((0, 0.0), |(c, &v)| (c, v));
            Confound {
                kind: l.kind.name().to_string(),
                information_lost: here[i].0,
                worst_component: labels.get(worst).copied().unwrap_or("?").to_string(),
                worst_component_lost: worst_lost,
                with_held_run: held[i].0,
                with_reversed_run: reversed[i].0,
                like_run: st.runs[like].run.clone(),
            }
        })
        .collect()
}
