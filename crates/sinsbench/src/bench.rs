//! `sinsbench bench`: the figures the issues ask for, each step in a child process so that its
//! wall time and peak memory are its own.

use crate::child::{Measured, child};
use crate::defaults;
use crate::out::say;
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// Arguments of `bench`.
#[derive(clap::Args)]
pub struct Args {
    /// Working directory for the benchmark datasets (about 1 GB per 15 h dataset).
    #[arg(long, default_value = "out/bench")]
    pub dir: PathBuf,
    /// Keep the datasets afterwards.
    #[arg(long)]
    pub keep: bool,
    /// Skip the error-free floor (four extra 15 h replays).
    #[arg(long)]
    pub no_floor: bool,
    /// Skip the replica-uq step (a short study: 4 main samples, 2 per candidate).
    #[arg(long)]
    pub no_uq: bool,
    /// Skip the import step (a 15 h recording as CSV text and as binary records, about 2.6 GB
    /// of scratch files, against reading the project's own CSV).
    #[arg(long)]
    pub no_import: bool,
    /// Instead of the steps above, measure the cost per sample of the replay and of the
    /// diagnosis of one run at 1.5, 15 and 150 h (200 Hz) and at 100, 200, 400 and 1000 Hz
    /// (1.5 h), with peak memory: about 10 min on 2 cores and a 5.7 GB file for 150 h.
    #[arg(long)]
    pub scaling: bool,
}

fn p(path: &Path) -> String {
    path.display().to_string()
}

/// Run the benchmark and print its figures.
pub fn run(args: Args, _quiet: bool) -> Result<()> {
    let exp = defaults::experiments_dir();
    std::fs::create_dir_all(&args.dir)?;
    say!(
        "sinsbench bench ({} logical CPUs)",
        std::thread::available_parallelism().map_or(0, |n| n.get())
    )?;

    if args.scaling {
        crate::bench_scaling::run(&args.dir, &exp)?;
        if !args.keep {
            let _ = std::fs::remove_dir_all(&args.dir);
        }
        return Ok(());
    }
    let nav_exp = exp.join("paper_navigation.toml");
    let m = child(&[
        "simulate",
        &p(&nav_exp),
        "--run",
        "nav1",
        "--out",
        &p(&args.dir),
    ])?;
    child(&[
        "simulate",
        &p(&nav_exp),
        "--run",
        "nav2",
        "--run",
        "nav3",
        "--out",
        &p(&args.dir),
    ])?;
    let dataset = args.dir.join("nav1.parquet");
    let bytes = std::fs::metadata(&dataset).map(|m| m.len()).unwrap_or(0);
    say!(
        "simulate 15 h / 200 Hz (10.8 M samples, noise, thermal, Parquet): {:.2} s wall, peak RSS {:.0} MB, file {:.0} MB",
        m.wall_s,
        m.peak_rss_mb,
        bytes as f64 / 1e6
    )?;

    let truth = exp.join("imu/paper_truth.toml");
    let m = child(&[
        "navigate",
        "--dataset",
        &p(&dataset),
        "--params",
        &p(&truth),
    ])?;
    say!(
        "replay 15 h / 200 Hz (Parquet decode + 42-state compensation + alignment + reconstruction + mechanization): {:.2} s wall, peak RSS {:.0} MB",
        m.wall_s,
        m.peak_rss_mb
    )?;
    say_indented(&m.stdout)?;
    if !args.no_import {
        crate::bench_import::run(&args.dir, &exp, &nav_exp)?;
    }

    // The navigation runs' own IMU (Table 1 constants + Table 3 temperature coefficients).
    let cal_exp = exp.join("paper_truth_calibration.toml");
    let cal_dir = args.dir.join("calibration");
    child(&["simulate", &p(&cal_exp), "--out", &p(&cal_dir)])?;
    let cal = cal_dir.join("truth_cal1.parquet");
    let params_out = args.dir.join("cal1_42.toml");
    let m = calibrate_42(&cal, &params_out)?;
    say!(
        "calibrate 4.2 h / 200 Hz with the 42-state filter (Parquet decode + alignment + filter, 1 s updates, history and .rrd): {:.2} s wall, peak RSS {:.0} MB",
        m.wall_s,
        m.peak_rss_mb
    )?;

    let m = child(&[
        "noise",
        "--dataset",
        &p(&dataset),
        "--params",
        &p(&params_out),
        "--out",
        &p(&args.dir.join("noise")),
    ])?;
    say!(
        "noise identification 15 h / 200 Hz (accelerometers compensated with the 42-state set, Allan deviation of the 7 h stationary, fit, noise.toml, Allan PNG, .rrd): {:.2} s wall, peak RSS {:.0} MB",
        m.wall_s,
        m.peak_rss_mb
    )?;

    let m = diagnose_set(&cal, &args.dir, &params_out, &args.dir.join("diagnosis"))?;
    say!(
        "diagnose one set (4.2 h calibration run + three 15 h navigation runs: Parquet, noise identification, replays, sensitivities, twin, fits, time-local scan, validation, report): {:.1} s wall, peak RSS {:.0} MB",
        m.wall_s,
        m.peak_rss_mb
    )?;
    say_indented(&m.stdout)?;

    gap_set(&args.dir, &exp)?;

    // One thread first (each run after the other, as before the runs were put side by side),
    // then the default: the same summary, the wall time of each.
    let one = child(&[
        "report",
        "--threads",
        "1",
        "--reports-dir",
        &p(&args.dir.join("reports-1")),
    ])?;
    let m = child(&["report", "--reports-dir", &p(&args.dir.join("reports"))])?;
    say!(
        "report (default replica: two 4.2 h calibration runs simulated (ramp, stable 20 degC) + 42-state and two 30-state filters, 3 x 15 h simulated + replayed under the 3 sets, Table 5 as a prediction from the shipped study, plots, .rrd): {:.1} s wall, peak RSS {:.0} MB (the runs side by side, --threads 3; one after the other, --threads 1: {:.1} s, {:.0} MB)",
        m.wall_s,
        m.peak_rss_mb,
        one.wall_s,
        one.peak_rss_mb
    )?;
    say_indented(&m.stdout)?;

    if !args.no_uq {
        uq_step(&args.dir)?;
    }

    if !args.no_floor {
        let floor_exp = exp.join("error_free_navigation.toml");
        let floor_dir = args.dir.join("floor");
        let m = child(&["simulate", &p(&floor_exp), "--out", &p(&floor_dir)])?;
        say!("simulate error-free 15 h: {:.2} s", m.wall_s)?;
        let file = std::fs::read_dir(&floor_dir)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .find(|f| f.extension().is_some_and(|x| x == "parquet"))
            .context("the error-free experiment wrote no dataset")?;
        for algorithm in ["reconstruct", "two-sample", "one-plus-previous"] {
            let args = [
                "navigate",
                "--dataset",
                &p(&file),
                "--start",
                "truth",
                "--algorithm",
                algorithm,
            ];
            let m = child(&args)?;
            say!(
                "error-free floor at 200 Hz, {algorithm} ({:.2} s replay):",
                m.wall_s
            )?;
            say_indented(&m.stdout)?;
        }
    }
    if !args.keep {
        let _ = std::fs::remove_dir_all(&args.dir);
    }
    Ok(())
}

/// A short `replica-uq` study (the default assumptions, 4 main samples and 2 per candidate):
/// time per sample and the projected wall time of the default study.
fn uq_step(dir: &Path) -> Result<()> {
    let exp = defaults::experiments_dir().join("replica/assumptions.toml");
    let text = std::fs::read_to_string(&exp).with_context(|| p(&exp))?;
    let candidates = text.matches("[[candidate]]").count();
    let default_main: usize = text
        .lines()
        .find_map(|l| {
            l.trim()
                .strip_prefix("samples = ")
                .and_then(|v| v.trim().parse().ok())
        })
        .unwrap_or(0);
    let jobs = 1 + 4 + 2 * candidates;
    let out = dir.join("uq");
    let m = child(&[
        "replica-uq",
        "--samples",
        "4",
        "--candidate-samples",
        "2",
        "--out",
        &p(&out),
    ])?;
    let per = m.wall_s / jobs as f64;
    let default_jobs = 1 + default_main + 6 * candidates;
    say!(
        "replica-uq short study ({jobs} samples on 2 threads: each a 4.2 h calibration run, 30- and 42-state filters, 3 x 15 h simulated + replayed twice): {:.1} s wall, {per:.1} s per sample, peak RSS {:.0} MB; the default study ({default_jobs} samples) projects to {:.1} min",
        m.wall_s,
        m.peak_rss_mb,
        per * default_jobs as f64 / 60.0
    )?;
    Ok(())
}

/// The hidden effect of the large-gap benchmark set: an 8 mm x-accelerometer lever arm, which
/// rectifies Table 4's vibration into a few hundred km of error and needs the nonlinear
/// refinement (the slowest path of `diagnose`).
const GAP_EFFECT: &str =
    "[[imu.effect]]\nkind = \"size_effect\"\nlever_arm_x_mm = [-8.0, 0.0, 0.0]\n";

/// Calibrate and diagnose a set whose "real" IMU has an unmodelled effect, so the diagnosis
/// finds a large gap, ranks, refines and validates: the 2-minute target's worst case.
fn gap_set(dir: &Path, exp: &Path) -> Result<()> {
    let gap_dir = dir.join("gap");
    std::fs::create_dir_all(&gap_dir)?;
    let effects = gap_dir.join("effect.toml");
    std::fs::write(&effects, GAP_EFFECT)?;
    for experiment in ["paper_truth_calibration.toml", "paper_navigation.toml"] {
        child(&[
            "simulate",
            &p(&exp.join(experiment)),
            "--effects",
            &p(&effects),
            "--out",
            &p(&gap_dir),
        ])?;
    }
    let cal = gap_dir.join("truth_cal1.parquet");
    let params = gap_dir.join("cal1_42.toml");
    calibrate_42(&cal, &params)?;
    let m = diagnose_set(&cal, &gap_dir, &params, &gap_dir.join("diagnosis"))?;
    say!(
        "diagnose one set with a large gap (same four runs, hidden -8 mm x-accelerometer lever arm: ranking, nonlinear refinement, validation): {:.1} s wall, peak RSS {:.0} MB",
        m.wall_s,
        m.peak_rss_mb
    )?;
    say_indented(&m.stdout)?;
    Ok(())
}

/// `sinsbench calibrate` of dataset `cal` with the 42-state filter into `out`.
fn calibrate_42(cal: &Path, out: &Path) -> Result<Measured> {
    child(&[
        "calibrate",
        "--dataset",
        &p(cal),
        "--states",
        "42",
        "--out",
        &p(out),
    ])
}

/// `diagnose` on calibration run `cal` and `nav_dir`'s nav1-nav3 under `params`, into `out`.
fn diagnose_set(cal: &Path, nav_dir: &Path, params: &Path, out: &Path) -> Result<Measured> {
    let mut args = vec!["diagnose".to_string()];
    let runs = ["nav1", "nav2", "nav3"].map(|n| (n, nav_dir.join(format!("{n}.parquet"))));
    for (name, file) in std::iter::once(("cal", cal.to_path_buf())).chain(runs) {
        args.push("--dataset".into());
        args.push(format!("{name}={}", p(&file)));
    }
    for a in ["--params", &p(params), "--out", &p(out)] {
        args.push(a.to_string());
    }
    child(&args.iter().map(String::as_str).collect::<Vec<_>>())
}

/// Print a child's output indented by four spaces.
fn say_indented(s: &str) -> Result<()> {
    s.lines().try_for_each(|l| say!("    {l}"))
}
