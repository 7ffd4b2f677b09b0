//! The paper's Table 1 and Table 3 as shipped in `experiments/reference/`: complete, in the
//! paper's units, consistent with the truth files they describe, and malformed rows refused with
//! file, line and reason.

use sins_calstudy::reference::{TABLE1_FILE, TABLE3_FILE};
use sins_calstudy::units::{PARAMS, vec_to_paper};
use sins_calstudy::{ReferenceError, load_table1, load_table3, parse_table1, parse_table3};
use sins_imu::ParamModel;
use std::path::PathBuf;

fn experiments() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments")
}

fn truth(file: &str) -> Vec<f64> {
    let p = sins_config::load_params(experiments().join("imu").join(file)).expect("params load");
    vec_to_paper(&sins_kf::params_to_vec(&p.params, ParamModel::States42))
}

#[test]
fn shipped_table1_matches_the_simulation_truth() {
    let t = load_table1(experiments().join("reference").join(TABLE1_FILE)).expect("loads");
    assert_eq!(t.rows.len(), 33);
    // Table 1's presets are the truth of paper_calibration.toml (imu/paper_table1.toml).
    let truth = truth("paper_table1.toml");
    for r in &t.rows {
        let k = r.state_index;
        assert_eq!(r.name, PARAMS[k].name);
        assert!(
            (r.preset - truth[k]).abs() <= 1e-9 * truth[k].abs(),
            "{}",
            r.name
        );
    }
    let b_gz = t.by_state(2).expect("B_gz");
    assert_eq!((b_gz.residual, b_gz.resolution), (0.00002, 1e-5));
    let tm = t.by_state(31).expect("TM_axz");
    assert_eq!(
        (tm.name.as_str(), tm.residual, tm.resolution),
        ("TM_axz", 0.0, 1e-3)
    );
}

#[test]
fn shipped_table3_proposed_column_is_the_truth_imu() {
    let t = load_table3(experiments().join("reference").join(TABLE3_FILE)).expect("loads");
    let names: Vec<&str> = t.rows.iter().map(|r| r.name.as_str()).collect();
    let want: Vec<&str> = PARAMS[21..].iter().map(|p| p.name).collect();
    assert_eq!(names, want, "eq-8 order");
    // imu/paper_truth.toml carries Table 3's proposed column as its temperature coefficients.
    let truth = truth("paper_truth.toml");
    for r in &t.rows {
        let v = truth[r.state_index];
        assert!((r.proposed - v).abs() <= 1e-9 * v.abs(), "{}", r.name);
    }
    assert_eq!(t.rows[2].least_squares, -29.38);
    assert_eq!(t.rows[6].least_squares, -0.22);
}

fn malformed(e: ReferenceError) -> (String, usize, String) {
    match e {
        ReferenceError::Malformed { file, line, what } => (file, line, what),
        other => panic!("expected a malformed-row error, got {other}"),
    }
}

#[test]
fn malformed_rows_are_refused_with_file_line_and_reason() {
    let good =
        std::fs::read_to_string(experiments().join("reference").join(TABLE1_FILE)).expect("reads");
    let lines: Vec<&str> = good.lines().collect();
    let line_of = |name: &str| {
        1 + lines
            .iter()
            .position(|l| l.starts_with(&format!("{name},")))
            .expect("row present")
    };
    let cases: [(&str, &str, &str, &str); 5] = [
        (
            "dK_gy",
            "dK_gy,ppm,40,39.93,0.o7",
            "dK_gy",
            "residual \"0.o7\"",
        ),
        ("B_az", "B_az,ug,1,1.01", "B_az", "4 fields"),
        ("TK_ay", "TK_ay,ppm,2,1.999,0.001", "TK_ay", "unit \"ppm\""),
        (
            "B_gx",
            "B_qx,deg/h,0.003,0.00316,0.00016",
            "B_gx",
            "unknown coefficient \"B_qx\"",
        ),
        (
            "TM_ayz",
            "TM_ayz,arcsec/degC,-0.6,-0.601,-0.001",
            "TM_ayz",
            "negative",
        ),
    ];
    for (row, replacement, name, what) in cases {
        let line = line_of(row);
        let text = good.replace(lines[line - 1], replacement);
        let (file, got_line, got_what) = malformed(parse_table1(&text, "t1.csv").expect_err(name));
        assert_eq!(
            (file.as_str(), got_line),
            ("t1.csv", line),
            "{name}: {got_what}"
        );
        assert!(got_what.contains(what), "{name}: {got_what}");
    }
    // A duplicate names the second occurrence; a missing row names the coefficient.
    let dup = good.replace(lines[line_of("B_ay") - 1], lines[line_of("B_ax") - 1]);
    let (_, l, w) = malformed(parse_table1(&dup, "t1.csv").expect_err("duplicate"));
    assert_eq!(l, line_of("B_ay"));
    assert!(w.contains("B_ax appears twice"), "{w}");
    let missing = good.replace(lines[line_of("dM_azy") - 1], "");
    let (_, l, w) = malformed(parse_table1(&missing, "t1.csv").expect_err("missing"));
    assert_eq!(l, 0);
    assert!(w.contains("no row for dM_azy"), "{w}");
    // Table 3: a TM index outside 1..6, with the file's line number.
    let t3 = "# c\ngroup\nTB,ug/degC,x,1,2\n";
    let (_, l, w) = malformed(parse_table3(t3, "t3.csv").expect_err("header-like row"));
    assert_eq!(l, 2, "{w}");
    let t3 = "TM,arcsec/degC,7,0.1,0.2\n";
    let (f, l, w) = malformed(parse_table3(t3, "t3.csv").expect_err("index"));
    assert_eq!((f.as_str(), l), ("t3.csv", 1));
    assert!(w.contains("TM index \"7\""), "{w}");
    // A file that does not exist is an I/O error naming it.
    let e = load_table1("/nonexistent/table1.csv").expect_err("missing file");
    assert!(e.to_string().contains("/nonexistent/table1.csv"), "{e}");
}
