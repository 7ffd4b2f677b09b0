//! A shard's result file: what it holds, how it is checked against the manifest before anything
//! uses it, and where a damaged one is kept.
//!
//! A result is *damaged* when it is there but cannot be trusted: empty, truncated, not JSON, of
//! another plan, of another shard, with one outcome too few or too many, or with an outcome of
//! the wrong shape for the campaign's kind (e.g. per-seed arrays shorter than a 42-state
//! calibration's). A damaged result counts as missing: `status` lists it for resubmission,
//! `shard` keeps it aside as `shard-IIIII.json.damaged-N` and runs the shard again, and the reduce
//! names it instead of using it.

use crate::CampaignError;
use crate::kinds::check_shape;
use crate::manifest::Manifest;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// One shard's result as written to `DIR/shards/shard-IIIII.json`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ShardResult {
    /// The SHA-256 of the manifest of the plan it belongs to.
    pub manifest_sha256: String,
    /// Its shard index.
    pub shard: usize,
    /// Its jobs, `[start, end)`.
    pub jobs: [usize; 2],
    /// The host that ran it.
    pub host: String,
    /// Its wall time (s).
    pub wall_s: f64,
    /// One outcome per job, in job order.
    pub outcomes: Vec<serde_json::Value>,
}

/// What is at a shard's result path.
#[derive(Clone, Debug)]
pub enum ShardState {
    /// Nothing: the shard has not run, or did not finish.
    Missing,
    /// A file that is not a usable result of this shard; what is wrong with it.
    Damaged(String),
    /// A result that passed every check.
    Done(ShardResult),
}

/// Parses the bytes of shard `s`'s result file and checks them against `manifest`: the plan's
/// hash, the shard's index and job range, one outcome per job, each of the shape of the
/// campaign's kind. The error says what is wrong, for a reader who has the file's name.
pub fn parse_shard(bytes: &[u8], manifest: &Manifest, s: usize) -> Result<ShardResult, String> {
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err("is empty".into());
    }
    let f: ShardResult = serde_json::from_slice(bytes)
        .map_err(|e| format!("is truncated or not a shard result ({e})"))?;
    if f.manifest_sha256 != manifest.manifest_sha256 {
        return Err(format!(
            "belongs to another plan (manifest SHA-256 {}…, this plan's is {}…)",
            short(&f.manifest_sha256),
            short(&manifest.manifest_sha256)
        ));
    }
    let r = manifest.shard_jobs(s);
    if f.shard != s || f.jobs != [r.start, r.end] {
        return Err(format!(
            "holds shard {} (jobs {}..{}) where shard {s} (jobs {}..{}) belongs",
            f.shard, f.jobs[0], f.jobs[1], r.start, r.end
        ));
    }
    if f.outcomes.len() != r.len() {
        return Err(format!(
            "holds {} outcomes for the {} jobs {}..{} of shard {s}",
            f.outcomes.len(),
            r.len(),
            r.start,
            r.end
        ));
    }
    for (job, o) in r.zip(&f.outcomes) {
        check_shape(&manifest.kind, o)
            .map_err(|e| format!("holds an unusable outcome of job {job}: {e}"))?;
    }
    Ok(f)
}

fn short(hash: &str) -> &str {
    hash.get(..12).unwrap_or(hash)
}

/// The result file of shard `s` of the campaign in `dir`, checked with [`parse_shard`]. An
/// error only when the file is there but cannot be read.
pub fn read_shard(dir: &Path, manifest: &Manifest, s: usize) -> Result<ShardState, CampaignError> {
    let path = shard_path(dir, s);
    match std::fs::read(&path) {
        Ok(bytes) => Ok(match parse_shard(&bytes, manifest, s) {
            Ok(f) => ShardState::Done(f),
            Err(e) => ShardState::Damaged(e),
        }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(ShardState::Missing),
        Err(e) => Err(CampaignError::io(&path, e)),
    }
}

/// The result file of shard `s`.
pub fn shard_path(dir: &Path, s: usize) -> PathBuf {
    dir.join("shards").join(format!("shard-{s:05}.json"))
}

/// A damaged result moved out of the way of its shard's new run.
#[derive(Clone, Debug, PartialEq)]
pub struct SetAside {
    /// The shard.
    pub shard: usize,
    /// Where the damaged result was.
    pub path: PathBuf,
    /// Where it is kept now.
    pub kept: PathBuf,
    /// What is wrong with it.
    pub reason: String,
}

impl std::fmt::Display for SetAside {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} {}; kept as {}, shard {} runs again",
            self.path.display(),
            self.reason,
            self.kept.display(),
            self.shard
        )
    }
}

/// Renames the damaged result `path` to `<name>.damaged-N`, N the first number not taken, and
/// returns the new path. A file already moved by another process is not an error.
pub fn set_aside(path: &Path) -> Result<PathBuf, CampaignError> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let kept = (1..)
        .map(|n| path.with_file_name(format!("{name}.damaged-{n}")))
        .find(|p| std::fs::symlink_metadata(p).is_err())
        .unwrap_or_else(|| path.with_file_name(format!("{name}.damaged")));
    match std::fs::rename(path, &kept) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(CampaignError::Io {
            path: path.to_owned(),
            source: std::io::Error::new(
                e.kind(),
                format!(
                    "a damaged result cannot be moved aside to {} ({e}); move or remove it, then run the shard again",
                    kept.display()
                ),
            ),
        }),
        _ => Ok(kept),
    }
}
