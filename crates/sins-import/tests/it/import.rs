//! Imports of synthetic recordings with known answers: every layout, unit, axis convention,
//! rate rule and time-stamp rule, and the refusals.

use std::io::Write;
use std::path::{Path, PathBuf};

use sins_data::read_all;
use sins_import::{Description, ImportError, ImportReport, ImportRequest, import};

const RATE_HZ: f64 = 100.0;
const DT: f64 = 1.0 / RATE_HZ;
const SITE: &str = "[site]\nlatitude_deg = 34.2\nlongitude_deg = 108.9\nheight_m = 380.0\n";

/// A gyro rate that is linear in time (rad/s, sensor axes) and its exact integral.
fn rate(t: f64) -> [f64; 3] {
    [0.01 + 0.002 * t, -0.02 + 0.001 * t, 0.03 - 0.003 * t]
}

fn angle(t0: f64, t1: f64) -> [f64; 3] {
    let a = |c: f64, b: f64| c * (t1 - t0) + 0.5 * b * (t1 * t1 - t0 * t0);
    [a(0.01, 0.002), a(-0.02, 0.001), a(0.03, -0.003)]
}

/// Specific force (m/s^2, sensor axes), constant.
const FORCE: [f64; 3] = [0.1, -0.2, 9.8];

fn run(dir: &Path, source: &Path, desc_text: &str) -> Result<(ImportReport, PathBuf), ImportError> {
    let desc_file = dir.join("desc.toml");
    std::fs::write(&desc_file, desc_text).unwrap();
    let desc = Description::from_toml(desc_text, &desc_file)?;
    let out = dir.join("out.parquet");
    let report = import(
        &ImportRequest {
            source,
            description: &desc,
            description_file: &desc_file,
            description_text: desc_text,
            out: &out,
        },
        &mut |_| {},
    )?;
    Ok((report, out))
}

/// CSV text with columns t, gx, gy, gz (deg/s), ax, ay, az (g) at the given stamps.
fn csv_rates(stamps: &[f64]) -> String {
    let mut s = String::from("t,gx,gy,gz,ax,ay,az\n");
    for &t in stamps {
        let w = rate(t).map(f64::to_degrees);
        let f = FORCE.map(|x| x / 9.80665);
        s.push_str(&format!(
            "{t},{},{},{},{},{},{}\n",
            w[0], w[1], w[2], f[0], f[1], f[2]
        ));
    }
    s
}

const RATES_DESC: &str = r#"
format = "delimited"
[time]
column = "t"
[gyro]
columns = ["gx", "gy", "gz"]
quantity = "rate"
unit = "deg/s"
[accel]
columns = ["ax", "ay", "az"]
quantity = "rate"
unit = "g"
"#;

fn stamps(n: usize) -> Vec<f64> {
    (0..n).map(|k| k as f64 * DT).collect()
}

#[test]
fn trapezoid_integrates_a_linear_rate_exactly_and_g_becomes_m_per_s2() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("r.csv");
    std::fs::write(&src, csv_rates(&stamps(201))).unwrap();
    let (rep, out) = run(dir.path(), &src, &format!("{RATES_DESC}{SITE}")).unwrap();
    let (info, b) = read_all(&out).unwrap();
    // The first record only opens the first interval.
    assert_eq!(b.samples.len(), 200);
    assert_eq!(info.meta.sample_rate_hz, RATE_HZ);
    assert!(
        rep.rate_from.contains("mean single step"),
        "{}",
        rep.rate_from
    );
    for (k, s) in b.samples.iter().enumerate() {
        let t1 = (k + 1) as f64 * DT;
        assert!((s.t_s - t1).abs() < 1e-12, "t {} vs {t1}", s.t_s);
        let a = angle(t1 - DT, t1);
        for i in 0..3 {
            assert!(
                (s.dtheta_rad[i] - a[i]).abs() < 1e-15,
                "axis {i}: {} vs {}",
                s.dtheta_rad[i],
                a[i]
            );
            assert!((s.dv_mps[i] - FORCE[i] * DT).abs() < 1e-14);
        }
    }
    let meta = &info.meta.extra;
    assert_eq!(meta["time_base"], "nominal");
    assert_eq!(meta["import.source_sha256"].len(), 64);
    assert!(
        meta["import.conversions"].contains("Trapezoid"),
        "{}",
        meta["import.conversions"]
    );
    assert!(meta["import.description"].contains("deg/s"));
}

#[test]
fn hold_takes_each_rate_over_the_interval_ending_at_it() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("r.csv");
    std::fs::write(&src, csv_rates(&stamps(50))).unwrap();
    let desc = RATES_DESC
        .replace("unit = \"deg/s\"", "unit = \"deg/s\"\nrule = \"hold\"")
        .replace("unit = \"g\"", "unit = \"g\"\nrule = \"hold\"");
    let (_, out) = run(dir.path(), &src, &format!("{desc}{SITE}")).unwrap();
    let (_, b) = read_all(&out).unwrap();
    assert_eq!(b.samples.len(), 50);
    for (k, s) in b.samples.iter().enumerate() {
        let w = rate(k as f64 * DT);
        for i in 0..3 {
            assert!((s.dtheta_rad[i] - w[i] * DT).abs() < 1e-15);
        }
    }
}

#[test]
fn the_trapezoid_error_on_a_sine_rate_is_third_order() {
    // r(t) = sin(w t): the trapezoid error per interval is -(w^2 dt^3 / 12) sin(w t) + O(dt^5).
    let dir = tempfile::tempdir().unwrap();
    let w = 2.0 * std::f64::consts::PI * 1.5;
    let mut text = String::from("t,gx,gy,gz,ax,ay,az\n");
    for k in 0..101 {
        let t = k as f64 * DT;
        text.push_str(&format!("{t},{},0,0,0,0,1\n", (w * t).sin()));
    }
    let src = dir.path().join("s.csv");
    std::fs::write(&src, text).unwrap();
    let desc = RATES_DESC.replace("deg/s", "rad/s");
    let (_, out) = run(dir.path(), &src, &format!("{desc}{SITE}")).unwrap();
    let (_, b) = read_all(&out).unwrap();
    for (k, s) in b.samples.iter().enumerate() {
        let (t0, t1) = (k as f64 * DT, (k + 1) as f64 * DT);
        let exact = ((w * t0).cos() - (w * t1).cos()) / w;
        let predicted = -w * w * DT.powi(3) / 12.0 * (w * (t0 + t1) / 2.0).sin();
        // The next term of the series, w^4 dt^5 / 720, is about 1e-9 here.
        assert!((s.dtheta_rad[0] - exact - predicted).abs() < 2e-9);
        assert!(predicted.abs() < 1e-9 || (s.dtheta_rad[0] - exact).abs() > 1e-8);
    }
}

#[test]
fn forward_right_down_axes_become_right_forward_up() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("r.csv");
    std::fs::write(&src, csv_rates(&stamps(11))).unwrap();
    let frd = format!("{RATES_DESC}{SITE}[axes]\nconvention = \"frd\"\n");
    let explicit =
        format!("{RATES_DESC}{SITE}[axes]\nright = \"+y\"\nforward = \"x\"\nup = \"-z\"\n");
    for desc in [frd, explicit] {
        let (_, out) = run(dir.path(), &src, &desc).unwrap();
        let (_, b) = read_all(&out).unwrap();
        let a = angle(0.0, DT);
        let s = &b.samples[0];
        assert!((s.dtheta_rad[0] - a[1]).abs() < 1e-15, "right = sensor y");
        assert!((s.dtheta_rad[1] - a[0]).abs() < 1e-15, "forward = sensor x");
        assert!((s.dtheta_rad[2] + a[2]).abs() < 1e-15, "up = -sensor z");
        assert!((s.dv_mps[2] + FORCE[2] * DT).abs() < 1e-14);
    }
    let mirror = format!("{RATES_DESC}{SITE}[axes]\nright = \"x\"\nforward = \"y\"\nup = \"-z\"\n");
    let err = run(dir.path(), &src, &mirror).unwrap_err().to_string();
    assert!(
        err.contains("axes") && err.contains("not a rotation"),
        "{err}"
    );
}

#[test]
fn jittered_stamps_are_accepted_and_measured() {
    let dir = tempfile::tempdir().unwrap();
    // +-1 % alternating jitter, as a PC-stamped 64 Hz log.
    let t: Vec<f64> = (0..400)
        .map(|k| k as f64 * DT + if k % 2 == 1 { 0.01 * DT } else { 0.0 })
        .collect();
    let src = dir.path().join("j.csv");
    std::fs::write(&src, csv_rates(&t)).unwrap();
    // Estimated from the stamps, the rate is right to the jitter over the probe.
    let (rep, _) = run(dir.path(), &src, &format!("{RATES_DESC}{SITE}")).unwrap();
    assert!(
        (rep.rate_hz / RATE_HZ - 1.0).abs() < 1e-4,
        "{}",
        rep.rate_hz
    );
    let given =
        format!("{RATES_DESC}{SITE}").replace("column = \"t\"", "column = \"t\"\nrate_hz = 100");
    let (rep, out) = run(dir.path(), &src, &given).unwrap();
    assert_eq!(rep.steps.n, 399);
    assert!(
        (rep.steps.std_s() - 0.01 * DT).abs() < 1e-6 * DT,
        "{}",
        rep.stamps_line()
    );
    assert!(
        (rep.steps.max_s - 1.01 * DT).abs() < 1e-12 && (rep.steps.min_s - 0.99 * DT).abs() < 1e-12
    );
    let (_, b) = read_all(&out).unwrap();
    // The nominal base: regular output times.
    assert!((b.samples[398].t_s - 399.0 * DT).abs() < 1e-12);
    // Recorded stamps: the output keeps them, and the dataset reader accepts the jitter.
    let recorded = given.replace("column = \"t\"", "column = \"t\"\nstamps = \"recorded\"");
    let (_, out) = run(dir.path(), &src, &recorded).unwrap();
    let (info, b) = read_all(&out).unwrap();
    assert!(info.meta.recorded_stamps());
    assert_eq!(b.samples[0].t_s, t[1]);
    // Each increment covers its own stamped interval.
    let a = angle(t[0], t[1]);
    assert!((b.samples[0].dtheta_rad[0] - a[0]).abs() < 1e-15);
}

#[test]
fn a_dropped_sample_is_bridged_and_listed() {
    let dir = tempfile::tempdir().unwrap();
    let mut t = stamps(300);
    t.remove(150);
    let src = dir.path().join("d.csv");
    std::fs::write(&src, csv_rates(&t)).unwrap();
    let (rep, out) = run(dir.path(), &src, &format!("{RATES_DESC}{SITE}")).unwrap();
    assert_eq!(rep.gaps.len(), 1);
    assert_eq!((rep.gaps[0].missing, rep.gaps[0].bridged), (1, true));
    assert_eq!(rep.gaps[0].at.record, 150);
    assert_eq!(rep.gaps[0].at.line, Some(152));
    let (info, b) = read_all(&out).unwrap();
    assert_eq!(b.samples.len(), 299);
    assert!(
        info.meta.extra["import.gaps"].contains("bridged at line 152"),
        "{}",
        info.meta.extra["import.gaps"]
    );
    // The rate is linear, so the bridged trapezoid is exact too.
    for (k, s) in b.samples.iter().enumerate() {
        let t1 = (k + 1) as f64 * DT;
        assert!((s.t_s - t1).abs() < 1e-9);
        let a = angle(t1 - DT, t1);
        assert!((s.dtheta_rad[2] - a[2]).abs() < 1e-14, "sample {k}");
    }
}

#[test]
fn a_long_gap_is_refused_or_split() {
    let dir = tempfile::tempdir().unwrap();
    let mut t = stamps(300);
    t.drain(100..110);
    let src = dir.path().join("g.csv");
    std::fs::write(&src, csv_rates(&t)).unwrap();
    let err = run(dir.path(), &src, &format!("{RATES_DESC}{SITE}")).unwrap_err();
    let msg = err.to_string();
    assert!(matches!(err, ImportError::Gap { missing: 10, .. }), "{msg}");
    assert!(
        msg.contains("line 102") && msg.contains("max_bridge_samples = 5") && msg.contains("split"),
        "{msg}"
    );
    assert!(!dir.path().join("out.parquet").exists(), "nothing written");
    let split = format!("{RATES_DESC}{SITE}")
        .replace("column = \"t\"", "column = \"t\"\non_gap = \"split\"");
    let (rep, _) = run(dir.path(), &src, &split).unwrap();
    assert_eq!(rep.stretches.len(), 2);
    assert_eq!(rep.stretches[0].rows, 99);
    assert_eq!(rep.stretches[1].rows, 189);
    assert!(rep.stretches[1].path.ends_with("out_part2.parquet"));
    let (_, b) = read_all(&rep.stretches[1].path).unwrap();
    assert!((b.samples[0].t_s - 111.0 * DT).abs() < 1e-12);
}

#[test]
fn stamps_that_go_back_are_refused_naming_the_rows() {
    let dir = tempfile::tempdir().unwrap();
    let mut t = stamps(50);
    t.swap(20, 21);
    let src = dir.path().join("b.csv");
    std::fs::write(&src, csv_rates(&t)).unwrap();
    let msg = run(dir.path(), &src, &format!("{RATES_DESC}{SITE}"))
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("line 23 (record 21)")
            && msg.contains("record 20")
            && msg.contains("must increase"),
        "{msg}"
    );
}

#[test]
fn a_counter_finds_dropped_samples_without_stamps() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("n gx gy gz ax ay az\n");
    for k in (0..40).filter(|k| *k != 17 && *k != 18) {
        text.push_str(&format!("{k} 36 0 0 0 0 1000\n"));
    }
    let src = dir.path().join("c.txt");
    std::fs::write(&src, text).unwrap();
    let desc = format!(
        "format = \"delimited\"\n[delimited]\ndelimiter = \"whitespace\"\n[time]\ncounter = \"n\"\nrate_hz = 100\n\
         [gyro]\ncolumns = [\"gx\", \"gy\", \"gz\"]\nquantity = \"increment\"\nunit = \"arcsec\"\n\
         [accel]\ncolumns = [\"ax\", \"ay\", \"az\"]\nquantity = \"increment\"\nunit = \"ug*s\"\n{SITE}"
    );
    let (rep, out) = run(dir.path(), &src, &desc).unwrap();
    assert_eq!(rep.gaps.len(), 1);
    assert_eq!(rep.gaps[0].missing, 2);
    let (_, b) = read_all(&out).unwrap();
    assert_eq!(b.samples.len(), 40);
    assert!((b.samples[39].t_s - 0.40).abs() < 1e-12);
    let arcsec = std::f64::consts::PI / 648_000.0;
    assert!((b.samples[17].dtheta_rad[0] - 36.0 * arcsec).abs() < 1e-18);
    assert!((b.samples[0].dv_mps[2] - 1000e-6 * 9.80665).abs() < 1e-15);
}

fn write_binary(path: &Path, big: bool) {
    let mut f = std::fs::File::create(path).unwrap();
    f.write_all(b"HDR!").unwrap();
    for k in 0..30i32 {
        let t = k as f64 * DT;
        let counts: [i16; 3] = [100 + k as i16, -200, 300];
        let dv: [f32; 3] = [0.001, -0.002, 0.098];
        let put = |f: &mut std::fs::File, b: &[u8]| f.write_all(b).unwrap();
        if big {
            put(&mut f, &t.to_be_bytes());
            counts.iter().for_each(|c| put(&mut f, &c.to_be_bytes()));
            dv.iter().for_each(|c| put(&mut f, &c.to_be_bytes()));
        } else {
            put(&mut f, &t.to_le_bytes());
            counts.iter().for_each(|c| put(&mut f, &c.to_le_bytes()));
            dv.iter().for_each(|c| put(&mut f, &c.to_le_bytes()));
        }
        put(&mut f, &[0, 0]);
    }
}

const BINARY_DESC: &str = r#"
format = "binary"
[binary]
header_bytes = 4
byte_order = "little"
fields = [
  { name = "t", type = "f64" },
  { name = "gx", type = "i16" }, { name = "gy", type = "i16" }, { name = "gz", type = "i16" },
  { name = "vx", type = "f32" }, { name = "vy", type = "f32" }, { name = "vz", type = "f32" },
  { name = "spare", type = "pad2" },
]
[time]
column = "t"
rate_hz = 100
[gyro]
columns = ["gx", "gy", "gz"]
quantity = "increment"
unit = "counts"
count_scale = [0.1, 0.1, 0.1]
count_unit = "arcsec"
[accel]
columns = ["vx", "vy", "vz"]
quantity = "increment"
unit = "m/s"
"#;

#[test]
fn binary_records_in_either_byte_order() {
    let dir = tempfile::tempdir().unwrap();
    let arcsec = std::f64::consts::PI / 648_000.0;
    for big in [false, true] {
        let src = dir.path().join("b.bin");
        write_binary(&src, big);
        let desc = if big {
            BINARY_DESC.replace("\"little\"", "\"big\"")
        } else {
            BINARY_DESC.to_string()
        };
        let (rep, out) = run(dir.path(), &src, &format!("{desc}{SITE}")).unwrap();
        assert_eq!(rep.records, 30);
        let (_, b) = read_all(&out).unwrap();
        assert_eq!(b.samples.len(), 30);
        assert!((b.samples[5].dtheta_rad[0] - 10.5 * arcsec).abs() < 1e-18);
        assert!((b.samples[5].dtheta_rad[1] + 20.0 * arcsec).abs() < 1e-18);
        assert_eq!(b.samples[5].dv_mps[2], f64::from(0.098f32));
        assert!((b.samples[5].t_s - 0.05).abs() < 1e-15);
    }
    // A truncated file names the byte offset of the broken record.
    let src = dir.path().join("b.bin");
    write_binary(&src, false);
    let bytes = std::fs::read(&src).unwrap();
    std::fs::write(&src, &bytes[..bytes.len() - 7]).unwrap();
    let msg = run(dir.path(), &src, &format!("{BINARY_DESC}{SITE}"))
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("byte offset 816 (record 29)") && msg.contains("ends inside a record"),
        "{msg}"
    );
}

#[test]
fn psins_files_describe_themselves() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from(
        "% PSINS-format SIMU log file.\n\n0.5 -0.25 -90.6 0 0 0\n34.246048 108.909664 380.0 0 10 9.780327\n\
         0.1 0.1 0.1 125 125 125\n",
    );
    for k in 0..200 {
        text.push_str(&format!("{} -4 7 0 2 {}\n", k % 3, 80 + k % 2));
    }
    let src = dir.path().join("x.imu");
    std::fs::write(&src, text).unwrap();
    let desc = Description::psins();
    let out = dir.path().join("x.parquet");
    let rep = import(
        &ImportRequest {
            source: &src,
            description: &desc,
            description_file: &src,
            description_text: "format = \"psins\"",
            out: &out,
        },
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(rep.psins.unwrap().interval_ms, 10.0);
    let (info, b) = read_all(&out).unwrap();
    assert_eq!(b.samples.len(), 200);
    assert_eq!(info.meta.sample_rate_hz, 100.0);
    assert!((info.meta.site.lat_rad.to_degrees() - 34.246048).abs() < 1e-9);
    assert_eq!(info.meta.extra["initial_yaw_deg"], "-90.6");
    assert_eq!(info.meta.extra["initial_pitch_deg"], "0.5");
    let arcsec = std::f64::consts::PI / 648_000.0;
    assert!((b.samples[1].dtheta_rad[0] - 0.1 * arcsec).abs() < 1e-18);
    assert!((b.samples[1].dtheta_rad[1] + 0.4 * arcsec).abs() < 1e-18);
    // 81 counts of 125 ug*s, ug being 1e-6 of the header's g.
    assert!((b.samples[1].dv_mps[2] - 81.0 * 125e-6 * 9.780327).abs() < 1e-15);
    assert!((b.samples[0].t_s - 0.01).abs() < 1e-15);
}

#[test]
fn gzip_and_tab_separated_text_read_as_they_come() {
    let dir = tempfile::tempdir().unwrap();
    let csv = csv_rates(&stamps(21)).replace(',', "\t");
    let src = dir.path().join("r.tsv.gz");
    let mut gz = flate2_writer(&src);
    gz.write_all(csv.as_bytes()).unwrap();
    drop(gz);
    let desc = format!("{RATES_DESC}{SITE}[delimited]\ndelimiter = \"tab\"\n");
    let (_, out) = run(dir.path(), &src, &desc).unwrap();
    let (_, b) = read_all(&out).unwrap();
    assert_eq!(b.samples.len(), 20);
}

fn flate2_writer(path: &Path) -> impl Write {
    // The test builds its gzip file with the system's gzip, an independent encoder.
    struct Gz(PathBuf, Vec<u8>);
    impl Write for Gz {
        fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
            self.1.extend_from_slice(b);
            Ok(b.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    impl Drop for Gz {
        fn drop(&mut self) {
            let mut child = std::process::Command::new("gzip")
                .arg("-c")
                .stdin(std::process::Stdio::piped())
                .stdout(std::process::Stdio::piped())
                .spawn()
                .unwrap();
            child.stdin.take().unwrap().write_all(&self.1).unwrap();
            let out = child.wait_with_output().unwrap();
            std::fs::write(&self.0, out.stdout).unwrap();
        }
    }
    Gz(path.to_path_buf(), Vec::new())
}

#[test]
fn every_refusal_names_the_file_the_place_and_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("r.csv");
    std::fs::write(&src, csv_rates(&stamps(20))).unwrap();
    let with_site = |d: String| format!("{d}{SITE}");
    let cases: Vec<(String, &[&str])> = vec![
        (
            with_site(RATES_DESC.replace("\"gz\"", "\"gq\"")),
            &["gyro.columns[2]", "'gq' is not a column", "gx, gy, gz"],
        ),
        (
            with_site(RATES_DESC.replace("deg/s", "furlong")),
            &["gyro.unit", "'furlong'", "deg/s"],
        ),
        (
            with_site(RATES_DESC.replace("unit = \"g\"", "unit = \"g\"\ncolour = 3")),
            &["unknown field", "colour"],
        ),
        (RATES_DESC.to_string(), &["site", "required"]),
        (
            with_site(RATES_DESC.replace("column = \"t\"", "column = \"t\"\nunit = \"fortnight\"")),
            &["time.unit", "fortnight"],
        ),
    ];
    for (desc, want) in cases {
        let msg = run(dir.path(), &src, &desc).unwrap_err().to_string();
        assert!(msg.contains("desc.toml"), "{msg}");
        for w in want {
            assert!(msg.contains(w), "'{w}' not in: {msg}");
        }
    }
    // A bad number names the line and the column.
    let text = csv_rates(&stamps(20)).replacen("0.05,", "0.05x,", 1);
    std::fs::write(&src, text).unwrap();
    let msg = run(dir.path(), &src, &format!("{RATES_DESC}{SITE}"))
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("r.csv")
            && msg.contains("line 7")
            && msg.contains("time.column")
            && msg.contains("not a number"),
        "{msg}"
    );
    // A ragged line.
    std::fs::write(&src, "t,gx,gy,gz,ax,ay,az\n0,1,2,3,4,5,6\n0.01,1,2\n").unwrap();
    let msg = run(dir.path(), &src, &format!("{RATES_DESC}{SITE}"))
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("line 3") && msg.contains("3 fields where the first record has 7"),
        "{msg}"
    );
}

#[test]
fn padded_fields_read_as_unpadded_and_odd_bytes_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("r.csv");
    let desc = format!("{RATES_DESC}{SITE}");
    let plain = csv_rates(&stamps(40));
    std::fs::write(&src, &plain).unwrap();
    let (_, out) = run(dir.path(), &src, &desc).unwrap();
    // Temperatures are NaN (none given), so compare time and increments.
    let numbers = |out: &Path| -> Vec<[f64; 7]> {
        let b = read_all(out).unwrap().1;
        b.samples
            .iter()
            .map(|s| {
                let (g, a) = (s.dtheta_rad, s.dv_mps);
                [s.t_s, g.x, g.y, g.z, a.x, a.y, a.z]
            })
            .collect()
    };
    let a = numbers(&out);
    // The same numbers with blanks and tabs around every field (the header's too).
    let padded: String = plain
        .lines()
        .map(|l| format!(" {} \n", l.replace(',', " ,\t")))
        .collect();
    std::fs::write(&src, padded).unwrap();
    let (_, out) = run(dir.path(), &src, &desc).unwrap();
    assert_eq!(numbers(&out), a);
    for (field, reason) in [
        (&b"inf"[..], "is not finite"),
        (b"0.0\xff5", "is not UTF-8 text"),
    ] {
        let mut bytes = plain.replacen("0.05,", "@,", 1).into_bytes();
        let at = bytes.iter().position(|&b| b == b'@').unwrap();
        bytes.splice(at..=at, field.iter().copied());
        std::fs::write(&src, bytes).unwrap();
        let msg = run(dir.path(), &src, &desc).unwrap_err().to_string();
        assert!(msg.contains("line 7") && msg.contains(reason), "{msg}");
    }
}
