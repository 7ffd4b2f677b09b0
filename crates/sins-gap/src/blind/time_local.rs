//! Grading the time-local cases: was the hidden step, ramp, transient, pulse, plateau or
//! oscillation reported as an event on its channel (and run), with the onset within three
//! sigma of the truth; and the null cases' time-local false alarms.

use super::plan::{CaseAnswer, HiddenEffect};
use serde::Serialize;
use sins_config::markdown::Table;
use sins_diag::events::{DetectableCurve, TimeLocalEvent};
use sins_diag::report::Diagnosis;
use sins_imu::EffectKind;
use sins_imu::effects::Sensor;

/// The grade of one time-local case.
#[derive(Clone, Debug, Serialize)]
pub struct TimeLocalGrade {
    /// The channel (`gyro x` ...).
    pub channel: String,
    /// The hidden shape (`step`, `ramp`, `transient`, `turn-on transient`).
    pub shape: String,
    /// The event reported on that channel (and run), the strongest if several; failing that,
    /// the strongest that names the channel among those the data cannot tell from its own.
    pub event: Option<TimeLocalEvent>,
    /// The event names the channel only as an indistinguishable alternative.
    pub as_alternative: bool,
    /// The event's onset is within three of its sigmas of the truth.
    pub onset_within_3_sigma: bool,
    /// The event has the hidden shape.
    pub shape_right: bool,
    /// The scan's detectable size for this shape, channel, run and onset (paper unit).
    pub detectable: Option<f64>,
    /// The hidden size is above it (true when unknown).
    pub above_detectable: bool,
    /// The onset is graded: false for an effect in the calibration run only (no navigation run
    /// carries it, so no event can be located; such a case is graded by its verdict alone,
    /// a confident misattribution or not).
    pub onset_graded: bool,
}

fn channel(h: &HiddenEffect, kind: EffectKind) -> String {
    let sensor = match kind.sensor() {
        Sensor::Gyro => "gyro",
        Sensor::Accel => "accel",
    };
    format!("{sensor} {}", h.component_label)
}

fn shape(h: &HiddenEffect, kind: EffectKind) -> &'static str {
    match kind {
        EffectKind::GyroBiasRamp | EffectKind::AccelBiasRamp => "ramp",
        EffectKind::GyroBiasPlateau | EffectKind::AccelBiasPlateau => "plateau",
        EffectKind::GyroBiasPulse | EffectKind::AccelBiasPulse => "pulse",
        EffectKind::GyroBiasDecayingOscillation | EffectKind::AccelBiasDecayingOscillation => {
            "decaying oscillation"
        }
        EffectKind::GyroBiasTransient | EffectKind::AccelBiasTransient => {
            if h.onset_time_s() == 0.0 {
                "turn-on transient"
            } else {
                "transient"
            }
        }
        _ => "step",
    }
}

/// The detectable level of the hidden effect: the curve of its run, channel and shape (the
/// transient's nearest time constant, the pulse's nearest duration, the plateau's nearest rise
/// time), at the onset nearest its own; the smallest over the runs it acts on.
fn detectable(h: &HiddenEffect, ch: &str, sh: &str, curves: &[DetectableCurve]) -> Option<f64> {
    let timed = |c: &DetectableCurve| c.time_constant_s.or(c.duration_s);
    let time = match sh {
        "pulse" | "plateau" => h.duration_s,
        _ => h.time_constant_s,
    }
    .unwrap_or(1.0);
    let matching: Vec<&DetectableCurve> = curves
        .iter()
        .filter(|c| c.channel == ch && c.shape == sh && h.acts_on(&c.run))
        .collect();
    let best_time = matching
        .iter()
        .filter_map(|c| timed(c))
        .min_by(|a, b| (a / time).ln().abs().total_cmp(&(b / time).ln().abs()));
    matching
        .iter()
        .filter(|c| timed(c) == best_time)
        .filter_map(|c| {
            let onset = h.onset_time_s();
            c.onset_s
                .iter()
                .zip(&c.level)
                .min_by(|a, b| (a.0 - onset).abs().total_cmp(&(b.0 - onset).abs()))
                .map(|(_, l)| *l)
        })
        .min_by(f64::total_cmp)
}

/// Grade a case whose hidden effect is time-local (`None` otherwise). An effect in one run is
/// looked for in that run; one common to every navigation run in any of them (the strongest
/// event on the channel, its onset against the common onset); one in the calibration run only
/// has no onset to locate (`onset_graded` false).
pub fn grade_case(a: &CaseAnswer, d: &Diagnosis) -> Option<TimeLocalGrade> {
    let h = a.hidden.as_ref().filter(|h| h.is_time_local())?;
    let kind = EffectKind::from_name(&h.kind)?;
    let ch = channel(h, kind);
    let sh = shape(h, kind);
    let strongest = |named: &dyn Fn(&TimeLocalEvent) -> bool| {
        d.events
            .events
            .iter()
            .filter(|e| named(e) && h.acts_on(&e.run))
            .max_by(|x, y| x.chi2.total_cmp(&y.chi2))
            .cloned()
    };
    let on_channel = strongest(&|e| e.channel == ch);
    let as_alternative = on_channel.is_none();
    let event =
        on_channel.or_else(|| strongest(&|e| e.alternatives.iter().any(|a| a.channel == ch)));
    let as_alternative = as_alternative && event.is_some();
    let truth = h.onset_time_s();
    let onset_within_3_sigma = event
        .as_ref()
        .is_some_and(|e| (e.onset_s - truth).abs() <= 3.0 * e.onset_sigma_s + 1e-9);
    // A pulse and a plateau have curves of their own (a diagnosis from before the scan had
    // them has none); an oscillation is graded against the step's level at its onset (a
    // lower bound on its detectable size: it holds that level for less time).
    let detectable = detectable(h, &ch, sh, &d.events.detectable)
        .or_else(|| detectable(h, &ch, "step", &d.events.detectable));
    Some(TimeLocalGrade {
        onset_graded: !h.calibration_only(),
        shape_right: event.as_ref().is_some_and(|e| e.shape == sh),
        above_detectable: detectable.is_none_or(|l| h.magnitude.abs() > l),
        channel: ch,
        shape: sh.to_string(),
        event,
        as_alternative,
        onset_within_3_sigma,
        detectable,
    })
}

/// A diagnosis reports an event that no catalogue term explains.
pub fn has_unexplained_event(d: &Diagnosis) -> bool {
    d.events.events.iter().any(|e| e.explained_by.is_none())
}

/// The time-local section of the grades' Markdown.
pub fn render(
    rows: &[(&CaseAnswer, &TimeLocalGrade)],
    found: (usize, usize),
    on_channel: (usize, usize),
    false_alarms: (usize, usize),
    wide: Option<((usize, usize), (usize, usize))>,
    frac: fn((usize, usize)) -> String,
) -> String {
    let mut figures = Table::new(["figure", "result", "target"]);
    if let Some((wide_found, wide_on_channel)) = wide {
        figures
            .row([
                "widened draw: reported with the onset within 3 sigma, their channel named, \
                 cases in navigation runs above the detectable level (calibration-only cases \
                 are graded by their verdict)"
                    .to_string(),
                frac(wide_found),
                "≥ 90 %".to_string(),
            ])
            .row([
                "the same, their channel the event's own".to_string(),
                frac(wide_on_channel),
                "-".to_string(),
            ]);
    }
    figures
        .row([
            "reported with the onset within 3 sigma, their channel named (as the event's or as one \
             the data cannot tell from it), cases above the detectable level"
                .to_string(),
            frac(found),
            "≥ 90 %".to_string(),
        ])
        .row([
            "the same, their channel the event's own".to_string(),
            frac(on_channel),
            "-".to_string(),
        ])
        .row([
            "null cases with a time-local event outside the catalogue".to_string(),
            frac(false_alarms),
            "≤ 1 in 10".to_string(),
        ]);
    let mut t = Table::new([
        "case",
        "hidden",
        "run",
        "onset (s)",
        "size (× typical)",
        "detectable",
        "event",
        "onset ± 1σ (s)",
        "size ± 1σ",
        "within 3σ",
    ]);
    for (a, g) in rows {
        let Some(h) = &a.hidden else { continue };
        let tau = h
            .time_constant_s
            .map_or(String::new(), |t| format!(", τ {t:.0} s"));
        let tau = match h.duration_s {
            Some(d) => {
                let what = match g.shape.as_str() {
                    "plateau" => "rise",
                    "pulse" => "duration",
                    _ => "period",
                };
                format!("{tau}, {what} {d:.0} s")
            }
            None => tau,
        };
        let ev = g.event.as_ref();
        t.row([
            a.case.clone(),
            format!("{} {} {}{tau}", g.shape, g.channel, h.kind),
            match (h.scope, h.run.as_deref()) {
                (Some(super::plan::EventScope::AllNavigationRuns), _) => "every navigation run",
                (_, Some(super::plan::CALIBRATION_SCOPE)) => "calibration only",
                (_, Some(r)) => r,
                (_, None) => "all",
            }
            .to_string(),
            format!("{:.0}", h.onset_time_s()),
            format!("{:.3e} {} ({:.1}×)", h.magnitude, h.unit, h.times_typical),
            g.detectable.map_or("-".into(), |v| format!("{v:.2e}")),
            ev.map_or("none".into(), |e| {
                format!(
                    "{} {}{} in {}{}",
                    e.shape,
                    e.channel,
                    if g.as_alternative {
                        format!(" (or {})", g.channel)
                    } else {
                        String::new()
                    },
                    e.run,
                    e.explained_by
                        .as_ref()
                        .map_or(String::new(), |x| format!(" (explained by {x})"))
                )
            }),
            ev.map_or("-".into(), |e| {
                format!("{:.0} ± {:.0}", e.onset_s, e.onset_sigma_s)
            }),
            ev.map_or("-".into(), |e| {
                format!("{:.3e} ± {:.1e}", e.size, e.size_sigma)
            }),
            if !g.onset_graded {
                "- (calibration only)"
            } else if g.onset_within_3_sigma {
                "yes"
            } else {
                "no"
            }
            .to_string(),
        ]);
    }
    format!(
        "\n## Time-local effects (steps, ramps, transients{})\n\n{figures}\n{t}",
        if wide.is_some() {
            "; plateaus, pulses, decaying oscillations"
        } else {
            ""
        }
    )
}
