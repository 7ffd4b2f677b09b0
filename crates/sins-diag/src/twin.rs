//! The twin of every run: the sensitivity pass (columns and noise covariance, runs in
//! parallel) and the calibration run's absorption of every candidate.

use crate::absorb::{Absorption, CalibrationRun, absorption};
use crate::error::DiagError;
use crate::input::{DiagnoseConfig, DiagnosisInput};
use crate::noise::NoiseSpec;
use crate::pass::Grid;
use crate::rank::Layout;
use crate::replay::temperature_series;
use crate::report::{Note, NoteKind};
use crate::runs::par_runs;
use crate::sensitivity::{RunSensitivity, SensitivitySetup, run_sensitivity};
use sins_imu::{EffectKind, ImuErrorParams};

/// The settings of the base sensitivity pass.
pub(crate) fn base_setup<'a>(
    params: &'a ImuErrorParams,
    noise: &'a NoiseSpec,
    cfg: &'a DiagnoseConfig,
    kinds: &'a [EffectKind],
) -> SensitivitySetup<'a> {
    SensitivitySetup {
        params,
        noise,
        replay: &cfg.replay,
        candidates: kinds,
        grid: Grid {
            output_every_s: cfg.output_interval_s.max(1),
            fit_every: (cfg.fit_interval_s / cfg.output_interval_s.max(1)).max(1),
        },
        refine: None,
        turn_on_taus_s: if cfg.events.enabled {
            &cfg.events.time_constants_s
        } else {
            &[]
        },
    }
}

/// Sensitivities of every run (the temperature series are computed first when missing).
pub(crate) fn sensitivities(
    input: &mut DiagnosisInput,
    cfg: &DiagnoseConfig,
    kinds: &[EffectKind],
) -> Result<Vec<RunSensitivity>, DiagError> {
    let (params, noise) = (input.params, input.noise);
    let setup = base_setup(&params, &noise, cfg, kinds);
    par_runs(&mut input.runs, cfg.threads, |r| {
        if r.temperatures.is_none() {
            r.temperatures = Some(temperature_series(
                r.source.as_mut(),
                cfg.replay.temperature_rate_half_window_s,
            )?);
        }
        let temps = r
            .temperatures
            .as_ref()
            .ok_or_else(|| DiagError::input(&r.name, "temperature series missing"))?;
        run_sensitivity(&r.name, r.source.as_mut(), &r.site, &r.track, temps, &setup)
    })
}

/// The sensitivities of every run ([`sensitivities`]) and the calibration run's absorption of
/// every deterministic candidate of `layouts` (none without a calibration run among the
/// inputs). With two or more threads and a calibration run whose source reads twice at once,
/// the recalibrations run beside the passes: the passes of runs of unequal length leave a core
/// idle, and both read the runs as they are, so the results are those of one after the other.
pub(crate) fn twin_passes(
    input: &mut DiagnosisInput,
    cfg: &DiagnoseConfig,
    kinds: &[EffectKind],
    layouts: &[Layout],
) -> Result<(Vec<RunSensitivity>, Option<Absorption>), DiagError> {
    let Some(name) = input.calibration_run.clone() else {
        return Ok((sensitivities(input, cfg, kinds)?, None));
    };
    let (params, noise) = (input.params, input.noise);
    let comps = components(layouts);
    let beside = match cfg.threads >= 2 {
        true => CalibrationRun::among(&mut input.runs, &name)
            .ok()
            .and_then(|c| Some((c.source.try_clone()?, *c.site, c.temps.clone()))),
        false => None,
    };
    let Some((mut source, site, temps)) = beside else {
        let sens = sensitivities(input, cfg, kinds)?;
        let cal = CalibrationRun::among(&mut input.runs, &name)?;
        let a = absorption(cal, &params, &noise, &comps, cfg.threads)?;
        return Ok((sens, Some(a)));
    };
    let cal = CalibrationRun {
        run: &name,
        source: source.as_mut(),
        site: &site,
        temps: &temps,
    };
    let (sens, a) = std::thread::scope(|scope| {
        let worker = scope.spawn(|| absorption(cal, &params, &noise, &comps, cfg.threads));
        let sens = sensitivities(input, cfg, kinds);
        (sens, worker.join())
    });
    let a = a.map_err(|_| {
        DiagError::Numerical("the calibration absorption stopped unexpectedly (a panic)".into())
    });
    // A failed pass is what running the passes first reports.
    let sens = sens?;
    Ok((sens, Some(a??)))
}

/// Every component of the candidates of `layouts`.
fn components(layouts: &[Layout]) -> Vec<(EffectKind, usize)> {
    layouts
        .iter()
        .flat_map(|l| (0..l.n).map(move |c| (l.kind, c)))
        .collect()
}

/// Fold the calibration run's absorption `a` ([`twin_passes`]) into the candidate columns of
/// every run, and say what it did.
pub(crate) fn fold_absorption(
    input: &DiagnosisInput,
    a: Option<&Absorption>,
    sens: &mut [RunSensitivity],
    notes: &mut Vec<Note>,
) {
    let Some(a) = a else {
        notes.push(Note::new(
            NoteKind::CalibrationAbsorption,
            "no calibration run among the inputs: the candidates act on the navigation only, \
             not through the coefficients a calibration in their presence would have biased",
        ));
        return;
    };
    let (name, params, comps) = (&a.run, input.params, &a.components);
    for s in sens.iter_mut() {
        a.fold(s, None);
    }
    let given = sins_kf::params_to_vec(&params, params.model);
    let sigma = input
        .param_sigma
        .map(|p| sins_kf::params_to_vec(&p, params.model));
    let worst = sigma.map(|sg| {
        given
            .iter()
            .zip(&a.recalibrated)
            .zip(&sg)
            .map(|((g, r), s)| if *s > 0.0 { (g - r).abs() / s } else { 0.0 })
            .fold(0.0, f64::max)
    });
    let text = format!(
        "calibration absorption: run '{name}' recalibrated ({}-state filter, twin noise) once as \
         recorded and once per candidate component with it added, {} components; each candidate \
         acts on the navigation directly and through the coefficients it biases{}",
        params.model.n_states(),
        comps.len(),
        worst.map_or(String::new(), |w| format!(
            "; the recalibration reproduces the given set within {w:.2} sigma"
        ))
    );
    let mut note = Note::new(NoteKind::CalibrationAbsorption, text)
        .run(name.as_str())
        .figure("components", comps.len() as f64);
    if let Some(w) = worst {
        note = note.figure("recalibration_sigma", w);
    }
    notes.push(note);
}
