//! A campaign's shard-result reader: `sins_campaign::parse_shard` on arbitrary bytes, checked
//! against the manifest of a small calibration Monte Carlo (4 jobs, 2 per shard) as shard 0 and
//! as shard 1, as `campaign status`, `shard` and `reduce` check every result before using it
//! (a damaged result must be refused with a message, never a panic); a result it accepts holds
//! one outcome per job of its shard.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sins_campaign::manifest::FORMAT;
use sins_campaign::{BinaryId, Manifest, parse_shard};
use sinsbench_fuzz::{guard, render};
use std::sync::OnceLock;

/// The manifest the seeds were written for (fuzz/seed.sh writes the same fields and hash).
fn manifest() -> &'static Manifest {
    static M: OnceLock<Manifest> = OnceLock::new();
    M.get_or_init(|| {
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
    })
}

fuzz_target!(|data: &[u8]| {
    guard(|| {
        let m = manifest();
        for s in 0..m.shards {
            match parse_shard(data, m, s) {
                Ok(f) => assert_eq!(f.outcomes.len(), m.shard_jobs(s).len()),
                Err(e) => {
                    render(&e);
                }
            }
        }
    })
});
