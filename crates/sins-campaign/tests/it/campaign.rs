//! A campaign planned, sharded and reduced: the summary is byte-identical however the shards
//! ran (order, workers), equals the in-process calibration study's Table 1, and every bad input
//! is refused with a clear message and nothing half-written.

use sins_campaign::{BinaryId, CampaignError, Context, ShardRun, open, plan, shard_path};
use std::path::{Path, PathBuf};

fn experiments() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../experiments")
        .canonicalize()
        .unwrap()
}

fn ctx() -> Context {
    Context {
        experiments_dir: experiments(),
        binary: BinaryId {
            version: "test".into(),
            sha256: "0".repeat(64),
        },
    }
}

/// A calibration Monte Carlo of 3 seeds cut to 30 min (4 jobs, 2 per shard).
fn short_campaign(dir: &Path) -> PathBuf {
    let p = dir.join("short.toml");
    std::fs::write(
        &p,
        format!(
            "schema = 1\nname = \"short\"\nkind = \"calibration-mc\"\nseed = 5\njobs_per_shard = 2\n\n[calibration_mc]\nseeds = 3\nexperiment = \"{}\"\nmax_duration_s = 1800.0\n",
            experiments().join("paper_calibration.toml").display()
        ),
    )
    .unwrap();
    p
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn shards_in_any_order_or_threads_give_the_in_process_table_1() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = short_campaign(tmp.path());
    // Shard by shard in reverse order, each opened afresh (as separate processes would).
    let a = tmp.path().join("a");
    let (m, fresh) = plan(&cfg, &a, &ctx()).unwrap();
    assert!(fresh);
    assert_eq!((m.jobs, m.shards), (4, 2));
    for s in (0..m.shards).rev() {
        assert!(matches!(
            open(&a, &ctx()).unwrap().run_shard(s).unwrap(),
            ShardRun::Ran(_)
        ));
    }
    // Running a finished shard again is a no-op: the file is not rewritten.
    let before = std::fs::metadata(shard_path(&a, 0))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(
        open(&a, &ctx()).unwrap().run_shard(0).unwrap(),
        ShardRun::AlreadyDone
    );
    assert_eq!(
        std::fs::metadata(shard_path(&a, 0))
            .unwrap()
            .modified()
            .unwrap(),
        before
    );
    open(&a, &ctx()).unwrap().reduce().unwrap();
    // All in one process on three workers.
    let b = tmp.path().join("b");
    plan(&cfg, &b, &ctx()).unwrap();
    open(&b, &ctx()).unwrap().run_local(3, &|_| {}).unwrap();
    open(&b, &ctx()).unwrap().reduce().unwrap();
    for f in ["summary.json", "report.md"] {
        assert_eq!(read(&a.join(f)), read(&b.join(f)), "{f} differs");
    }
    // The same Monte Carlo in one process through the calibration study: same Table 1.
    let mut study = sins_calstudy::StudyConfig::paper(experiments());
    study.seeds = 3;
    study.max_duration_s = Some(1800.0);
    let in_process = sins_calstudy::run_study(&study).unwrap().table1;
    // The study starts its seeds at the run's own seed (1); the campaign at its seed 5.
    let campaign: serde_json::Value =
        serde_json::from_slice(&read(&a.join("summary.json"))).unwrap();
    assert_eq!(campaign["seeds"], serde_json::json!([5, 6, 7]));
    let cfg1 = tmp.path().join("seed1.toml");
    std::fs::write(
        &cfg1,
        std::fs::read_to_string(&cfg)
            .unwrap()
            .replace("seed = 5", "seed = 1"),
    )
    .unwrap();
    let c = tmp.path().join("c");
    plan(&cfg1, &c, &ctx()).unwrap();
    open(&c, &ctx()).unwrap().run_local(2, &|_| {}).unwrap();
    open(&c, &ctx()).unwrap().reduce().unwrap();
    let want = serde_json::to_string_pretty(&in_process).unwrap() + "\n";
    let got = String::from_utf8(read(&c.join("summary.json"))).unwrap();
    if got != want {
        let diff: Vec<String> = got
            .lines()
            .zip(want.lines())
            .enumerate()
            .filter(|(_, (g, w))| g != w)
            .take(10)
            .map(|(i, (g, w))| format!("line {i}: campaign {g} / in process {w}"))
            .collect();
        panic!(
            "the campaign's Table 1 differs from the study's:\n{}",
            diff.join("\n")
        );
    }
}

fn err<T>(r: Result<T, CampaignError>) -> String {
    match r {
        Ok(_) => panic!("must be refused"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_inputs_are_refused_clearly_and_leave_nothing_half_written() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = short_campaign(tmp.path());
    let dir = tmp.path().join("run");
    plan(&cfg, &dir, &ctx()).unwrap();
    // A shard index out of range.
    let e = err(open(&dir, &ctx()).unwrap().run_shard(2));
    assert!(
        e.contains("shard index 2 is out of range") && e.contains("has 2 shards"),
        "{e}"
    );
    // A reduce with a missing shard: refused, listing it, and no summary written.
    open(&dir, &ctx()).unwrap().run_shard(0).unwrap();
    let e = err(open(&dir, &ctx()).unwrap().reduce());
    assert!(
        e.contains("1 of 2 shards have no result") && e.contains(": 1 "),
        "{e}"
    );
    assert!(!dir.join("summary.json").exists() && !dir.join("report.md").exists());
    // Another build.
    let mut other = ctx();
    other.binary.sha256 = "1".repeat(64);
    let e = err(open(&dir, &other));
    assert!(e.contains("another sinsbench build"), "{e}");
    // A tampered manifest (one more shard).
    let m = dir.join("manifest.json");
    let text = std::fs::read_to_string(&m).unwrap();
    std::fs::write(&m, text.replace("\"shards\": 2", "\"shards\": 3")).unwrap();
    let e = err(open(&dir, &ctx()));
    assert!(
        e.contains("manifest.json") && e.contains("modified after planning"),
        "{e}"
    );
    std::fs::write(&m, &text).unwrap();
    // An input edited after planning (the experiment the jobs read).
    let exp = shortened(tmp.path(), "paper_calibration.toml", &[]);
    let cfg2 = tmp.path().join("edited.toml");
    let own = experiments()
        .join("paper_calibration.toml")
        .display()
        .to_string();
    let text2 = std::fs::read_to_string(&cfg)
        .unwrap()
        .replace(&own, &exp.display().to_string());
    std::fs::write(&cfg2, text2).unwrap();
    let dir2 = tmp.path().join("run2");
    plan(&cfg2, &dir2, &ctx()).unwrap();
    let edited = std::fs::read_to_string(&exp)
        .unwrap()
        .replace("seed = 1", "seed = 2");
    std::fs::write(&exp, edited).unwrap();
    let e = err(open(&dir2, &ctx()));
    assert!(e.contains("inputs changed since it was planned"), "{e}");
    // An unknown kind: refused before anything is created.
    let bad = tmp.path().join("bad.toml");
    std::fs::write(
        &bad,
        std::fs::read_to_string(&cfg)
            .unwrap()
            .replace("kind = \"calibration-mc\"", "kind = \"sweep\""),
    )
    .unwrap();
    let dir3 = tmp.path().join("run3");
    let e = err(plan(&bad, &dir3, &ctx()));
    assert!(e.contains("kind = 'sweep' is not a campaign kind"), "{e}");
    assert!(!dir3.exists());
    // A foreign directory or a file at --out: refused, left as it was.
    let foreign = tmp.path().join("foreign");
    std::fs::create_dir(&foreign).unwrap();
    std::fs::write(foreign.join("notes.txt"), "mine").unwrap();
    let e = err(plan(&cfg, &foreign, &ctx()));
    assert!(e.contains("holds no campaign"), "{e}");
    assert_eq!(std::fs::read_dir(&foreign).unwrap().count(), 1);
    let e = err(plan(&cfg, &foreign.join("notes.txt"), &ctx()));
    assert!(e.contains("is not a directory"), "{e}");
    assert_eq!(
        std::fs::read_to_string(foreign.join("notes.txt")).unwrap(),
        "mine"
    );
}

/// Experiment `name` of experiments/ written into `dir` with its relative paths made absolute
/// and each `(from, to)` replaced.
fn shortened(dir: &Path, name: &str, replace: &[(&str, &str)]) -> PathBuf {
    let e = experiments();
    let mut text = std::fs::read_to_string(e.join(name))
        .unwrap()
        .replace("\"imu/", &format!("\"{}/imu/", e.display()))
        .replace("\"schemes/", &format!("\"{}/schemes/", e.display()));
    for (from, to) in replace {
        text = text.replace(from, to);
    }
    let p = dir.join(format!("short_{name}"));
    std::fs::write(&p, text).unwrap();
    p
}

/// The navigation experiment cut to 1.2 h (alignment, 10 min stationary, 10 min of each
/// pattern with 6 min stationary between).
fn short_navigation(dir: &Path) -> PathBuf {
    shortened(
        dir,
        "paper_navigation.toml",
        &[
            ("duration_s = 16800.0", "duration_s = 600.0"),
            ("duration_s = 9600.0", "duration_s = 600.0"),
            ("duration_h = 1.0", "duration_h = 0.1"),
        ],
    )
}

/// The truth IMU's calibration with one pass of the 18-step scheme (1.3 h).
fn short_calibration(dir: &Path) -> PathBuf {
    shortened(
        dir,
        "paper_truth_calibration.toml",
        &[
            ("total_s = 13920.0", "total_s = 3480.0"),
            ("repeat = 4", "repeat = 1"),
            ("duration_s = 15120.0", "duration_s = 4680.0"),
        ],
    )
}

#[test]
fn a_blind_campaign_grades_as_the_blind_suite_does() {
    use sins_gap::blind::plan::SuiteShape;
    use sins_gap::blind::suite::{SuiteConfig, run_suite};
    let tmp = tempfile::tempdir().unwrap();
    let (cal, nav) = (short_calibration(tmp.path()), short_navigation(tmp.path()));
    let cfg = tmp.path().join("blind.toml");
    std::fs::write(
        &cfg,
        format!(
            "schema = 1\nname = \"b\"\nkind = \"blind\"\nseed = 3\n[blind]\ncases = 2\nnull = 1\noutside = 0\nruns = [\"nav1\"]\ncalibration_experiment = \"{}\"\nnavigation_experiment = \"{}\"\n",
            cal.display(),
            nav.display()
        ),
    )
    .unwrap();
    let dir = tmp.path().join("campaign");
    plan(&cfg, &dir, &ctx()).unwrap();
    // The answers are sealed at planning, before any shard runs.
    assert!(dir.join("sealed/index.json").exists());
    for s in [1, 0] {
        open(&dir, &ctx()).unwrap().run_shard(s).unwrap();
    }
    open(&dir, &ctx()).unwrap().reduce().unwrap();
    let suite = SuiteConfig {
        out: tmp.path().join("suite"),
        suite_seed: 3,
        shape: SuiteShape {
            cases: 2,
            null_cases: 1,
            out_of_catalogue: 0,
            ..SuiteShape::default()
        },
        calibration_experiment: cal,
        histories_experiment: nav.clone(),
        navigation_experiment: nav,
        navigation_runs: vec!["nav1".into()],
        keep_datasets: false,
        only: vec![],
        diagnose: sins_diag::input::DiagnoseConfig::default(),
        identified_noise: false,
    };
    struct Quiet;
    impl sins_report::Progress for Quiet {
        fn begin(&mut self, _: &str, _: u64) {}
        fn advance(&mut self, _: u64) {}
        fn end(&mut self) {}
    }
    let result = run_suite(&suite, &mut Quiet).unwrap();
    let summary: serde_json::Value =
        serde_json::from_slice(&read(&dir.join("summary.json"))).unwrap();
    assert_eq!(
        summary["suite_sha256"],
        serde_json::json!(result.index.suite_sha256)
    );
    assert_eq!(
        summary["grades"],
        serde_json::to_value(&result.grades).unwrap()
    );
    // The report is the suite's, without its timing table.
    let md = String::from_utf8(read(&dir.join("report.md"))).unwrap();
    assert!(
        result.markdown.starts_with(&md),
        "campaign report differs from the suite's"
    );
}
