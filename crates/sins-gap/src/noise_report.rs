//! The report of `sinsbench noise`: the identified terms as paper-unit tables, the data used
//! (runs, still stretches, motion left out), the warnings of an inconsistent model, the Allan
//! plot, and the directory `noise.toml` + `allan.png` + `noise.rrd` + `noise.md` written
//! aside and renamed into place.

use crate::GapError;
use sins_config::markdown::Table;
use sins_config::units::{DEG_PER_H_PER_SQRT_H, DEG_PER_SQRT_H, UG_PER_SQRT_H, UG_PER_SQRT_HZ};
use sins_nav::{ARCSEC, DEG_PER_H, UG};
use sins_noiseid::{Estimate, IdentifiedNoise, SensorNoise};
use sins_plot::{AllanPanel, AllanSeries, allan_figure};
use sins_report::ReportError;
use sins_sim::NoiseModel;
use sins_viz::AllanRecord;
use std::path::{Path, PathBuf};

/// A paper-unit figure with its 1-sigma (or upper bound).
fn fig(e: &Estimate, per_unit: f64, digits: usize) -> String {
    let v = e.value / per_unit;
    if e.value == 0.0 {
        return match e.upper_95 {
            Some(u) if u.is_finite() => format!("0 (< {:.*} at 95 %)", digits, u / per_unit),
            Some(_) => "0 (no finite 95 % bound: too little still data)".into(),
            None => "0".into(),
        };
    }
    if e.value.is_infinite() {
        return "inf".into();
    }
    if e.sigma.is_infinite() {
        return format!("{v:.digits$} (not identified)");
    }
    format!("{v:.digits$} ± {:.digits$}", e.sigma / per_unit)
}

/// The identified terms as `(term with its unit, figure ± 1-sigma)` rows in paper units: the
/// tables of `noise.md` and the lines `sinsbench noise` prints.
pub fn noise_rows(gyro: &SensorNoise, accel: &SensorNoise) -> Vec<(String, String)> {
    let (rrw_g, rrw_a) = (DEG_PER_H_PER_SQRT_H, UG_PER_SQRT_H);
    let mut r = vec![
        (
            "gyro angle random walk [deg/√h]".into(),
            fig(&gyro.white_per_sqrt_s, DEG_PER_SQRT_H, 6),
        ),
        (
            "gyro bias instability (Allan floor) [deg/h]".into(),
            fig(&gyro.bias_instability, DEG_PER_H, 6),
        ),
        (
            "gyro bias correlation time [s]".into(),
            fig(&gyro.bias_correlation_s, 1.0, 0),
        ),
        (
            format!(
                "gyro quantum [arcsec]{}",
                if gyro.quantum_from_lattice {
                    " (lattice of the increments)"
                } else {
                    ""
                }
            ),
            fig(&gyro.quantum, ARCSEC, 4),
        ),
        (
            "gyro rate random walk [deg/h/√h] (not in the twin)".into(),
            fig(&gyro.rate_random_walk_per_sqrt_s, rrw_g, 6),
        ),
        (
            "accel velocity random walk [ug/√Hz]".into(),
            fig(&accel.white_per_sqrt_s, UG_PER_SQRT_HZ, 3),
        ),
        (
            "accel bias instability (Allan floor) [ug]".into(),
            fig(&accel.bias_instability, UG, 3),
        ),
        (
            "accel bias correlation time [s]".into(),
            fig(&accel.bias_correlation_s, 1.0, 0),
        ),
        (
            "accel rate random walk [ug/√h] (not in the twin)".into(),
            fig(&accel.rate_random_walk_per_sqrt_s, rrw_a, 3),
        ),
    ];
    if accel.quantum_from_lattice {
        // Read off the lattice; its noise is part of the white velocity noise below.
        r.push((
            "accel quantum [mm/s] (lattice of the increments; not in the twin)".into(),
            fig(&accel.quantum, 1e-3, 4),
        ));
    }
    // White angle or velocity noise beyond the quantum (vibration, dither): bounded, reported.
    if gyro.quantum_from_lattice {
        r.push((
            "gyro white angle noise beyond the quantum [arcsec] (vibration; not in the twin)"
                .into(),
            fig(&gyro.white_phase, ARCSEC, 4),
        ));
    }
    r.push((
        "accel white velocity noise [mm/s] (vibration, quantisation; not in the twin)".into(),
        fig(&accel.white_phase, 1e-3, 4),
    ));
    r
}

/// One line with the twin's figures (for `diagnose`'s notes).
pub fn noise_one_line(id: &IdentifiedNoise) -> String {
    let r = noise_rows(&id.gyro, &id.accel);
    let pick = |k: usize| r.get(k).map_or(String::new(), |x| x.1.clone());
    format!(
        "gyro ARW {} deg/√h, bias instability {} deg/h (T {} s), quantum {} arcsec; accel VRW {} ug/√Hz, bias instability {} ug (T {} s); from {:.1} h stationary",
        pick(0),
        pick(1),
        pick(2),
        pick(3),
        pick(5),
        pick(6),
        pick(7),
        id.stationary_s() / 3600.0
    )
}

fn markdown(id: &IdentifiedNoise, datasets: &[(String, PathBuf)], seconds: f64) -> String {
    let mut md = String::from("# Sensor noise identified from stationary data\n\n");
    md.push_str("Overlapping Allan deviation (IEEE Std 952/1554) of every stationary stretch, pooled over stretches and runs; weighted (generalised) least-squares fit of the twin's terms; 1-sigma from the fit. `allan.png`: data with 68 % chi-square intervals, dashed the triad's fitted model.\n\n");
    let pooled = noise_rows(&id.gyro, &id.accel);
    let axes: Vec<Vec<(String, String)>> = (0..3)
        .filter_map(|a| Some(noise_rows(id.gyro_axes.get(a)?, id.accel_axes.get(a)?)))
        .collect();
    let mut terms = Table::new(["term", "triad (pooled)", "x", "y", "z"]);
    for (k, (term, v)) in pooled.iter().enumerate() {
        let mut cells = vec![term.clone(), v.clone()];
        // One cell per axis, empty where an axis was not identified.
        cells.extend((0..3).map(|a| {
            axes.get(a)
                .and_then(|r| r.get(k))
                .map_or(String::new(), |x| x.1.clone())
        }));
        terms.row(cells);
    }
    md.push_str(&terms.render());
    let mut data = Table::new(["run", "file", "stationary [h]", "stretches", "too short"]);
    for r in &id.runs {
        let file = datasets
            .iter()
            .find(|(n, _)| n == &r.name)
            .map_or(String::new(), |(_, p)| p.display().to_string());
        data.row([
            r.name.clone(),
            file,
            format!("{:.2}", r.stationary_s / 3600.0),
            r.stretches.to_string(),
            r.skipped.to_string(),
        ]);
    }
    md.push_str("\n## Data\n\n");
    md.push_str(&data.render());
    let mut means = Table::new([
        "run",
        "start [s]",
        "length [s]",
        "gyro - Earth rate [deg/h] x, y, z",
        "accel - (-g) [ug] x, y, z",
    ]);
    for s in &id.stretches {
        let f = |v: Option<[f64; 3]>, u: f64| {
            v.map_or("(alignment failed)".into(), |v| {
                format!("{:.4}, {:.4}, {:.4}", v[0] / u, v[1] / u, v[2] / u)
            })
        };
        means.row([
            s.run.clone(),
            format!("{:.0}", s.start_s),
            format!("{:.0}", s.duration_s),
            f(s.gyro_residual_radps, DEG_PER_H),
            f(s.accel_residual_mps2, UG),
        ]);
    }
    if !id.inconsistent.is_empty() {
        md.push_str("\n## The identified model is inconsistent with its data\n\nDo not trust a twin built on it (`diagnose --noise-from` says so in its verdict):\n\n");
        for r in &id.inconsistent {
            md.push_str(&format!("- {r}\n"));
        }
    }
    if !id.motion.is_empty() {
        let mut moved = Table::new([
            "run",
            "from [s]",
            "to [s]",
            "channel",
            "offset",
            "vibration (RMS)",
            "statistic / threshold",
        ]);
        for m in &id.motion {
            let (size, vib) = if m.channel.starts_with("gyro") {
                (
                    format!("{:.2} deg/h", m.size / DEG_PER_H),
                    format!("{:.2} deg/h", m.vibration / DEG_PER_H),
                )
            } else {
                (
                    format!("{:.0} ug", m.size / UG),
                    format!("{:.0} ug", m.vibration / UG),
                )
            };
            moved.row([
                m.run.clone(),
                format!("{:.1}", m.start_s),
                format!("{:.1}", m.end_s),
                m.channel.clone(),
                size,
                vib,
                format!("{:.1}", m.excess),
            ]);
        }
        md.push_str("\n## Motion found and left out\n\nThe stillness detector (1 s windows; within-window scatter and change of the window means against the sensor's own white noise, chi-square thresholds at 0.01 false alarms per hour of still data) found the IMU moving here; these windows and two either side are not used:\n\n");
        md.push_str(&moved.render());
    }
    md.push_str("\nStretch means against the Earth rate and gravity at the site (TRIAD attitude of the stretch itself; the observable part of the turn-on bias):\n\n");
    md.push_str(&means.render());
    if !id.notes.is_empty() {
        md.push_str("\n## Notes\n\n");
        for n in &id.notes {
            md.push_str(&format!("- {n}\n"));
        }
    }
    md.push_str(&format!("\nIdentification time: {seconds:.1} s.\n"));
    md
}

/// 1-sigma of each field of the twin's model.
fn sigma_model(id: &IdentifiedNoise) -> NoiseModel {
    NoiseModel {
        gyro_arw_rad_per_sqrt_s: id.gyro.white_per_sqrt_s.sigma,
        gyro_bias_instability_radps: id.gyro.bias_sigma.sigma,
        gyro_bias_correlation_s: id.gyro.bias_correlation_s.sigma,
        gyro_quantum_rad: id.gyro.quantum.sigma,
        accel_vrw_mps_per_sqrt_s: id.accel.white_per_sqrt_s.sigma,
        accel_bias_instability_mps2: id.accel.bias_sigma.sigma,
        accel_bias_correlation_s: id.accel.bias_correlation_s.sigma,
    }
}

/// One channel's Allan curves in paper units (deg/h or ug): `(channel, τ, [adev, lo, hi, fit])`.
type PaperCurve = (String, Vec<f64>, [Vec<f64>; 4]);

fn paper_curves(id: &IdentifiedNoise) -> Vec<PaperCurve> {
    id.curves
        .iter()
        .map(|c| {
            let u = if c.channel.starts_with("gyro") {
                DEG_PER_H
            } else {
                UG
            };
            let s = |v: &[f64]| v.iter().map(|x| x / u).collect::<Vec<f64>>();
            (
                c.channel.clone(),
                c.tau_s.clone(),
                [s(&c.adev), s(&c.lo), s(&c.hi), s(&c.fit_triad)],
            )
        })
        .collect()
}

fn plot(id: &IdentifiedNoise) -> Result<Vec<u8>, sins_plot::PlotError> {
    let conv = paper_curves(id);
    let series = |prefix: &str| -> Vec<AllanSeries<'_>> {
        conv.iter()
            .filter(|(n, _, _)| n.starts_with(prefix))
            .map(|(n, tau, v)| AllanSeries {
                label: n.rsplit('_').next().unwrap_or(n),
                tau_s: tau,
                adev: &v[0],
                lo: &v[1],
                hi: &v[2],
                fit: &v[3],
            })
            .collect()
    };
    allan_figure(
        "Allan deviation of the stationary stretches (68 % intervals; dashed: fitted twin model)",
        &[
            AllanPanel {
                title: "gyros",
                unit: "deg/h",
                series: series("gyro"),
            },
            AllanPanel {
                title: "accelerometers",
                unit: "ug",
                series: series("accel"),
            },
        ],
    )
    .size_px(1400, 520)
    .to_png_bytes()
}

/// Writes `<parent>/<name>/` (`noise.toml`, readable by `diagnose --noise-from` and checked
/// with its reader before anything is written, `allan.png`, `noise.rrd`, `noise.md`) aside and
/// renames it into place; `datasets` are the runs' names and files, `seconds` the
/// identification's time. Returns the directory.
pub fn write_noise_report(
    parent: &Path,
    name: &str,
    id: &IdentifiedNoise,
    datasets: &[(String, PathBuf)],
    seconds: f64,
) -> Result<PathBuf, GapError> {
    let files = sins_report::write_dir_atomically(parent, name, "noise", |dir| {
        let mismatch =
            |what: &str, e: &dyn std::fmt::Display| ReportError::Mismatch(format!("{what}: {e}"));
        let mut comments =
            vec!["Identified by `sinsbench noise` from the stationary stretches of:".to_string()];
        for (n, p) in datasets {
            comments.push(format!("  {n} = {}", p.display()));
        }
        comments.push(format!(
            "{:.2} h stationary in all; see noise.md.",
            id.stationary_s() / 3600.0
        ));
        for n in &id.notes {
            comments.push(format!("note: {n}"));
        }
        for (what, s) in [("gyro", &id.gyro), ("accel", &id.accel)] {
            match s.bias_instability.upper_95 {
                Some(u) if u.is_finite() => comments.push(format!(
                    "{what} bias instability fitted 0: 95 % upper bound {u:e} (SI)"
                )),
                Some(_) => comments.push(format!(
                    "{what} bias instability fitted 0: the data put no finite 95 % upper bound on it"
                )),
                None => {}
            }
        }
        let description = format!(
            "noise identified from {} run(s), {:.2} h stationary",
            id.runs.len(),
            id.stationary_s() / 3600.0
        );
        let toml = sins_config::noise_to_toml_checked(
            &id.to_noise_model(),
            Some(&sigma_model(id)),
            id.to_noise_spec().unresolved_walk_per_sqrt_s,
            &description,
            &comments,
            &id.inconsistent,
        );
        // What `diagnose --noise-from` will read: checked with its own reader before anything
        // is written (the whole set is then left unwritten).
        sins_config::parse_noise_file(&toml, &parent.join(name).join("noise.toml")).map_err(
            |e| {
                ReportError::Mismatch(format!(
                    "the noise file would not read back with `diagnose --noise-from` ({e}); nothing written (a bug: please report it with the datasets)"
                ))
            },
        )?;
        sins_report::write_bytes(&dir.join("noise.toml"), toml.as_bytes())?;
        let png = plot(id).map_err(|e| mismatch("Allan plot", &e))?;
        sins_report::write_bytes(&dir.join("allan.png"), &png)?;
        let paper = paper_curves(id);
        let records: Vec<AllanRecord<'_>> = paper
            .iter()
            .map(|(ch, tau, v)| AllanRecord {
                channel: ch,
                tau_s: tau,
                adev: &v[0],
                lo: &v[1],
                hi: &v[2],
                fit: &v[3],
            })
            .collect();
        sins_viz::write_allan(&dir.join("noise.rrd"), name, &records)
            .map_err(|e| mismatch("noise.rrd", &e))?;
        sins_report::write_bytes(
            &dir.join("noise.md"),
            markdown(id, datasets, seconds).as_bytes(),
        )?;
        Ok(vec![
            "noise.toml".into(),
            "allan.png".into(),
            "noise.rrd".into(),
            "noise.md".into(),
        ])
    })?;
    Ok(files.dir)
}
