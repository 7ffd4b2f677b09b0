//! `sinsbench`: simulate, calibrate and replay a strapdown INS the way Wang et al. 2021 did,
//! with numbers you can trust. This binary is thin: every computation lives in the library
//! crates (`sins-nav`, `sins-imu`, `sins-sim`, `sins-replay`), every file format in
//! `sins-config` and `sins-data`.

// The argument structs' doc comments are the commands' `--help` text, which names placeholders
// as `<stem>`, `<run>`, `<NAME>`: plain text for clap, not HTML for rustdoc.
#![allow(rustdoc::invalid_html_tags)]

mod argcheck;
mod bench;
mod bench_import;
mod bench_scaling;
mod blind;
mod calibrate;
mod calreport;
mod campaign;
mod child;
mod defaults;
mod diagnose;
mod gate;
mod gate_power;
mod import;
mod malloc;
mod navigate;
mod noise;
mod out;
mod outputs;
mod progress;
mod report;
mod simulate;
mod stats;
mod uq;

use clap::{Parser, Subcommand};

/// Strapdown INS test harness after Wang et al. 2021 (laser gyros, quartz accelerometers,
/// 3-axis turntable in a thermal chamber).
///
/// Typical flow: `simulate` an experiment definition (TOML in experiments/) into datasets
/// (Parquet or CSV), then `navigate` a dataset with a parameter set to see how far pure
/// inertial navigation drifts. Frames: n = north-east-down, b = right-forward-up. Files carry
/// the paper's units (deg/h, ppm, arcsec, ug); everything inside is SI.
#[derive(Parser)]
#[command(name = "sinsbench", version, about, long_about)]
struct Cli {
    /// Print no progress bars (for CI logs).
    #[arg(long, global = true)]
    quiet: bool,
    /// Print wall time and peak resident memory when the command ends.
    #[arg(long, global = true)]
    stats: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate an experiment definition into one dataset per run.
    ///
    /// With no EXPERIMENT, simulates the paper's 15 h navigation experiment
    /// (experiments/paper_navigation.toml: three runs, 5 h stationary then vibration patterns
    /// 1-3 of Table 4 with 1 h stationary between, chamber temperature dropping) into
    /// out/paper_navigation/.
    Simulate(simulate::Args),
    /// Read a real recording as it comes (delimited text, fixed binary records or the PSINS
    /// .imu format; gzip or not) into a dataset, as a description file (TOML) says: columns,
    /// units (deg/s, g, counts with a scale, ...), rates or increments, axes (e.g. forward-
    /// right-down), time stamps or a counter, site, labels. Jittered stamps are accepted and
    /// their statistics printed; dropped samples are bridged up to time.max_bridge_samples
    /// (default 5) and listed; a longer gap is refused or splits the run. The dataset records
    /// the source's SHA-256, the description and every conversion. See docs/import.md.
    Import(import::Args),
    /// Replay a dataset: self-alignment (20 min) or a known start, then pure inertial
    /// navigation with a parameter set applied; prints the horizontal error.
    Navigate(navigate::Args),
    /// System-level calibration (the paper's 42- or 30-state Kalman filter) of a calibration
    /// dataset; writes the parameter set with 1-sigma and the convergence history.
    Calibrate(calibrate::Args),
    /// The paper's calibration study: Table 1 reproduced over Monte Carlo seeds (our estimate,
    /// residual and 1-sigma beside the paper's, NEES, observability ratios), the 30-state
    /// filter's temperature leak, and the four-temperature least-squares baseline against the
    /// 42-state filter (Table 3 with the truth). Writes reports/calibration/.
    CalibrationReport(calreport::Args),
    /// The paper's Table 5, end to end: with no arguments, simulate the truth IMU's
    /// calibration, calibrate it with the 30- and 42-state filters, simulate the three 15 h
    /// navigation runs, replay each under both parameter sets and write reports/paper_replica/
    /// (report.md, summary.json, PNG plots, one .rrd per run, error tracks). --config runs the
    /// same on your own parameter files and datasets.
    Report(report::Args),
    /// Release gate: check a report's summary.json against thresholds (maximum horizontal
    /// error per parameter set, minimum improvement). Exit code 0 = pass, 1 = a threshold is
    /// exceeded (one line per failure), 2 = bad input.
    Gate(gate::Args),
    /// Sim-to-real gap: replay real runs with their calibrated parameter set, compare them with
    /// the twin (identified model + noise model), localise the gap (segment, channel, time
    /// scale, first exit of the 3-sigma envelope), rank the catalogue of unmodelled effects by
    /// evidence, and measure how far the gap shrinks on withheld runs. Writes report.md,
    /// diagnosis.json, PNG plots and a .rrd.
    Diagnose(diagnose::Args),
    /// Identify the IMU's sensor noise from the stationary segments of its runs (Allan
    /// deviation and a fit of the twin's noise terms with 1-sigma); writes noise.toml (usable as
    /// `diagnose --noise-from`), allan.png, noise.rrd and noise.md.
    ///
    /// The Allan deviation σ_A(τ) is the standard deviation of the change between consecutive
    /// τ-long averages of a sensor's rate. Each noise process leaves its own slope on a log-log
    /// plot of σ_A against τ: quantization falls as 1/τ, white noise (gyro angle random walk
    /// ARW, accelerometer velocity random walk VRW) as 1/√τ; a Gauss-Markov bias (the 'bias
    /// instability', its correlation time T) rises as √τ below T, peaks at 0.62 σ near 1.9 T
    /// (the datasheet's bias-instability figure) and falls beyond; a rate random walk rises
    /// as √τ.
    ///
    /// `noise` computes the overlapping Allan deviation of the three gyros and three
    /// accelerometers over every stationary stretch of the given runs (the 20 min alignment and
    /// the stationary segments: the Earth rate and gravity are constant there and cancel),
    /// pools stretches and runs, and fits the terms of the twin's noise model with their
    /// 1-sigma; the gyro quantum is read off the increments when they are quantised. The twin
    /// of `diagnose` takes its spread from these terms (diagnose identifies them itself when
    /// no --noise-from is given). A correlation time longer than about a quarter of the longest
    /// stretch cannot be told from a rate random walk: the notes then say so.
    Noise(noise::Args),
    /// Blind validation of `diagnose`: cases with a hidden effect (or none, or one outside the
    /// catalogue) drawn at random, answers sealed with SHA-256 before the diagnoses run, then
    /// graded (top-1, false alarms, magnitudes, shrinkage, confusion table).
    Blind(blind::Args),
    /// Measure simulation and replay speed, peak memory and the error-free navigation floor.
    Bench(bench::Args),
    /// The replica of Table 5 as a validated prediction: a Monte Carlo over the declared
    /// assumptions (experiments/replica/assumptions.toml) and sensor-noise seeds; per cell the
    /// median, 5-95 % interval and their bootstrap errors, grouped Sobol indices, the ASME V&V 20
    /// comparison with the paper, Table 2 against the replica's spread, and the replica-vs-paper
    /// gap diagnosed (candidates chosen on some cells, judged on the withheld ones). Runs in one
    /// process or as shards (--shard I/K) with the same result. Writes reports/replica_uq/.
    ReplicaUq(uq::Args),
    /// Campaigns of independent runs (blind suite, calibration Monte Carlo, replica UQ, a list
    /// of reports; experiments/campaigns/*.toml) split into shards by a fixed rule: `plan` a
    /// directory, run each `shard` anywhere that sees it (one process, Slurm array tasks via
    /// scripts/slurm-campaign, Kubernetes indexed jobs), then `reduce`; or `local` for all of it
    /// on this machine. The summary is byte-identical however the shards were run.
    Campaign(campaign::Args),
    /// Read and validate every row of a dataset (the import benchmark's baseline).
    #[command(hide = true)]
    ReadDataset {
        /// The dataset.
        file: std::path::PathBuf,
    },
}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    let started = std::time::Instant::now();
    if let Err(e) = outputs::install() {
        out::note!("error: {}", error_chain(&e));
        return std::process::ExitCode::from(2);
    }
    let result = match cli.command {
        Command::Simulate(a) => simulate::run(a, cli.quiet),
        Command::Import(a) => import::run(a, cli.quiet),
        Command::Navigate(a) => navigate::run(a, cli.quiet),
        Command::Calibrate(a) => calibrate::run(a, cli.quiet),
        Command::CalibrationReport(a) => calreport::run(a, cli.quiet),
        Command::Report(a) => report::run(a, cli.quiet),
        Command::Gate(a) => gate::run(a, cli.quiet),
        Command::Diagnose(a) => diagnose::run(a, cli.quiet),
        Command::Noise(a) => noise::run(a, cli.quiet),
        Command::Blind(a) => blind::run(a, cli.quiet),
        Command::Bench(a) => bench::run(a, cli.quiet),
        Command::ReplicaUq(a) => uq::run(a, cli.quiet),
        Command::Campaign(a) => campaign::run(a, cli.quiet),
        Command::ReadDataset { file } => bench_import::read_dataset(&file),
    };
    // The output locks go with the process; their files go now (a run killed with SIGKILL
    // leaves its lock file, which blocks nothing).
    sins_files::lock::release_all();
    if cli.stats {
        stats::print(started.elapsed());
    }
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) if e.is::<gate::GateFailed>() => {
            out::note!("{e}");
            std::process::ExitCode::from(1)
        }
        Err(e) => {
            out::note!("error: {}", error_chain(&e));
            std::process::ExitCode::from(2)
        }
    }
}

/// The error and its causes on one line, leaving out causes whose text an outer message
/// already quotes (library errors often include their source in their own message).
fn error_chain(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in e.chain() {
        let c = cause.to_string();
        if text.contains(&c) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&c);
    }
    text
}
