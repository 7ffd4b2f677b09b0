//! `sinsbench calibrate`: the paper's system-level calibration on any calibration dataset.

use crate::out::say;
use crate::progress;
use anyhow::{Context, Result, bail};
use sins_config::{ParamSet, coefficient_table, write_params};
use sins_data::DatasetReader;
use sins_harness::pipeline::calibration_filter;
use sins_imu::ParamModel;
use sins_kf::{CalibrationResult, FilterNoise, params_from_vec};
use sins_nav::{DEG_PER_H, UG};
use sins_sim::noise::gauss_markov_sigma_from_allan;
use std::path::{Path, PathBuf};

/// Arguments of `calibrate`.
#[derive(clap::Args)]
pub struct Args {
    /// Calibration dataset: a stationary start (20 min self-alignment) followed by the rotation
    /// scheme on a turntable at a known site (Parquet or CSV, see README).
    #[arg(long)]
    pub dataset: PathBuf,
    /// Filter: 42 states (with the 12 accelerometer temperature coefficients; needs the
    /// temp_a*_degc columns) or 30 states (constant coefficients only).
    #[arg(long, value_enum, default_value_t = States::S42)]
    pub states: States,
    /// Output parameter set (.toml or .json, paper units, with 1-sigma). The convergence history
    /// is written beside it as <stem>_history.parquet, and the estimation curves (the paper's
    /// figure 2) as <stem>.rrd for the Rerun viewer.
    #[arg(long)]
    pub out: PathBuf,
    /// Temperature (degC) at which the temperature terms vanish (the paper uses T itself: 0).
    #[arg(long, default_value_t = 0.0)]
    pub reference_temperature_degc: f64,
    /// Gyro angle random walk assumed by the filter (deg/sqrt(h)).
    #[arg(long, default_value_t = 0.0005)]
    pub gyro_arw_deg_per_sqrt_h: f64,
    /// Gyro bias instability (Allan figure, deg/h), modelled as a 1 h Gauss-Markov wander.
    #[arg(long, default_value_t = 0.0005)]
    pub gyro_bias_instability_deg_per_h: f64,
    /// Accelerometer velocity random walk assumed by the filter (ug/sqrt(Hz)).
    #[arg(long, default_value_t = 10.0)]
    pub accel_vrw_ug_per_sqrt_hz: f64,
    /// Accelerometer bias instability (Allan figure, ug), modelled as a 1 h Gauss-Markov wander.
    #[arg(long, default_value_t = 5.0)]
    pub accel_bias_instability_ug: f64,
}

/// Filter size.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum States {
    /// 30 states: navigation errors + 21 constant coefficients.
    #[value(name = "30")]
    S30,
    /// 42 states: the 30 + 12 accelerometer temperature coefficients.
    #[value(name = "42")]
    S42,
}

/// Run `calibrate`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    let model = match args.states {
        States::S30 => ParamModel::States30,
        States::S42 => ParamModel::States42,
    };
    let mut reader = DatasetReader::open(&args.dataset)?;
    let info = reader.info().clone();
    if model == ParamModel::States42 && !info.has_temperature {
        bail!(
            "{}: a 42-state calibration needs the accelerometer temperatures (columns temp_ax_degc, temp_ay_degc, \
             temp_az_degc), which this dataset lacks; use --states 30",
            info.path.display()
        );
    }
    sins_config::ParamFormat::from_path(&args.out)?;
    let history = history_path(&args.out);
    let rrd = args.out.with_extension("rrd");
    for (path, what) in [
        (&args.out, "parameter"),
        (&history, "history"),
        (&rrd, "Rerun recording"),
    ] {
        crate::outputs::check_file_target(path, what)?;
    }
    let parent = match args.out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    crate::outputs::sweep(parent);
    sins_files::lock::lock_output(parent, None)?;
    let unchanged = format!(
        "the previous {}, {} and {} are unchanged",
        args.out.display(),
        history.display(),
        rrd.display()
    );
    sins_files::set_interrupt_note(Some(unchanged.clone()));
    let noise = FilterNoise::from_sensor(
        args.gyro_arw_deg_per_sqrt_h * sins_nav::DEG / 60.0,
        gauss_markov_sigma_from_allan(args.gyro_bias_instability_deg_per_h * DEG_PER_H),
        3600.0,
        args.accel_vrw_ug_per_sqrt_hz * UG,
        gauss_markov_sigma_from_allan(args.accel_bias_instability_ug * UG),
        3600.0,
    );
    let mut filter = calibration_filter(
        model,
        info.meta.sample_interval_s(),
        info.meta.site,
        noise,
        args.reference_temperature_degc,
    )?;
    let pb = progress::bar(info.n_rows, "calibrate", quiet);
    while let Some(batch) = reader.next_batch()? {
        filter
            .push_batch(&batch.samples, None)
            .with_context(|| format!("{}: calibration stopped", info.path.display()))?;
        pb.inc(batch.samples.len() as u64);
    }
    pb.finish_and_clear();
    let result = filter
        .finish()
        .with_context(|| format!("{}: calibration failed", info.path.display()))?;
    let description = format!(
        "{}-state system-level calibration of {} ({} filter updates, {:.2} h)",
        model.n_states(),
        info.path.display(),
        result.updates,
        (result.filter_end_s - result.filter_start_s) / 3600.0
    );
    // The three files are written into a staging directory beside them and moved into place
    // together once all are complete: an interrupted or failed run leaves the previous ones.
    let staging = sins_files::Temporary::dir(&args.out).with_context(|| {
        format!(
            "cannot create a staging directory beside {}",
            args.out.display()
        )
    })?;
    let names = [&args.out, &history, &rrd].map(|p| {
        p.file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
    });
    let staged = |k: usize| staging.path().join(&names[k]);
    write_params(
        staged(0),
        &ParamSet {
            params: result.params,
            sigma: Some(result.sigma),
            description,
        },
    )
    .with_context(|| unchanged.clone())?;
    let curves = write_history(&staged(1), &result, model, args.reference_temperature_degc)
        .with_context(|| unchanged.clone())?;
    let series: Vec<sins_viz::Series<'_>> = curves
        .iter()
        .map(|(entity, points)| sins_viz::Series { entity, points })
        .collect();
    sins_viz::write_series(&staged(2), "calibration", &series)
        .with_context(|| unchanged.clone())?;
    sins_files::commit_files(staging, &names)
        .with_context(|| format!("cannot move the new files into place; {unchanged}"))?;
    print_result(&result)?;
    say!(
        "wrote {}, {} and {}",
        args.out.display(),
        history.display(),
        rrd.display()
    )?;
    Ok(())
}

/// `<stem>_history.parquet` beside the parameter file.
pub fn history_path(out: &Path) -> PathBuf {
    let stem = out
        .file_stem()
        .map_or("params".into(), |s| s.to_string_lossy().into_owned());
    out.with_file_name(format!("{stem}_history.parquet"))
}

fn print_result(r: &CalibrationResult) -> Result<()> {
    say!(
        "{:<8} {:>14} {:>12} {:<12} {:>10}",
        "coeff",
        "estimate",
        "1-sigma",
        "unit",
        "σ/σ0"
    )?;
    let est = coefficient_table(&r.params);
    let sig = coefficient_table(&r.sigma);
    for (k, (e, s)) in est.iter().zip(&sig).enumerate() {
        let ratio = r
            .observability
            .states
            .get(9 + k)
            .map_or(f64::NAN, |o| o.ratio);
        say!(
            "{:<8} {:>14.5} {:>12.5} {:<12} {:>10.4}",
            e.name,
            e.value,
            s.value,
            e.unit,
            ratio
        )?;
    }
    let weak = r.observability.weak_states();
    if weak.is_empty() {
        let worst = r
            .observability
            .states
            .iter()
            .map(|o| o.ratio)
            .fold(0.0, f64::max);
        say!("every state observable: the largest final/initial sigma ratio is {worst:.4}")
    } else {
        say!("weakly observable under this scheme: {}", weak.join(", "))
    }
}

/// One estimation curve for the Rerun log: entity path and `(t_s, value)` points.
type Curve = (String, Vec<(f64, f64)>);

/// Convergence history in the paper's units: `t_s`, then `<name>` and `<name>_sigma` per
/// coefficient. Returns the curves as `(entity path, (t_s, value))` for the Rerun log.
fn write_history(
    path: &Path,
    r: &CalibrationResult,
    model: ParamModel,
    reference_degc: f64,
) -> Result<Vec<Curve>> {
    let n = r.history.len();
    let names: Vec<&str> = coefficient_table(&r.params)
        .iter()
        .map(|c| c.name)
        .collect();
    let mut values = vec![Vec::with_capacity(n); 2 * names.len()];
    for snap in &r.history {
        let est = coefficient_table(&params_from_vec(&snap.estimate, model, reference_degc));
        let sig = coefficient_table(&params_from_vec(&snap.sigma[9..], model, reference_degc));
        for (k, (e, s)) in est.iter().zip(&sig).enumerate() {
            values[2 * k].push(e.value);
            values[2 * k + 1].push(s.value);
        }
    }
    let times: Vec<f64> = r.history.iter().map(|s| s.t_s).collect();
    let units: Vec<&str> = coefficient_table(&r.params)
        .iter()
        .map(|c| c.unit)
        .collect();
    let mut curves = Vec::with_capacity(2 * names.len());
    for (k, name) in names.iter().enumerate() {
        let unit = units[k].replace('/', "_per_");
        for (suffix, col) in [("estimate", &values[2 * k]), ("sigma", &values[2 * k + 1])] {
            let pts = times.iter().copied().zip(col.iter().copied()).collect();
            curves.push((format!("calibration/{name}_{unit}/{suffix}"), pts));
        }
    }
    let mut columns = Vec::with_capacity(2 * names.len());
    for (k, name) in names.iter().enumerate() {
        columns.push((name.to_string(), std::mem::take(&mut values[2 * k])));
        columns.push((
            format!("{name}_sigma"),
            std::mem::take(&mut values[2 * k + 1]),
        ));
    }
    sins_report::frames::write_calibration_history(path, times, columns)?;
    Ok(curves)
}
