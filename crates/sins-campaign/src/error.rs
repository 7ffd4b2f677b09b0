//! Errors of a campaign: every message names the file, key or shard concerned.

use std::path::PathBuf;

/// Why a campaign step could not be done.
#[derive(Debug, thiserror::Error)]
pub enum CampaignError {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// The campaign file is not valid (unknown kind, missing key, bad value).
    #[error("{path}: {message}")]
    Spec {
        /// The campaign file.
        path: PathBuf,
        /// What is wrong, naming the key.
        message: String,
    },
    /// The campaign directory does not belong to this campaign, this build, or was altered.
    #[error("{path}: {message}")]
    Manifest {
        /// The manifest (or directory) concerned.
        path: PathBuf,
        /// What does not match.
        message: String,
    },
    /// A shard index outside the plan.
    #[error(
        "shard index {index} is out of range: the campaign in {dir} has {shards} shards (0..{shards})"
    )]
    ShardOutOfRange {
        /// The campaign directory.
        dir: PathBuf,
        /// The index asked for.
        index: usize,
        /// Number of shards.
        shards: usize,
    },
    /// Shards without a result: the reduce refuses to report on a partial set.
    #[error(
        "{missing_count} of {shards} shards have no result in {dir}: {missing} (run them with `sinsbench campaign shard {dir} --index I`, then reduce again)"
    )]
    MissingShards {
        /// The campaign directory.
        dir: PathBuf,
        /// Their indices, in Slurm array syntax.
        missing: String,
        /// How many.
        missing_count: usize,
        /// Number of shards.
        shards: usize,
    },
    /// Shard results that are there but damaged (see `crate::shard`): the reduce uses none.
    #[error(
        "{count} of {shards} shard results in {dir} are damaged and were not used: {details}; run those shards again with `sinsbench campaign shard {dir} --index I` (I = {indices}; it keeps each damaged file aside as shard-IIIII.json.damaged-N), then reduce again"
    )]
    DamagedShards {
        /// The campaign directory.
        dir: PathBuf,
        /// Their indices, in Slurm array syntax.
        indices: String,
        /// How many.
        count: usize,
        /// Number of shards.
        shards: usize,
        /// Each damaged file and what is wrong with it (and the shards without any result).
        details: String,
    },
    /// A shard's result file is not what its shard must hold.
    #[error("{path}: {message}")]
    BadShard {
        /// The shard file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The work of a job failed.
    #[error("job {job}: {message}")]
    Job {
        /// The job index.
        job: usize,
        /// The underlying error.
        message: String,
    },
}

impl CampaignError {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}
