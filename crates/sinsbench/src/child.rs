//! Running `sinsbench` itself as a child process with its wall time and peak memory: the
//! steps of `bench` each in their own process, so that their figures are their own.

use anyhow::{Context, Result, bail};
use std::process::Command;

/// A child's wall time, peak memory and output.
pub(crate) struct Measured {
    pub wall_s: f64,
    pub peak_rss_mb: f64,
    pub stdout: String,
}

/// Run `sinsbench ARGS --quiet --stats` and measure it.
pub(crate) fn child(args: &[&str]) -> Result<Measured> {
    let exe = std::env::current_exe().context("cannot find the sinsbench executable")?;
    let out = Command::new(exe)
        .args(args)
        .args(["--quiet", "--stats"])
        .output()?;
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    if !out.status.success() {
        bail!("sinsbench {} failed:\n{stderr}", args.join(" "));
    }
    let line = stderr
        .lines()
        .rev()
        .find(|l| l.starts_with("stats:"))
        .context("child printed no stats line")?;
    let field = |k: &str| -> f64 {
        line.split_whitespace()
            .find_map(|f| f.strip_prefix(k))
            .and_then(|v| v.parse().ok())
            .unwrap_or(f64::NAN)
    };
    Ok(Measured {
        wall_s: field("wall_s="),
        peak_rss_mb: field("peak_rss_mb="),
        stdout: String::from_utf8_lossy(&out.stdout).to_string(),
    })
}
