//! Damaged shard results: a file that is there but cannot be trusted (empty, truncated, per-seed
//! arrays of the wrong length, another seed's outcome) is never used and never panics the
//! reduce; it counts as missing for `status`, and is kept aside when its shard runs again.
//! The shard files here are written by hand (the outcomes' numbers are made up), so nothing
//! is simulated.

use sins_calstudy::montecarlo::{McRunOutcome, SeedOutcome};
use sins_campaign::{BinaryId, Context, Manifest, open, parse_shard, plan, shard_path, status};
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

/// A calibration Monte Carlo of 3 seeds (5, 6, 7) and the noise-free run: 4 jobs, 2 per shard,
/// planned into `dir/run`.
fn planned(dir: &Path) -> (PathBuf, Manifest) {
    let cfg = dir.join("short.toml");
    std::fs::write(
        &cfg,
        format!(
            "schema = 1\nname = \"short\"\nkind = \"calibration-mc\"\nseed = 5\njobs_per_shard = 2\n\n[calibration_mc]\nseeds = 3\nexperiment = \"{}\"\nmax_duration_s = 1800.0\n",
            experiments().join("paper_calibration.toml").display()
        ),
    )
    .unwrap();
    let run = dir.join("run");
    let (m, _) = plan(&cfg, &run, &ctx()).unwrap();
    (run, m)
}

/// An outcome of a 42-state calibration of `seed` (33 coefficients, 42 states), numbers made up.
fn outcome(seed: u64) -> McRunOutcome {
    McRunOutcome {
        outcome: SeedOutcome {
            seed,
            estimate: vec![1.0; 33],
            error: vec![0.1; 33],
            sigma: vec![0.2; 33],
            nees: 33.0,
            sigma_ratio: vec![0.05; 42],
            max_normalized_innovation: 1.0,
        },
        initial_sigma_si: vec![1e-3; 42],
        final_sigma_si: vec![5e-5; 42],
        estimate_si: vec![1e-6; 33],
    }
}

/// The seed of each job: 5, 6, 7, then the noise-free run with the experiment's own seed.
fn seeds() -> Vec<u64> {
    let own = sins_config::load_experiment(experiments().join("paper_calibration.toml"))
        .unwrap()
        .scenarios[0]
        .seed;
    vec![5, 6, 7, own]
}

/// The text of shard `s`'s result file holding `outcomes`.
fn shard_text(m: &Manifest, s: usize, outcomes: &[McRunOutcome]) -> String {
    let r = m.shard_jobs(s);
    serde_json::json!({
        "manifest_sha256": m.manifest_sha256,
        "shard": s,
        "jobs": [r.start, r.end],
        "host": "test",
        "wall_s": 1.0,
        "outcomes": outcomes,
    })
    .to_string()
}

/// Writes both shards from the made-up outcomes, `edit` applied to each outcome (by job) first.
fn write_shards(dir: &Path, m: &Manifest, edit: impl Fn(usize, &mut McRunOutcome)) {
    let all: Vec<McRunOutcome> = seeds()
        .into_iter()
        .enumerate()
        .map(|(job, seed)| {
            let mut o = outcome(seed);
            edit(job, &mut o);
            o
        })
        .collect();
    for s in 0..m.shards {
        let r = m.shard_jobs(s);
        std::fs::write(shard_path(dir, s), shard_text(m, s, &all[r])).unwrap();
    }
}

fn reduce_error(dir: &Path) -> String {
    match open(dir, &ctx()).unwrap().reduce() {
        Ok(_) => panic!("a damaged shard must be refused"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn reduce_names_per_seed_arrays_of_the_wrong_length_instead_of_panicking() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, m) = planned(tmp.path());
    // Well-formed, the made-up shards reduce.
    write_shards(&dir, &m, |_, _| {});
    open(&dir, &ctx()).unwrap().reduce().unwrap();
    std::fs::remove_file(dir.join("summary.json")).unwrap();
    // Seed 7's per-seed arrays cut short (was: index out of bounds in Table 1's assembly).
    write_shards(&dir, &m, |job, o| {
        if job == 2 {
            o.outcome.error.truncate(30);
            o.outcome.sigma.truncate(30);
        }
    });
    let e = reduce_error(&dir);
    for needle in [
        "1 of 2 shard results",
        "are damaged and were not used",
        "shard-00001.json",
        "holds an unusable outcome of job 2: error has",
        "error has 30 values where a 42-state calibration has 33",
        "--index I` (I = 1;",
    ] {
        assert!(e.contains(needle), "'{needle}' missing from: {e}");
    }
    // One state too many in the first seed's observability (was: index out of bounds).
    write_shards(&dir, &m, |job, o| {
        if job == 0 {
            o.initial_sigma_si.push(1.0);
        }
    });
    let e = reduce_error(&dir);
    assert!(
        e.contains("shard-00000.json")
            && e.contains("initial_sigma_si has 43 values where a 42-state calibration has 42"),
        "{e}"
    );
    // Another seed's outcome in job 1's place.
    write_shards(&dir, &m, |job, o| {
        if job == 1 {
            o.outcome.seed = 99;
        }
    });
    let e = reduce_error(&dir);
    assert!(
        e.contains("shard-00000.json holds an unusable outcome of job 1 (seed 6): it is the outcome of seed 99, where seed 6 belongs"),
        "{e}"
    );
    assert!(
        !dir.join("summary.json").exists(),
        "nothing reduced from damaged shards"
    );
}

#[test]
fn damaged_results_count_as_missing_and_are_kept_aside() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, m) = planned(tmp.path());
    write_shards(&dir, &m, |_, _| {});
    assert!(status(&dir).unwrap().missing.is_empty());
    let good = std::fs::read_to_string(shard_path(&dir, 1)).unwrap();
    let truncated = &good[..good.len() / 2];
    std::fs::write(shard_path(&dir, 0), "").unwrap();
    std::fs::write(shard_path(&dir, 1), truncated).unwrap();
    let st = status(&dir).unwrap();
    assert_eq!(st.missing, [0, 1]);
    assert_eq!(st.damaged.len(), 2);
    assert_eq!(st.damaged[0], (0, "is empty".to_string()));
    assert!(
        st.damaged[1]
            .1
            .starts_with("is truncated or not a shard result (EOF while parsing"),
        "{:?}",
        st.damaged
    );
    let opened = open(&dir, &ctx()).unwrap();
    assert_eq!(opened.missing().unwrap(), [0, 1]);
    // Kept aside under the first free name, byte for byte; then the shard is simply missing.
    let aside = opened
        .set_aside_damaged(1)
        .unwrap()
        .expect("shard 1 is damaged");
    let kept = dir.join("shards/shard-00001.json.damaged-1");
    assert_eq!(aside.kept, kept);
    assert_eq!(std::fs::read_to_string(&kept).unwrap(), truncated);
    assert!(!shard_path(&dir, 1).exists());
    assert_eq!(
        aside.to_string(),
        format!(
            "{} {}; kept as {}, shard 1 runs again",
            shard_path(&dir, 1).display(),
            aside.reason,
            kept.display()
        )
    );
    assert_eq!(opened.set_aside_damaged(1).unwrap(), None);
    std::fs::write(shard_path(&dir, 1), "{}").unwrap();
    let again = opened.set_aside_damaged(1).unwrap().unwrap();
    assert_eq!(again.kept, dir.join("shards/shard-00001.json.damaged-2"));
    let st = status(&dir).unwrap();
    assert_eq!((st.missing, st.damaged.len()), (vec![0, 1], 1));
    // A reduce refuses, naming the damaged file and the missing shard.
    let e = reduce_error(&dir);
    assert!(
        e.contains("shard-00000.json is empty") && e.contains("no result at all: 1"),
        "{e}"
    );
}

#[test]
fn the_reader_refuses_every_truncation_and_never_panics() {
    let tmp = tempfile::tempdir().unwrap();
    let (_, m) = planned(tmp.path());
    let text = shard_text(&m, 1, &[outcome(7), outcome(seeds()[3])]);
    let bytes = text.as_bytes();
    assert!(parse_shard(bytes, &m, 1).is_ok());
    for n in 0..bytes.len() {
        assert!(
            parse_shard(&bytes[..n], &m, 1).is_err(),
            "a prefix of {n} bytes was accepted"
        );
    }
    for k in (0..bytes.len()).step_by(7) {
        let mut b = bytes.to_vec();
        b[k] ^= 0x5a;
        let _ = parse_shard(&b, &m, 1);
    }
    // The right file in the wrong place: refused.
    let e = parse_shard(bytes, &m, 0).unwrap_err();
    assert!(
        e.contains("holds shard 1 (jobs 2..4) where shard 0 (jobs 0..2) belongs"),
        "{e}"
    );
}
