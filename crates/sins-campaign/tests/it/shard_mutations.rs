//! The shard-result reader under damage it was not written for (issue 30: no panic anywhere in
//! the reduce): seeded mutations of the valid and damaged results in `fuzz/seeds/shard_result`,
//! read as both shards of their manifest, as `status`, `shard` and `reduce` read them. Byte
//! edits (flips, inserts, deletes, truncation, splices of two files) and structural edits of the
//! JSON (a key removed, a value replaced by an extreme number, a string, null, an empty or a
//! nested container, an array cut short or lengthened) on a deterministic generator, so a
//! failure names its iteration and is reproduced by the same run.
//!
//! Every input must be refused with a message or accepted with one outcome per job of the shard,
//! each of the shape of a 42-state calibration; a panic fails the test. Not coverage-guided:
//! `just fuzz shard_result` runs the same reader under libFuzzer.

use serde_json::Value;
use sins_campaign::manifest::FORMAT;
use sins_campaign::{BinaryId, Manifest, parse_shard};
use std::path::PathBuf;

/// The manifest the seeds were written for (as in fuzz/fuzz_targets/shard_result.rs).
fn manifest() -> Manifest {
    Manifest {
        format: FORMAT.into(),
        campaign: "fuzz".into(),
        kind: "calibration-mc".into(),
        source: "fuzz.toml".into(),
        experiments_dir: "experiments".into(),
        jobs: 4,
        jobs_per_shard: 2,
        shards: 2,
        config_sha256: "0".repeat(64),
        binary: BinaryId {
            version: "fuzz".into(),
            sha256: "0".repeat(64),
        },
        manifest_sha256: String::new(),
    }
    .sealed()
}

/// SplitMix64: a small deterministic generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn seeds() -> Vec<Vec<u8>> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/shard_result");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("fuzz/seeds/shard_result")
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files.iter().map(|p| std::fs::read(p).unwrap()).collect()
}

/// A replacement for any JSON value: the edges a reader must survive.
fn odd_value(rng: &mut Rng) -> Value {
    match rng.below(12) {
        0 => Value::Null,
        1 => serde_json::json!(0),
        2 => serde_json::json!(-1),
        3 => serde_json::json!(1e308),
        4 => serde_json::json!(-1e308),
        5 => serde_json::json!(u64::MAX),
        6 => serde_json::json!(i64::MIN),
        7 => serde_json::json!("x"),
        8 => serde_json::json!([]),
        9 => serde_json::json!({}),
        10 => serde_json::json!([[1.0, 2.0], {"a": null}]),
        _ => serde_json::json!(true),
    }
}

/// Every path (object keys and array indices) in `v`, parents before children.
fn paths(v: &Value, here: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    out.push(here.clone());
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                here.push(Step::Key(k.clone()));
                paths(x, here, out);
                here.pop();
            }
        }
        Value::Array(a) => {
            // The first and last elements stand for the rest (arrays of 33-42 equal values).
            for i in [0, a.len().saturating_sub(1)] {
                if let Some(x) = a.get(i) {
                    here.push(Step::Index(i));
                    paths(x, here, out);
                    here.pop();
                }
            }
        }
        _ => {}
    }
}

#[derive(Clone)]
enum Step {
    Key(String),
    Index(usize),
}

fn at<'a>(v: &'a mut Value, path: &[Step]) -> Option<&'a mut Value> {
    path.iter().try_fold(v, |v, s| match s {
        Step::Key(k) => v.get_mut(k.as_str()),
        Step::Index(i) => v.get_mut(*i),
    })
}

/// One structural edit of the JSON of `bytes`.
fn structural(bytes: &[u8], rng: &mut Rng) -> Vec<u8> {
    let Ok(mut v) = serde_json::from_slice::<Value>(bytes) else {
        return bytes.to_vec();
    };
    let mut all = Vec::new();
    paths(&v, &mut Vec::new(), &mut all);
    let path = all[rng.below(all.len())].clone();
    let choice = rng.below(4);
    let extra = rng.next();
    if choice == 0 {
        // Remove the node from its parent.
        if let Some((last, parent)) = path.split_last()
            && let Some(p) = at(&mut v, parent)
        {
            match (p, last) {
                (Value::Object(m), Step::Key(k)) => {
                    m.remove(k);
                }
                (Value::Array(a), Step::Index(i)) if *i < a.len() => {
                    a.remove(*i);
                }
                _ => {}
            }
        }
    } else if let Some(node) = at(&mut v, &path) {
        match (choice, node) {
            (1, Value::Array(a)) => a.truncate(extra as usize % (a.len() + 1)),
            (2, Value::Array(a)) if !a.is_empty() => {
                let x = a[0].clone();
                a.extend(std::iter::repeat_n(x, 1 + extra as usize % 3));
            }
            (_, node) => *node = odd_value(rng),
        }
    }
    serde_json::to_vec(&v).unwrap()
}

/// One to eight byte edits, a truncation, or a splice with another seed.
fn bytewise(bytes: &[u8], other: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut b = bytes.to_vec();
    match rng.below(4) {
        0 => b.truncate(rng.below(b.len() + 1)),
        1 => {
            let cut = rng.below(b.len() + 1);
            let from = rng.below(other.len() + 1);
            b.truncate(cut);
            b.extend_from_slice(&other[from..]);
        }
        _ => {
            for _ in 0..1 + rng.below(8) {
                let i = rng.below(b.len() + 1);
                match rng.below(3) {
                    0 if i < b.len() => b[i] ^= 1 << rng.below(8),
                    1 => {
                        const BYTES: &[u8] = b"{}[],:\"0-e.9 \\\xff";
                        b.insert(i, BYTES[rng.below(BYTES.len())]);
                    }
                    _ if i < b.len() => {
                        b.remove(i);
                    }
                    _ => {}
                }
            }
        }
    }
    b
}

/// An accepted outcome has every per-coefficient array at 33 and every per-state array at 42
/// (what the Table 1 reduce indexes).
fn assert_shape(o: &Value, it: usize) {
    let len = |v: Option<&Value>| v.and_then(Value::as_array).map(Vec::len);
    for (key, n) in [
        ("estimate", 33),
        ("error", 33),
        ("sigma", 33),
        ("sigma_ratio", 42),
    ] {
        assert_eq!(
            len(o["outcome"].get(key)),
            Some(n),
            "iteration {it}: outcome.{key}"
        );
    }
    for (key, n) in [
        ("initial_sigma_si", 42),
        ("final_sigma_si", 42),
        ("estimate_si", 33),
    ] {
        assert_eq!(len(o.get(key)), Some(n), "iteration {it}: {key}");
    }
}

#[test]
fn damaged_shard_results_are_refused_or_whole_never_a_panic() {
    let m = manifest();
    let seeds = seeds();
    assert!(
        seeds.len() >= 3,
        "fuzz/seeds/shard_result holds {}",
        seeds.len()
    );
    // The seeds themselves: both shards whole are accepted where they belong, the cut one refused.
    let accepted_seeds = seeds
        .iter()
        .filter(|b| (0..m.shards).any(|s| parse_shard(b, &m, s).is_ok()))
        .count();
    assert_eq!(accepted_seeds, 2, "the two whole seeds are results");
    let mut rng = Rng(20_261_128);
    let iterations = 60_000;
    let (mut accepted, mut refused) = (0usize, 0usize);
    for it in 0..iterations {
        let a = &seeds[rng.below(seeds.len())];
        let b = &seeds[rng.below(seeds.len())];
        let mut input = if rng.below(2) == 0 {
            structural(a, &mut rng)
        } else {
            bytewise(a, b, &mut rng)
        };
        // Some inputs get a second edit of the other kind.
        if rng.below(4) == 0 {
            input = structural(&input, &mut rng);
        }
        for s in 0..m.shards {
            let r = std::panic::catch_unwind(|| parse_shard(&input, &m, s));
            match r {
                Err(_) => panic!(
                    "iteration {it}, shard {s}: the reader panicked on {}",
                    String::from_utf8_lossy(&input)
                ),
                Ok(Ok(f)) => {
                    assert_eq!(f.outcomes.len(), m.shard_jobs(s).len(), "iteration {it}");
                    for o in &f.outcomes {
                        assert_shape(o, it);
                    }
                    accepted += 1;
                }
                Ok(Err(e)) => {
                    assert!(!e.is_empty(), "iteration {it}: an empty message");
                    refused += 1;
                }
            }
        }
    }
    eprintln!(
        "{iterations} mutated results x {} shards: {accepted} accepted, {refused} refused, 0 panics",
        m.shards
    );
    // Not vacuous: mutations that leave a result usable (a changed host or number) are accepted,
    // and most are refused.
    assert!(
        accepted > 100 && refused > iterations,
        "{accepted} / {refused}"
    );
}
