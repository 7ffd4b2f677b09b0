//! `sinsbench navigate`: replay one dataset under one parameter set.

use crate::out::say;
use crate::{argcheck, progress};
use anyhow::{Context, Result};
use sins_data::{DatasetInfo, DatasetReader};
use sins_harness::pipeline::NamedParams;
use sins_imu::{ImuErrorParams, ParamModel};
use sins_nav::{ConingOrder, Euler, NMI_M, NavState, ned_from_body_euler};
use sins_replay::setup::{ReplayOptions, StartMode as HarnessStart, VerticalMode};
use sins_replay::{ErrorPoint, ReplaySummary};
use std::path::PathBuf;

/// Arguments of `navigate`.
#[derive(clap::Args, Clone)]
pub struct Args {
    /// Dataset to replay (Parquet or CSV in the sinsbench format; see README).
    #[arg(long)]
    pub dataset: PathBuf,
    /// Parameter set to compensate with (TOML/JSON in the paper's units). Default: none (the
    /// raw increments are used as they are).
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// How navigation starts: `align` = 20 min stationary self-alignment on the data itself;
    /// `truth` = the initial attitude recorded in the dataset's metadata (simulated data).
    #[arg(long, value_enum, default_value_t = StartMode::Align)]
    pub start: StartMode,
    /// Replay from this time (s, the dataset's own `t_s`): samples before it are not used, and
    /// the self-alignment starts here (e.g. on a still stretch that `noise` found).
    #[arg(long, allow_negative_numbers = true)]
    pub start_s: Option<f64>,
    /// Self-alignment time (s, positive).
    #[arg(long, default_value_t = 1200.0, allow_negative_numbers = true, value_parser = argcheck::positive_f64)]
    pub align_s: f64,
    /// Attitude/velocity increment algorithm. `reconstruct` (default): high-order look-ahead
    /// reconstruction (6th-order Magnus on a 13-sample interpolation of the increments), whose
    /// error-free floor over the paper's 15 h vibration experiment at 200 Hz is 0.3 m. The
    /// classical coning/sculling algorithms (`one-plus-previous`, `two-sample`, `three-sample`,
    /// `four-sample`) drift by up to 1.7 deg/h under Table 4's pattern 3 at 200 Hz.
    #[arg(long, value_enum, default_value_t = Algorithm::Reconstruct)]
    pub algorithm: Algorithm,
    /// Vertical channel: held at the site height (default, turntable runs), damped, or free.
    #[arg(long, value_enum, default_value_t = Vertical::Hold)]
    pub vertical: Vertical,
    /// Worker threads of the reconstruction (results are identical for any count).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(1..=16))]
    pub threads: u8,
    /// Write errors.parquet (1 Hz error track) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Navigation start.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum StartMode {
    /// Stationary self-alignment (coarse + zero-velocity Kalman filter).
    Align,
    /// Start from the recorded initial attitude at rest at the site.
    Truth,
}

/// Vertical channel option.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Vertical {
    /// Height held at the site height.
    Hold,
    /// Second-order damping to the site height (100 s).
    Damped,
    /// Pure inertial (diverges).
    Free,
}

/// Increment algorithm option.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Algorithm {
    /// High-order look-ahead reconstruction (default).
    Reconstruct,
    /// One sample plus the previous one (1/12 cross products).
    OnePlusPrevious,
    /// Classic two-sample coning/sculling.
    TwoSample,
    /// Three-sample coning/sculling.
    ThreeSample,
    /// Four-sample coning/sculling.
    FourSample,
}

impl Algorithm {
    /// The mechanization setting.
    pub fn coning_order(self) -> ConingOrder {
        match self {
            Algorithm::Reconstruct => ConingOrder::Reconstruct,
            Algorithm::OnePlusPrevious => ConingOrder::OnePlusPrevious,
            Algorithm::TwoSample => ConingOrder::TwoSample,
            Algorithm::ThreeSample => ConingOrder::ThreeSample,
            Algorithm::FourSample => ConingOrder::FourSample,
        }
    }
}

/// Run `navigate`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    if let Some(dir) = &args.out {
        crate::outputs::create_dir_target(dir, "output")?;
        crate::outputs::check_file_target(&dir.join("errors.parquet"), "error track")?;
        crate::outputs::sweep(dir);
    }
    let (info, points, summary) = replay(&args, quiet)?;
    print_summary(&info, &summary)?;
    if let Some(dir) = &args.out {
        let path = dir.join("errors.parquet");
        write_errors(&path, &info, &points)?;
        say!("wrote {}", path.display())?;
    }
    Ok(())
}

/// Replay a dataset; returns its info, the 1 Hz error track and the summary.
pub fn replay(args: &Args, quiet: bool) -> Result<(DatasetInfo, Vec<ErrorPoint>, ReplaySummary)> {
    let coarse_s = sins_nav::AlignmentConfig::default().coarse_duration_s;
    if matches!(args.start, StartMode::Align) && args.align_s < coarse_s {
        anyhow::bail!(
            "--align-s {}: the self-alignment starts with {coarse_s} s of coarse alignment, so it \
             needs at least {coarse_s} s (give --align-s {coarse_s} or more, or --start truth)",
            args.align_s
        );
    }
    let info = DatasetReader::open(&args.dataset)?.info().clone();
    if matches!(args.start, StartMode::Align) {
        check_alignment_still(args)?;
    }
    let params = match &args.params {
        Some(p) => sins_config::load_params(p)?.params,
        None => ImuErrorParams::ideal(ParamModel::States30),
    };
    let options = ReplayOptions {
        coning: args.algorithm.coning_order(),
        vertical: match args.vertical {
            Vertical::Hold => VerticalMode::Hold,
            Vertical::Damped => VerticalMode::Damped { tau_s: 100.0 },
            Vertical::Free => VerticalMode::Free,
        },
        start: match args.start {
            StartMode::Align => HarnessStart::Align(sins_nav::AlignmentConfig {
                duration_s: args.align_s,
                ..sins_nav::AlignmentConfig::default()
            }),
            StartMode::Truth => HarnessStart::Known(NavState::at_rest(
                0.0,
                ned_from_body_euler(&initial_attitude(&info)?),
                info.meta.site,
            )),
        },
        reconstruct: sins_nav::reconstruct::ReconstructConfig {
            threads: args.threads as usize,
            ..Default::default()
        },
        output_interval_s: 1.0,
        stamped_intervals: info.meta.recorded_stamps(),
        start_s: args.start_s,
    };
    let set = NamedParams {
        key: args
            .params
            .as_ref()
            .map_or("none".to_string(), |p| p.display().to_string()),
        params,
    };
    let name = args
        .dataset
        .file_stem()
        .map_or("dataset".to_string(), |s| s.to_string_lossy().into_owned());
    let mut bars = progress::Bars::new(quiet);
    let outcome = sins_report::replay_dataset(&name, &args.dataset, &[set], &options, &mut bars)?;
    let track = outcome
        .tracks
        .into_iter()
        .next()
        .context("internal: the replay returned no track")?;
    Ok((info, track.points, track.summary))
}

/// Gross motion that refuses a self-alignment: the IMU turned through more than this angle
/// (rad; 1 deg: a vehicle turning, a hand moving the IMU)...
const ALIGN_REFUSE_ANGLE_RAD: f64 = std::f64::consts::PI / 180.0;
/// ...or its velocity changed by more than this (m/s; a vehicle driving off). Rocking below
/// both (a parked vehicle in the wind, an idling engine: back and forth) is reported and the
/// alignment goes on: it averages over the window.
const ALIGN_REFUSE_VELOCITY_MPS: f64 = 0.5;

/// Check the alignment window for motion with the stillness detector (at
/// [`sins_gap::still::ALIGNMENT_FALSE_ALARMS_PER_HOUR`]): gross motion refuses the alignment,
/// naming it and the still stretches long enough for it; smaller motion is reported.
fn check_alignment_still(args: &Args) -> Result<()> {
    let cfg = sins_noiseid::StillnessConfig {
        false_alarms_per_hour: sins_gap::still::ALIGNMENT_FALSE_ALARMS_PER_HOUR,
        ..Default::default()
    };
    // Without --start-s only the alignment window (and a minute more) is read.
    let span = args.start_s.is_none().then_some(args.align_s + 60.0);
    let found = sins_gap::still::dataset_stillness(&args.dataset, &cfg, span)?;
    let t_first = found.windows.first().map_or(0.0, |w| w.start_s);
    let from = args.start_s.unwrap_or(t_first).max(t_first);
    let to = from + args.align_s;
    let inside: Vec<&sins_noiseid::MotionReport> = found
        .stillness
        .motion
        .iter()
        .filter(|m| m.end_s > from && m.start_s < to)
        .collect();
    let gross = |m: &&sins_noiseid::MotionReport| {
        m.excursion
            > if m.channel.starts_with("gyro") {
                ALIGN_REFUSE_ANGLE_RAD
            } else {
                ALIGN_REFUSE_VELOCITY_MPS
            }
    };
    let size = |m: &sins_noiseid::MotionReport| {
        if m.channel.starts_with("gyro") {
            format!(
                "rate {:.1} deg/h, turned through {:.3} deg, vibration {:.1} deg/h RMS",
                m.size.to_degrees() * 3600.0,
                m.excursion.to_degrees(),
                m.vibration.to_degrees() * 3600.0
            )
        } else {
            format!(
                "{:.0} ug, velocity change {:.3} m/s, vibration {:.0} ug RMS",
                m.size / sins_nav::UG,
                m.excursion,
                m.vibration / sins_nav::UG
            )
        }
    };
    let list = |ms: &[&sins_noiseid::MotionReport]| {
        let shown: Vec<String> = ms
            .iter()
            .take(8)
            .map(|m| {
                format!(
                    "{:.1}-{:.1} s ({} {})",
                    m.start_s,
                    m.end_s,
                    m.channel,
                    size(m)
                )
            })
            .collect();
        let more = ms.len().saturating_sub(8);
        format!(
            "{}{}",
            shown.join(", "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        )
    };
    let refused: Vec<&sins_noiseid::MotionReport> = inside.iter().copied().filter(gross).collect();
    if refused.is_empty() {
        if !inside.is_empty() {
            let moving_s: f64 = inside
                .iter()
                .map(|m| m.end_s.min(to) - m.start_s.max(from))
                .sum();
            crate::out::note!(
                "note: the IMU rocks inside the alignment window {from:.1}-{to:.1} s: {} stretch(es) \
                 of motion, {moving_s:.0} s in all, below the refusal limits (turned through 1 deg, a velocity change of 0.5 m/s): {}",
                inside.len(),
                list(&inside)
            );
        }
        return Ok(());
    }
    let whole = sins_gap::still::dataset_stillness(&args.dataset, &cfg, None)?;
    let still: Vec<String> = whole
        .still_stretches(args.align_s)
        .iter()
        .map(|(a, b)| format!("{a:.1}-{b:.1} s"))
        .collect();
    anyhow::bail!(
        "{}: the IMU moves inside the alignment window {from:.1}-{to:.1} s: {}; a self-alignment \
         needs it still (refused when it turns through more than 1 deg or changes velocity by\
         0.5 m/s). Still stretches of at least {} s: {} \
         (give --start-s at one of them, a shorter --align-s, or --start truth)",
        args.dataset.display(),
        list(&refused),
        args.align_s,
        if still.is_empty() {
            "none".to_string()
        } else {
            still.join(", ")
        }
    )
}

fn initial_attitude(info: &DatasetInfo) -> Result<Euler> {
    let get = |k: &str| -> Result<f64> {
        let v = info.meta.extra.get(k).with_context(|| {
            format!("{}: --start truth needs metadata key sinsbench.{k} (simulated datasets carry it); use --start align", info.path.display())
        })?;
        v.parse::<f64>().with_context(|| {
            format!(
                "{}: metadata sinsbench.{k} = '{v}' is not a number",
                info.path.display()
            )
        })
    };
    Ok(Euler::from_deg(
        get("initial_pitch_deg")?,
        get("initial_roll_deg")?,
        get("initial_yaw_deg")?,
    ))
}

fn label(info: &DatasetInfo, segment: u16) -> &str {
    info.segment_labels
        .get(segment as usize)
        .map_or("-", String::as_str)
}

/// Print the summary table of a replay.
pub fn print_summary(info: &DatasetInfo, s: &ReplaySummary) -> Result<()> {
    say!("{}", info.path.display())?;
    say!(
        "  max horizontal error {:.4} nmi ({:.1} m) at t = {:.2} h in '{}'; RMS {:.1} m; final {:.1} m; navigated {:.2} h",
        s.max_horizontal_nmi(),
        s.max_horizontal_m,
        s.t_max_s / 3600.0,
        label(info, s.segment_at_max),
        s.rms_horizontal_m,
        s.final_horizontal_m,
        s.navigated_s / 3600.0
    )?;
    for g in &s.segments {
        say!(
            "  segment {:<12} max {:>10.3} m ({:.5} nmi) at t = {:.2} h",
            label(info, g.segment),
            g.max_horizontal_m,
            g.max_horizontal_m / NMI_M,
            g.t_max_s / 3600.0
        )?;
    }
    Ok(())
}

fn write_errors(path: &std::path::Path, info: &DatasetInfo, points: &[ErrorPoint]) -> Result<()> {
    let dataset = info.path.display().to_string();
    sins_report::frames::write_error_track(path, &dataset, points, &info.segment_labels)?;
    Ok(())
}
