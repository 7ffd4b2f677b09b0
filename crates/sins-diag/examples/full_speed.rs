//! Speed and memory of a full-size diagnosis: the paper's 4.2 h calibration run and its three
//! 15 h navigation runs at 200 Hz (truth = the parameter set = `imu/paper_truth.toml`, the
//! paper's noise), replayed and diagnosed.
//!
//! Run: `/usr/bin/time -v cargo run --release -p sins-diag --example full_speed -- [options]`
//!
//! - `--files DIR`: simulate each run once into a raw binary file in DIR and read the passes
//!   from it (like a dataset on disk); without it every pass regenerates the run by simulation.
//! - `--runs N`: navigation runs (default 3); `--seed K`: add K to every run's seed;
//! - `--effect KIND:COMPONENT:VALUE` (repeatable): hide an effect (value in the kind's unit);
//! - `--twin`: subtract each run's noise-free replay as the twin mean; `--noq`: no gyro quantizer;
//! - env `DIAG_KAPPA`: the twin's quantization factor; `DIAG_SERIES`: print the gap series.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test or an example is its failure message

use sins_diag::diagnose;
use sins_diag::input::{DiagnoseConfig, DiagnosisInput, RunData};
use sins_diag::noise::NoiseSpec;
use sins_diag::replay::{ReplaySetup, replay_run};
use sins_diag::source::{SampleSource, SimSource};
use sins_imu::ForwardModel;
use sins_sim::{Scenario, Simulator};
use std::path::PathBuf;
use std::time::Instant;

fn experiment(name: &str) -> Vec<Scenario> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../experiments")
        .join(name);
    sins_config::load_experiment(p)
        .expect("experiment")
        .scenarios
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n_nav: usize = args
        .iter()
        .position(|a| a == "--runs")
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(3);
    let truth_path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments/imu/paper_truth.toml");
    let truth = sins_config::load_params(truth_path).expect("truth").params;
    let mut scenarios = experiment("paper_calibration.toml");
    scenarios.truncate(1);
    scenarios.extend(experiment("paper_navigation.toml").into_iter().take(n_nav));
    let effects: Vec<sins_imu::EffectSpec> = args
        .iter()
        .enumerate()
        .filter(|(_, a)| *a == "--effect")
        .filter_map(|(i, _)| args.get(i + 1))
        .map(|e| {
            let parts: Vec<&str> = e.split(':').collect();
            let kind = sins_imu::EffectKind::from_name(parts[0]).expect("kind");
            let axis: usize = parts[1].parse().expect("axis");
            let value: f64 = parts[2].parse().expect("value");
            sins_imu::EffectSpec::unit(kind, axis).scaled(kind.unit().to_si(value))
        })
        .collect();
    for sc in &mut scenarios {
        sc.truth = truth;
        sc.effects = effects.clone();
        if args.iter().any(|a| a == "--noq") {
            sc.noise.gyro_quantum_rad = 0.0;
        }
        if let Some(seed) = args
            .iter()
            .position(|a| a == "--seed")
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse::<u64>().ok())
        {
            sc.seed += seed;
        }
    }
    let mut noise = NoiseSpec::from(&scenarios[1.min(scenarios.len() - 1)].noise);
    if let Ok(k) = std::env::var("DIAG_KAPPA") {
        noise.gyro_quantum_factor = k.parse().expect("kappa");
    }
    let files = args
        .iter()
        .position(|a| a == "--files")
        .and_then(|i| args.get(i + 1))
        .map(PathBuf::from);
    let make_sim = |sc: &Scenario| {
        let fwd = sc.effects.iter().fold(ForwardModel::new(sc.truth), |f, e| {
            f.with_effect(e.build(&sc.truth))
        });
        SimSource::new(Simulator::new(sc, fwd).expect("scenario"))
    };
    let make = |sc: &Scenario| -> (Box<dyn SampleSource>, Vec<String>) {
        let sim = make_sim(sc);
        let labels = sim.segment_labels();
        match &files {
            Some(dir) => {
                let tag: String = format!("{:?}", sc.effects)
                    .bytes()
                    .fold(0u64, |h, b| {
                        h.wrapping_mul(1_099_511_628_211).wrapping_add(b as u64)
                    })
                    .to_string();
                let path = dir.join(format!("{}-{}-{tag}.bin", sc.name, sc.seed));
                (Box::new(raw::RawFile::create(path, sim)), labels)
            }
            None => (Box::new(sim), labels),
        }
    };
    // Simulation alone (what reading a dataset replaces).
    let t = Instant::now();
    let mut src = make_sim(&scenarios[1.min(scenarios.len() - 1)]);
    let mut n = 0usize;
    src.visit(&mut |s, _| {
        n += s.len();
        Ok(())
    })
    .expect("sim");
    let sim_s = t.elapsed().as_secs_f64();
    eprintln!("simulation of one run: {n} samples in {sim_s:.1} s");
    let t_all = Instant::now();
    let mut runs = Vec::new();
    for sc in &scenarios {
        let t = Instant::now();
        let (mut src, labels) = make(sc);
        let track = replay_run(
            &sc.name,
            src.as_mut(),
            &truth,
            &sc.site,
            &ReplaySetup::default(),
        )
        .expect("replay");
        eprintln!(
            "replay {}: {:.1} s (max horizontal {:.0} m)",
            sc.name,
            t.elapsed().as_secs_f64(),
            track.summary.as_ref().map_or(0.0, |s| s.max_horizontal_m)
        );
        let twin_mean = if args.iter().any(|a| a == "--twin") {
            let mut clean = sc.clone();
            clean.noise = Default::default();
            clean.thermal.thermometer_noise_degc = 0.0;
            let mut csrc = make_sim(&clean);
            let t = replay_run(
                &sc.name,
                &mut csrc,
                &truth,
                &sc.site,
                &ReplaySetup::default(),
            )
            .expect("twin replay");
            eprintln!(
                "  noise-free twin {}: max horizontal {:.2} m",
                sc.name,
                t.summary.as_ref().map_or(0.0, |s| s.max_horizontal_m)
            );
            Some(t.points)
        } else {
            None
        };
        runs.push(RunData {
            name: sc.name.clone(),
            segment_labels: labels,
            source: src,
            site: sc.site,
            track: track.points,
            temperatures: Some(track.temperatures),
            twin_mean,
        });
    }
    let t = Instant::now();
    let mut input = DiagnosisInput {
        runs,
        params: truth,
        param_sigma: None,
        param_covariance: None,
        noise,
        calibration_run: None,
    };
    let d = diagnose(&mut input, &DiagnoseConfig::default()).expect("diagnosis");
    eprintln!("diagnose: {:.1} s", t.elapsed().as_secs_f64());
    eprintln!(
        "total {:.1} s (of which simulation about {:.1} s per pass and run)",
        t_all.elapsed().as_secs_f64(),
        sim_s
    );
    eprintln!(
        "verdict {:?}, null chi2 {:.1} / {:.1}",
        d.verdict, d.null_test.chi2, d.null_test.dof
    );
    for l in &d.localisation {
        eprintln!(
            "  run {}: chi2 {:.1} / {:.1}, first exit {:?} {:?}",
            l.run, l.chi2.chi2, l.chi2.dof, l.first_exit_s, l.first_exit_segment
        );
        for s in &l.segments {
            eprintln!(
                "    {:<12} {:<5} max {:>8.1} m rms {:>8.1} m max/sigma {:.2}",
                s.segment, s.channel, s.max_abs_m, s.rms_m, s.max_sigmas
            );
        }
    }
    for v in &d.validation {
        eprintln!(
            "  validation {} -> {}: rms {:.1} -> {:.1} ({:.0} %) max {:.1} -> {:.1} ({:.0} %)",
            v.fitted_on,
            v.evaluated_on,
            v.before.rms_gap_m,
            v.after.rms_gap_m,
            v.rms_shrinkage_percent,
            v.before.max_horizontal_gap_m,
            v.after.max_horizontal_gap_m,
            v.max_shrinkage_percent
        );
    }
    for c in d.candidates.iter().take(6) {
        let comps: Vec<String> = c
            .components
            .iter()
            .filter(|x| x.retained)
            .map(|x| {
                format!(
                    "{}={:.4}±{:.4}",
                    x.label,
                    x.value,
                    x.sigma.unwrap_or(f64::NAN)
                )
            })
            .collect();
        eprintln!(
            "  {:<30} dchi2 {:>8.1} p {:.1e} pass {} resid {:.1} [{}]",
            c.kind,
            c.dchi2,
            c.p_value,
            c.passes,
            c.residual.chi2,
            comps.join(" ")
        );
    }
    if std::env::var("DIAG_SERIES").is_ok() {
        for s in &d.series {
            for k in (0..s.t_s.len()).step_by(60) {
                eprintln!(
                    "{} {:.0} {} gap {:.1} {:.1} sigma {:.1} {:.1}",
                    s.run,
                    s.t_s[k],
                    s.segment[k],
                    s.gap_north_m[k],
                    s.gap_east_m[k],
                    s.sigma_north_m[k],
                    s.sigma_east_m[k]
                );
            }
        }
    }
}

/// Raw little-endian sample files: `t, dθ×3, dv×3, T×3` (f64) and the segment (u16) per sample.
mod raw {
    use sins_diag::DiagError;
    use sins_diag::source::{BatchSink, SampleSource, SimSource};
    use sins_imu::ImuSample;
    use sins_nav::Vec3;
    use std::io::{BufReader, BufWriter, Read, Write};
    use std::path::PathBuf;

    const REC: usize = 10 * 8 + 2;

    pub struct RawFile {
        path: PathBuf,
        h: f64,
    }

    impl RawFile {
        /// Write `sim` to `path` (unless it exists) and read it from there.
        pub fn create(path: PathBuf, mut sim: SimSource) -> Self {
            let h = sim.sample_interval_s();
            if !path.exists() {
                let tmp = path.with_extension("part");
                let mut w = BufWriter::new(std::fs::File::create(&tmp).expect("create"));
                sim.visit(&mut |s, g| {
                    for (x, &seg) in s.iter().zip(g) {
                        let v = [
                            x.t_s,
                            x.dtheta_rad.x,
                            x.dtheta_rad.y,
                            x.dtheta_rad.z,
                            x.dv_mps.x,
                            x.dv_mps.y,
                            x.dv_mps.z,
                            x.temp_degc[0],
                            x.temp_degc[1],
                            x.temp_degc[2],
                        ];
                        for f in v {
                            w.write_all(&f.to_le_bytes()).expect("write");
                        }
                        w.write_all(&seg.to_le_bytes()).expect("write");
                    }
                    Ok(())
                })
                .expect("simulate");
                w.flush().expect("flush");
                drop(w);
                std::fs::rename(&tmp, &path).expect("rename");
            }
            Self { path, h }
        }
    }

    impl SampleSource for RawFile {
        fn sample_interval_s(&self) -> f64 {
            self.h
        }
        fn visit(&mut self, sink: &mut BatchSink<'_>) -> Result<(), DiagError> {
            let f = std::fs::File::open(&self.path).map_err(|e| DiagError::Source {
                run: self.path.display().to_string(),
                reason: e.to_string(),
            })?;
            let mut r = BufReader::with_capacity(1 << 22, f);
            let batch = 65_536;
            let mut buf = vec![0u8; REC * batch];
            let (mut samples, mut segs) = (Vec::with_capacity(batch), Vec::with_capacity(batch));
            loop {
                let mut got = 0;
                while got < buf.len() {
                    let n = r.read(&mut buf[got..]).map_err(|e| DiagError::Source {
                        run: self.path.display().to_string(),
                        reason: e.to_string(),
                    })?;
                    if n == 0 {
                        break;
                    }
                    got += n;
                }
                samples.clear();
                segs.clear();
                for rec in buf[..got - got % REC].chunks_exact(REC) {
                    let f = |i: usize| {
                        f64::from_le_bytes(rec[8 * i..8 * i + 8].try_into().unwrap_or([0; 8]))
                    };
                    samples.push(ImuSample {
                        t_s: f(0),
                        dtheta_rad: Vec3::new(f(1), f(2), f(3)),
                        dv_mps: Vec3::new(f(4), f(5), f(6)),
                        temp_degc: [f(7), f(8), f(9)],
                    });
                    segs.push(u16::from_le_bytes([rec[80], rec[81]]));
                }
                if !samples.is_empty() {
                    sink(&samples, &segs)?;
                }
                if got < buf.len() {
                    return Ok(());
                }
            }
        }
    }
}
