//! Built-in defaults: where the project's experiment definitions live.

use std::path::PathBuf;

/// The `experiments/` folder: `./experiments` when run from the repository, else the copy next
/// to this crate's sources (so `cargo run` works from any directory of the checkout).
pub fn experiments_dir() -> PathBuf {
    let local = PathBuf::from("experiments");
    if local.is_dir() {
        return local;
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments")
}

/// The default experiment of `simulate`: the paper's 15 h navigation runs.
pub fn navigation_experiment() -> PathBuf {
    experiments_dir().join("paper_navigation.toml")
}

/// The default configuration of `report`: the built-in replica of the paper's Table 5.
pub fn report_config() -> PathBuf {
    experiments_dir().join("harness/report_paper.toml")
}
