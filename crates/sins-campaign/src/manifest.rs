//! The manifest of a planned campaign: what it runs (the campaign file's hash together with
//! everything its jobs read, as loaded), which build runs it, and how it splits into shards.
//! It carries its own hash, so that an edited manifest is refused rather than trusted.

use crate::CampaignError;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// Format tag of the manifest.
pub const FORMAT: &str = "sinsbench-campaign/1";

/// Which build of sinsbench planned the campaign (every shard must run the same).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct BinaryId {
    /// The package version.
    pub version: String,
    /// SHA-256 of the executable (hex).
    pub sha256: String,
}

impl BinaryId {
    /// The running executable: its version and the SHA-256 of its file.
    pub fn current(version: &str) -> Result<Self, CampaignError> {
        let exe =
            std::env::current_exe().map_err(|e| CampaignError::io("current executable", e))?;
        let mut file = std::fs::File::open(&exe).map_err(|e| CampaignError::io(&exe, e))?;
        let mut h = Sha256::new();
        std::io::copy(&mut file, &mut h).map_err(|e| CampaignError::io(&exe, e))?;
        Ok(Self {
            version: version.to_owned(),
            sha256: hex(&h.finalize()),
        })
    }
}

/// The plan of a campaign, written once to `DIR/manifest.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// [`FORMAT`].
    pub format: String,
    /// Campaign name.
    pub campaign: String,
    /// Campaign kind.
    pub kind: String,
    /// The campaign file it was planned from (absolute; its relative paths are taken from
    /// there). Its text is kept as `DIR/campaign.toml`.
    pub source: PathBuf,
    /// The experiments directory of the defaults (absolute).
    pub experiments_dir: PathBuf,
    /// Jobs in all.
    pub jobs: usize,
    /// Jobs per shard.
    pub jobs_per_shard: usize,
    /// Shards: `ceil(jobs / jobs_per_shard)`.
    pub shards: usize,
    /// SHA-256 of the campaign file's text and of everything its jobs read, as loaded.
    pub config_sha256: String,
    /// The build that planned it.
    pub binary: BinaryId,
    /// SHA-256 of this manifest with this field empty.
    pub manifest_sha256: String,
}

/// Hex of bytes.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// SHA-256 (hex) of a campaign's text and its work's fingerprint.
pub fn config_sha256(campaign_text: &str, fingerprint: &str) -> String {
    let mut h = Sha256::new();
    h.update(campaign_text.as_bytes());
    h.update([0u8]);
    h.update(fingerprint.as_bytes());
    hex(&h.finalize())
}

impl Manifest {
    /// The shard holding `job`.
    pub fn shard_of(&self, job: usize) -> usize {
        job / self.jobs_per_shard
    }

    /// The jobs of shard `s` (the fixed rule: `s·n .. min((s+1)·n, jobs)`).
    pub fn shard_jobs(&self, s: usize) -> std::ops::Range<usize> {
        let start = (s * self.jobs_per_shard).min(self.jobs);
        start..((s + 1) * self.jobs_per_shard).min(self.jobs)
    }

    fn self_hash(&self) -> String {
        let mut m = self.clone();
        m.manifest_sha256 = String::new();
        let text = serde_json::to_string(&m).unwrap_or_default();
        hex(&Sha256::digest(text.as_bytes()))
    }

    /// Fills in [`Manifest::manifest_sha256`].
    pub fn sealed(mut self) -> Self {
        self.manifest_sha256 = self.self_hash();
        self
    }

    /// The manifest as written (pretty JSON, one trailing newline).
    pub fn to_text(&self) -> String {
        format!(
            "{}\n",
            serde_json::to_string_pretty(self).unwrap_or_default()
        )
    }

    /// Reads `DIR/manifest.json` and checks its own hash and shape.
    pub fn read(dir: &Path) -> Result<Self, CampaignError> {
        let path = dir.join("manifest.json");
        let bad = |message: String| CampaignError::Manifest {
            path: path.clone(),
            message,
        };
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Err(bad(format!(
                    "no campaign planned in {} (run `sinsbench campaign plan CFG --out {}` first)",
                    dir.display(),
                    dir.display()
                )));
            }
            Err(e) => return Err(CampaignError::io(&path, e)),
        };
        let m: Manifest = serde_json::from_str(&text)
            .map_err(|e| bad(format!("not a campaign manifest: {e}")))?;
        if m.format != FORMAT {
            return Err(bad(format!("format '{}' is not {FORMAT}", m.format)));
        }
        if m.manifest_sha256 != m.self_hash() {
            return Err(bad(
                "was modified after planning (its own SHA-256 does not match); plan the campaign again into a new directory".into(),
            ));
        }
        if m.jobs_per_shard == 0 || m.shards != m.jobs.div_ceil(m.jobs_per_shard) {
            return Err(bad(format!(
                "{} shards cannot hold {} jobs of {} per shard",
                m.shards, m.jobs, m.jobs_per_shard
            )));
        }
        Ok(m)
    }

    /// Refuses a manifest planned by another build or from other inputs.
    pub fn check(
        &self,
        dir: &Path,
        config_sha256: &str,
        binary: &BinaryId,
    ) -> Result<(), CampaignError> {
        let bad = |message: String| CampaignError::Manifest {
            path: dir.join("manifest.json"),
            message,
        };
        if &self.binary != binary {
            return Err(bad(format!(
                "was planned by another sinsbench build (version {}, executable SHA-256 {}…; this is {} / {}…): every shard must run the build that planned it; plan again into a new directory",
                self.binary.version,
                &self.binary.sha256[..self.binary.sha256.len().min(12)],
                binary.version,
                &binary.sha256[..binary.sha256.len().min(12)]
            )));
        }
        if self.config_sha256 != config_sha256 {
            return Err(bad(format!(
                "the campaign's inputs changed since it was planned (configuration SHA-256 {}…, now {}…): {} or a file it reads was edited; plan again into a new directory",
                &self.config_sha256[..12.min(self.config_sha256.len())],
                &config_sha256[..12.min(config_sha256.len())],
                self.source.display()
            )));
        }
        Ok(())
    }
}

/// Slurm array syntax of sorted indices, ranges compressed: `0-3,7,9-12`.
pub fn array_syntax(indices: &[usize]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < indices.len() {
        let mut j = i;
        while j + 1 < indices.len() && indices[j + 1] == indices[j] + 1 {
            j += 1;
        }
        parts.push(if j > i {
            format!("{}-{}", indices[i], indices[j])
        } else {
            indices[i].to_string()
        });
        i = j + 1;
    }
    parts.join(",")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_follow_the_fixed_rule_and_ranges_compress() {
        let m = Manifest {
            format: FORMAT.into(),
            campaign: "c".into(),
            kind: "blind".into(),
            source: "c.toml".into(),
            experiments_dir: "e".into(),
            jobs: 7,
            jobs_per_shard: 3,
            shards: 3,
            config_sha256: "x".into(),
            binary: BinaryId {
                version: "v".into(),
                sha256: "y".into(),
            },
            manifest_sha256: String::new(),
        };
        assert_eq!(m.shard_jobs(0), 0..3);
        assert_eq!(m.shard_jobs(2), 6..7);
        assert_eq!(m.shard_of(6), 2);
        assert_eq!(array_syntax(&[0, 1, 2, 3, 7, 9, 10, 11, 12]), "0-3,7,9-12");
        assert_eq!(array_syntax(&[]), "");
        assert_eq!(array_syntax(&[4]), "4");
    }
}
