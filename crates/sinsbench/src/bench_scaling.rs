//! `sinsbench bench --scaling`: the cost of the replay and of the diagnosis against the work
//! they do. The paper's first navigation run is stretched to 1.5 h, 15 h and 150 h at 200 Hz and
//! sampled at 100, 200, 400 and 1000 Hz over 1.5 h; each point is simulated, replayed and
//! diagnosed in its own process, and the table gives the time per sample and the peak memory.
//! A cost per sample that grows with the data is a defect to find.

use crate::child::child;
use crate::out::say;
use anyhow::{Context, Result, bail};
use std::path::Path;

/// The paper's 15 h run (s) and its alignment dwell (s), which every point keeps.
const PAPER_RUN_S: f64 = 54_000.0;
const ALIGNMENT_S: f64 = 1_200.0;

/// The points of the table: (duration in hours, sample rate in Hz).
const POINTS: [(f64, f64); 6] = [
    (1.5, 200.0),
    (15.0, 200.0),
    (150.0, 200.0),
    (1.5, 100.0),
    (1.5, 400.0),
    (1.5, 1000.0),
];

/// `paper_navigation.toml`'s text (`text`, read from directory `exp_dir`) as a one-run
/// experiment of `hours` at `rate_hz`: the alignment dwell kept at 20 min, every other motion
/// segment stretched by the same factor, run `nav1`'s chamber history stretched to the new
/// length with the same total temperature drop, and the referenced files made absolute.
pub fn scaled_experiment(text: &str, exp_dir: &Path, hours: f64, rate_hz: f64) -> Result<String> {
    let mut doc: toml::Table = text.parse().context("paper_navigation.toml")?;
    let total_s = hours * 3600.0;
    if total_s <= ALIGNMENT_S {
        bail!("a scaled run must be longer than its {ALIGNMENT_S} s alignment");
    }
    let stretch = (total_s - ALIGNMENT_S) / (PAPER_RUN_S - ALIGNMENT_S);
    let table = |d: &mut toml::Table, k: &str| -> Result<toml::Table> {
        d.get(k)
            .and_then(|v| v.as_table())
            .cloned()
            .with_context(|| format!("paper_navigation.toml has no [{k}]"))
    };
    doc.insert(
        "name".into(),
        format!("scaling_{hours}h_{rate_hz}hz").into(),
    );
    let mut sampling = table(&mut doc, "sampling")?;
    sampling.insert("rate_hz".into(), rate_hz.into());
    doc.insert("sampling".into(), sampling.into());
    let exp_dir = std::path::absolute(exp_dir)?;
    let absolute = |rel: &str| exp_dir.join(rel).display().to_string();
    let mut imu = table(&mut doc, "imu")?;
    let truth = imu
        .get("truth")
        .and_then(|v| v.as_str())
        .context("imu.truth")?;
    imu.insert("truth".into(), absolute(truth).into());
    doc.insert("imu".into(), imu.into());
    let mut motion = table(&mut doc, "motion")?;
    if let Some(p) = motion.get("vibration_patterns").and_then(|v| v.as_str()) {
        let p = absolute(p);
        motion.insert("vibration_patterns".into(), p.into());
    }
    let segments = motion
        .get_mut("segment")
        .and_then(|v| v.as_array_mut())
        .context("motion.segment")?;
    for (i, seg) in segments.iter_mut().enumerate() {
        let seg = seg.as_table_mut().context("motion.segment")?;
        let s = seconds(seg).with_context(|| format!("motion.segment[{i}]: no duration"))?;
        let new_s = if i == 0 { s } else { s * stretch };
        seg.remove("duration_h");
        seg.insert("duration_s".into(), new_s.into());
    }
    doc.insert("motion".into(), motion.into());
    let runs = doc
        .get_mut("run")
        .and_then(|v| v.as_array_mut())
        .context("run")?;
    runs.retain(|r| r.get("name").and_then(|n| n.as_str()) == Some("nav1"));
    let run = runs
        .first_mut()
        .context("paper_navigation.toml has no run nav1")?;
    let chamber = run
        .get_mut("thermal")
        .and_then(|t| t.get_mut("chamber"))
        .and_then(|c| c.as_array_mut())
        .context("run nav1 has no thermal.chamber")?;
    let chamber_s: f64 = chamber
        .iter()
        .filter_map(|c| c.as_table().and_then(seconds))
        .sum();
    let factor = total_s / chamber_s;
    for c in chamber.iter_mut() {
        let c = c.as_table_mut().context("thermal.chamber")?;
        let s = seconds(c).context("thermal.chamber: no duration")?;
        c.remove("duration_h");
        c.insert("duration_s".into(), (s * factor).into());
        if let Some(r) = c.get("rate_degc_per_h").and_then(|v| v.as_float()) {
            c.insert("rate_degc_per_h".into(), (r / factor).into());
        }
    }
    Ok(toml::to_string(&doc)?)
}

/// A segment's `duration_s` or `duration_h`, in seconds.
fn seconds(t: &toml::Table) -> Option<f64> {
    let num = |v: &toml::Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
    t.get("duration_s")
        .and_then(num)
        .or_else(|| t.get("duration_h").and_then(num).map(|h| h * 3600.0))
}

/// Simulate, replay and diagnose every point and print the table.
pub fn run(dir: &Path, exp: &Path) -> Result<()> {
    let text = std::fs::read_to_string(exp.join("paper_navigation.toml"))?;
    let truth = exp.join("imu/paper_truth.toml").display().to_string();
    let dir = dir.join("scaling");
    std::fs::create_dir_all(&dir)?;
    let p = |x: &Path| x.display().to_string();
    say!(
        "scaling: run nav1 of the paper's navigation experiment stretched or resampled; replay = `navigate` under the truth set, diagnosis = `diagnose` of that one run (noise identified from its stationary segments, no calibration run); ns per sample = wall / samples"
    )?;
    say!(
        "  {:>7} {:>7} {:>11} | {:>9} {:>11} {:>8} | {:>9} {:>11} {:>8}",
        "hours",
        "Hz",
        "samples",
        "replay s",
        "ns/sample",
        "RSS MB",
        "diag s",
        "ns/sample",
        "RSS MB"
    )?;
    for (hours, rate_hz) in POINTS {
        let name = format!("{hours}h_{rate_hz}hz");
        let exp_file = dir.join(format!("{name}.toml"));
        std::fs::write(&exp_file, scaled_experiment(&text, exp, hours, rate_hz)?)?;
        let out = dir.join(&name);
        child(&["simulate", &p(&exp_file), "--out", &p(&out)])?;
        let data = out.join("nav1.parquet");
        let replay = child(&["navigate", "--dataset", &p(&data), "--params", &truth])?;
        let diag = child(&[
            "diagnose",
            "--dataset",
            &format!("nav1={}", p(&data)),
            "--params",
            &truth,
            "--out",
            &p(&out.join("diagnosis")),
        ])?;
        let samples = (hours * 3600.0 * rate_hz).round();
        say!(
            "  {hours:>7} {rate_hz:>7} {samples:>11} | {:>9.2} {:>11.1} {:>8.0} | {:>9.1} {:>11.1} {:>8.0}",
            replay.wall_s,
            replay.wall_s / samples * 1e9,
            replay.peak_rss_mb,
            diag.wall_s,
            diag.wall_s / samples * 1e9,
            diag.peak_rss_mb
        )?;
        // 150 h at 200 Hz is a 5.7 GB file: keep only what the next point needs.
        let _ = std::fs::remove_file(&data);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scaled experiment loads, lasts the asked time at the asked rate, and its chamber
    /// trend falls by the paper run's 20 degC over the whole run whatever its length.
    #[test]
    fn a_scaled_run_lasts_the_asked_time_with_the_papers_temperature_drop() {
        let exp = crate::defaults::experiments_dir();
        let text = std::fs::read_to_string(exp.join("paper_navigation.toml")).unwrap();
        let dir = std::env::temp_dir().join(format!("sinsbench-scaling-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (hours, rate) in [(1.5, 1000.0), (150.0, 200.0)] {
            let file = dir.join("x.toml");
            std::fs::write(&file, scaled_experiment(&text, &exp, hours, rate).unwrap()).unwrap();
            let e = sins_config::load_experiment(&file).unwrap();
            assert_eq!(e.scenarios.len(), 1);
            let s = &e.scenarios[0];
            assert_eq!(s.rate_hz, rate);
            use sins_sim::scenario::MotionSegment as M;
            let total: f64 = (s.motion.segments.iter())
                .map(|m| match m {
                    M::Dwell { duration_s, .. } | M::Vibrate { duration_s, .. } => *duration_s,
                    M::Rotate { .. } => 0.0,
                })
                .sum();
            assert!((total - hours * 3600.0).abs() < 1e-6 * total, "{total}");
            let drop: f64 = s
                .thermal
                .chamber
                .iter()
                .map(|c| c.trend_change_degc())
                .sum();
            assert!((drop + 20.0).abs() < 1e-9, "{drop}");
            let chamber_s: f64 = s
                .thermal
                .chamber
                .iter()
                .map(|c| match c {
                    sins_sim::scenario::ChamberSegment::Hold { duration_s, .. }
                    | sins_sim::scenario::ChamberSegment::Ramp { duration_s, .. }
                    | sins_sim::scenario::ChamberSegment::Fluctuating { duration_s, .. } => {
                        *duration_s
                    }
                })
                .sum();
            assert!((chamber_s - total).abs() < 1e-6 * total, "{chamber_s}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
