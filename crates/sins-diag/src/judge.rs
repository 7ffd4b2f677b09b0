//! The judge stage: the winner's constancy across runs, the verdict once the time-local events
//! are known, and its last checks: the gap the located events leave, the rival time courses
//! (see `crate::rival`) and the confound of the design (see `crate::confound`).

use crate::confound::confounds;
use crate::context::Context;
use crate::error::DiagError;
use crate::events::{EventScan, EventSignal, ScanRun};
use crate::rank::{Evaluated, verdict};
use crate::refinement::Refinement;
use crate::report::{ChiSquareTest, Confound, Note, NoteKind, TimeCourseAlternative, Verdict};
use crate::rival::{JudgeScope, challenge, named};
use crate::sensitivity::RunSensitivity;
use crate::stacked::Stacked;
use crate::timelocal::{scan_runs, with_events};
use crate::winner::winner_constancy;

/// The rerank stage's value, which the judge stage takes.
pub(crate) struct Reranked {
    /// The catalogue ranked on the gap less the located events, when that changed the leader
    /// (else the scan's ranking), with the scan's multiplicity when the null test passed.
    pub ranked: Vec<Evaluated>,
    /// The null test of the gap the located events leave (none without such events).
    pub left: Option<ChiSquareTest>,
    /// The calibration run's events through the coefficients, in every run's gap.
    pub absorbed: Vec<EventSignal>,
}

/// The judge stage's value.
pub(crate) struct Judged {
    /// The final ranking (the winner's constancy in its report).
    pub ranked: Vec<Evaluated>,
    /// The verdict.
    pub verdict: Verdict,
    /// The rival time courses the verdict cites.
    pub rivals: Vec<TimeCourseAlternative>,
    /// The confounds of the temperature-driven candidates.
    pub confound: Vec<Confound>,
}

/// The winner's constancy across the runs `names`, the verdict against the null test `null`
/// amended by the located `events`, and its challenge by the located events' leftover gap, the
/// rival time courses (on the whitened runs `stacked`, which this stage consumes) and the
/// confounds.
pub(crate) fn judge_stage(
    ctx: &Context<'_>,
    names: &[String],
    null: &ChiSquareTest,
    reranked: Reranked,
    events: &EventScan,
    stacked: Option<Stacked>,
    notes: &mut Vec<Note>,
) -> Result<Judged, DiagError> {
    let Reranked {
        mut ranked,
        left,
        absorbed,
    } = reranked;
    let cfg = ctx.cfg;
    winner_constancy(&mut ranked, ctx.refinements, ctx.problem, names, cfg)?;
    let verdict = with_events(verdict(ctx.problem, &ranked, null, cfg), events, notes);
    let Some(mut stacked) = stacked else {
        return Ok(Judged {
            ranked,
            verdict,
            rivals: Vec::new(),
            confound: Vec::new(),
        });
    };
    // The twin-alone gap in the leader's linearisation when it was refined (its linear
    // columns would leave its nonlinearity to the rivals).
    let leader = named(&verdict).into_iter().next();
    let refined = ctx
        .refinements
        .iter()
        .find(|r| leader.as_deref() == Some(r.layout.kind.name()));
    let mut runs = match refined {
        Some(r) => refined_runs(r, ctx.sens),
        None => scan_runs(None, &ranked, ctx),
    };
    for a in &absorbed {
        runs[a.run].residual -= &a.contribution;
    }
    stacked.take(&runs, &cfg.events)?;
    let confound = confounds(
        &stacked,
        ctx.data,
        ctx.layouts,
        cfg.events.onset_every_s as f64,
    );
    let names_cause = !named(&verdict).is_empty();
    if let Some(left) = left.as_ref().filter(|t| t.consistent && names_cause) {
        notes.push(no_credit_note(left));
        return Ok(Judged {
            ranked,
            verdict: Verdict::Unexplained,
            rivals: Vec::new(),
            confound,
        });
    }
    if !names_cause {
        return Ok(Judged {
            ranked,
            verdict,
            rivals: Vec::new(),
            confound,
        });
    }
    let sc = JudgeScope {
        data: refined.map_or(ctx.data, |r| &r.data),
        layouts: ctx.layouts,
        walks: ctx.walks,
        floor_var: ctx.floor_var,
        n_tests: ctx.tests.n_tests,
        absorbed: &absorbed,
    };
    let (verdict, rivals) = challenge(verdict, &stacked, &ranked, &sc, cfg, notes)?;
    Ok(Judged {
        ranked,
        verdict,
        rivals,
        confound,
    })
}

/// The note that the located events leave no significant gap (`left`), so the catalogue gets no
/// credit.
fn no_credit_note(left: &ChiSquareTest) -> Note {
    let text = format!(
        "the time-local events outside the catalogue leave no significant gap (chi2 {:.1} for \
         {:.1} expected, p {:.2}): the catalogue gets no credit",
        left.chi2, left.dof, left.p_value
    );
    Note::new(NoteKind::NoCredit, text)
        .figure("chi2", left.chi2)
        .figure("dof", left.dof)
        .figure("p_value", left.p_value)
}

/// The runs of refinement `r` with the gap of the twin alone in its linearisation: the
/// corrected gap plus the refined columns at the linearisation point.
fn refined_runs<'a>(r: &'a Refinement, sens: &'a [RunSensitivity]) -> Vec<ScanRun<'a>> {
    r.data
        .iter()
        .zip(sens)
        .map(|(fd, s)| {
            let mut residual = fd.gap.clone();
            for (&c, &t) in r.rf.retained.iter().zip(&r.theta_lin) {
                residual.axpy(t, &fd.columns.column(r.layout.first + c), 1.0);
            }
            ScanRun {
                sens: s,
                fit: fd,
                residual,
                nuisance: nalgebra::DMatrix::zeros(fd.gap.len(), 0),
                extra_cov: None,
                candidates: Vec::new(),
            }
        })
        .collect()
}
