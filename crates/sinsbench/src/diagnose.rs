//! `sinsbench diagnose`: where real data part from the twin, which unmodelled effect explains
//! it, and how far the gap shrinks on withheld runs.

use crate::argcheck;
use crate::out::{note, say};
use anyhow::{Result, anyhow, bail};
use sins_diag::input::DiagnoseConfig;
use sins_diag::noise::NoiseSpec;
use sins_diag::report::{Note, NoteKind};
use sins_gap::{
    DiagnoseRequest, diagnose_datasets, diagnose_datasets_identifying, write_diagnosis,
};
use std::path::PathBuf;

/// Arguments of `diagnose`.
#[derive(clap::Args)]
pub struct Args {
    /// A real run: a dataset in the project's format (repeat for several runs of the same IMU:
    /// the calibration run and/or navigation runs on the turntable). `NAME=PATH` names it,
    /// otherwise the file stem is the name. Runs need a 20 min stationary start (the
    /// self-alignment) and the site in their metadata; 42-state sets need the temperatures.
    #[arg(long = "dataset", value_name = "[NAME=]PATH", required = true)]
    pub datasets: Vec<String>,
    /// The calibrated parameter set the real runs are compensated with (TOML/JSON in the
    /// paper's units; its 1-sigma, when present, widens the twin).
    #[arg(long)]
    pub params: PathBuf,
    /// The IMU's sensor noise (the twin's spread): a noise file written by `sinsbench noise`
    /// (noise.toml) or an experiment file whose [imu.noise] gives it (e.g.
    /// experiments/paper_navigation.toml, the paper IMU's figures). Default: identified from
    /// the datasets' stationary segments (see --noise-labels) exactly as `sinsbench noise` does;
    /// the report's notes say which noise was used.
    #[arg(long)]
    pub noise_from: Option<PathBuf>,
    /// Segment labels of the stationary samples the noise is identified from when no
    /// --noise-from is given (comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "alignment,stationary")]
    pub noise_labels: Vec<String>,
    /// Only these candidate effects (comma-separated kind names); default the whole catalogue.
    #[arg(long, value_delimiter = ',')]
    pub candidates: Vec<String>,
    /// Output directory: report.md, diagnosis.json, gap_<run>.png, diagnosis.rrd.
    #[arg(long, default_value = "reports/diagnosis")]
    pub out: PathBuf,
    /// The run the parameter set was calibrated from (by `sinsbench calibrate`, same model):
    /// the diagnosis recalibrates it once per candidate component with the component added, so
    /// that each candidate also acts through the coefficients the calibration absorbed it into
    /// (an effect present during calibration biases them; about 1 s of filter per component).
    /// Default: the run named `cal`, if any; `none` turns it off.
    #[arg(long, value_name = "NAME")]
    pub calibration_run: Option<String>,
    /// Worker threads (results do not depend on it).
    #[arg(long, default_value_t = 2, value_parser = argcheck::threads)]
    pub threads: usize,
}

/// Run `diagnose`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    let datasets = argcheck::datasets(&args.datasets)?;
    let calibration_run = match args.calibration_run.as_deref() {
        Some("none") => None,
        Some(name) => {
            if !datasets.iter().any(|(n, _)| n == name) {
                bail!("--calibration-run {name}: no --dataset is named '{name}'");
            }
            Some(name.to_string())
        }
        None => datasets
            .iter()
            .find(|(n, _)| n == "cal")
            .map(|(n, _)| n.clone()),
    };
    let (parent, name) = crate::outputs::output_dir(&args.out, "diagnose")?;
    let set = sins_config::load_params(&args.params)?;
    let config = DiagnoseConfig {
        candidates: args.candidates.clone(),
        threads: args.threads,
        ..DiagnoseConfig::default()
    };
    config
        .candidate_kinds()
        .map_err(|e| anyhow!("--candidates: {e}"))?;
    // The inputs are read before the runs are checked, the runs before any work.
    let noise_file = match &args.noise_from {
        Some(path) => Some(sins_config::load_noise(path).map_err(|e| match e {
            sins_config::ConfigError::WrongKind { .. } => anyhow!(
                "--noise-from {e}; pass it as --params, and give --noise-from a noise.toml \
                     written by `sinsbench noise` or an experiment file with [imu.noise] (or \
                     leave --noise-from out to identify the noise from the datasets)"
            ),
            e => anyhow!(e),
        })?),
        None => None,
    };
    check_runs(&datasets, &set.params, &args.params, &config)?;
    let request = DiagnoseRequest {
        datasets,
        params: set.params,
        param_sigma: set.sigma,
        param_covariance: None,
        calibration_run,
        config,
    };
    let (mut outcome, said) = match noise_file {
        Some(table) => {
            let (noise, notes) = noise_of_file(&table);
            print_notes(&notes)?;
            if !quiet {
                replaying_note(&request, &args);
            }
            let outcome = diagnose_datasets(&request, noise)?;
            let untrusted = table.inconsistent.clone();
            (outcome, NoiseNotes { notes, untrusted })
        }
        None => {
            if !quiet {
                note!(
                    "diagnose: no --noise-from: identifying the twin's noise from the stationary segments ({}) of the datasets",
                    args.noise_labels.join(", ")
                );
                replaying_note(&request, &args);
            }
            let identified = diagnose_datasets_identifying(&request, || {
                identify(&request.datasets, &args.noise_labels, &set.params)
            })?;
            print_notes(&identified.1.notes)?;
            identified
        }
    };
    outcome.diagnosis.notes.splice(0..0, said.notes);
    outcome.diagnosis.noise_untrusted = said.untrusted;
    let dir = write_diagnosis(&parent, &name, &outcome)?;
    say!("verdict: {:?}", outcome.diagnosis.verdict)?;
    for r in &outcome.diagnosis.noise_untrusted {
        say!("  the twin's noise cannot be trusted: {r}")?;
    }
    for c in outcome.diagnosis.candidates.iter().take(3) {
        say!(
            "  {:<32} dchi2 {:>10.1}  dBIC {:>10.1}  {}",
            c.kind,
            c.dchi2,
            c.delta_bic,
            if c.passes { "passes" } else { "" }
        )?;
    }
    say!(
        "wrote {} (replays {:.1} s, diagnosis {:.1} s)",
        dir.display(),
        outcome.replay_s,
        outcome.diagnose_s
    )
}

/// Every run checked before any work: it opens, it has the temperatures a 42-state set needs,
/// and it is long enough for the self-alignment and two fit times after it (the least the
/// diagnosis fits); each refusal names the run, its file and what to do.
fn check_runs(
    datasets: &[(String, PathBuf)],
    params: &sins_imu::ImuErrorParams,
    params_path: &std::path::Path,
    config: &DiagnoseConfig,
) -> Result<()> {
    let align_s = config.replay.alignment.duration_s;
    let min_s = align_s + 2.0 * config.fit_interval_s as f64;
    for (name, path) in datasets {
        let info = argcheck::open_run(name, path)?;
        argcheck::require_temperatures(name, path, &info, params, params_path, "")?;
        let duration_s = info.n_rows as f64 * info.meta.sample_interval_s();
        if duration_s < min_s {
            bail!(
                "run '{name}' ({}): {} samples ({duration_s:.2} s), but diagnose replays every \
                 run from a {align_s:.0} s self-alignment at its start (the IMU still) and fits \
                 the navigation after it every {} s, at least twice: give a recording of at \
                 least {min_s:.0} s, or leave this run out",
                path.display(),
                info.n_rows,
                config.fit_interval_s
            );
        }
    }
    Ok(())
}

/// The twin's noise from a noise file (or an experiment's `[imu.noise]`) and the note that says
/// so.
fn noise_of_file(table: &sins_config::NoiseTable) -> (NoiseSpec, Vec<Note>) {
    let path = &table.source_path;
    let what = if table.from_noise_file {
        "noise file"
    } else {
        "[imu.noise] of experiment"
    };
    let bound = |v: f64, unit: f64, label: &str| {
        if v.is_finite() {
            format!("{:.3e} {label}", v / unit)
        } else {
            "no finite bound, not fitted".into()
        }
    };
    let walks = match table.unresolved_walk_per_sqrt_s {
        Some([g, a]) => format!(
            "; rate random walks it could not exclude, fitted on the gap within their bounds: gyro {}, accel {}",
            bound(g, sins_config::units::DEG_PER_H_PER_SQRT_H, "deg/h/√h"),
            bound(a, sins_config::units::UG_PER_SQRT_H, "ug/√h")
        ),
        None => String::new(),
    };
    (
        NoiseSpec {
            unresolved_walk_per_sqrt_s: table.unresolved_walk_per_sqrt_s,
            ..NoiseSpec::from(&table.noise)
        },
        vec![Note::new(
            NoteKind::NoiseIdentification,
            format!("twin noise: the {what} {}{walks}", path.display()),
        )],
    )
}

/// What the report says of the twin's noise: where it came from, and the reasons it cannot be
/// trusted (none when it can).
struct NoiseNotes {
    notes: Vec<Note>,
    untrusted: Vec<String>,
}

/// The twin's noise identified from the stationary segments labelled `labels` of `datasets`
/// (compensated with `params`), with its notes.
fn identify(
    datasets: &[(String, PathBuf)],
    labels: &[String],
    params: &sins_imu::ImuErrorParams,
) -> Result<(NoiseSpec, NoiseNotes)> {
    let id = sins_gap::identify_datasets(datasets, labels, Some(params)).map_err(|e| match e {
        // The identification itself failed (too little still data, ...): a noise file is then
        // the way on. Data errors name their file and row already.
        sins_gap::GapError::Invalid(_) => anyhow!(
            "{e}; no --noise-from was given, so the twin's noise is identified from the \
             datasets' still stretches: give --noise-from FILE (a noise.toml of `sinsbench \
             noise` on longer still data, or an experiment file with [imu.noise]) to use a \
             file instead"
        ),
        e => anyhow!(e),
    })?;
    let line = sins_gap::noise_report::noise_one_line(&id);
    let mut notes = vec![Note::new(
        NoteKind::NoiseIdentification,
        format!(
            "twin noise: identified from the data's stationary segments (sinsbench noise): {line}"
        ),
    )];
    notes.extend(id.diagnosis_notes());
    let untrusted = id.inconsistent.clone();
    Ok((id.to_noise_spec(), NoiseNotes { notes, untrusted }))
}

/// Print the noise notes, one a line.
fn print_notes(notes: &[Note]) -> Result<()> {
    notes.iter().try_for_each(|n| say!("{n}"))
}

/// The progress line that says what is replayed.
fn replaying_note(request: &DiagnoseRequest, args: &Args) {
    note!(
        "diagnose: replaying {} run(s) with {} and fitting the catalogue against the twin",
        request.datasets.len(),
        args.params.display()
    );
}
