//! A campaign as data: `experiments/campaigns/*.toml` names the work (its kind), its size and
//! its seed, and how many jobs make one shard. Paths inside are relative to the file.

use crate::CampaignError;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The kinds of campaign, as the file spells them.
pub const KINDS: [&str; 4] = ["blind", "calibration-mc", "replica-uq", "reports"];

/// A campaign file, resolved: paths absolute or relative to the working directory.
#[derive(Clone, Debug, PartialEq)]
pub struct Campaign {
    /// Name (reports and the manifest carry it).
    pub name: String,
    /// One line on what the campaign is for.
    pub description: String,
    /// Master seed, where the kind takes one (`None`: the kind's own default).
    pub seed: Option<u64>,
    /// Jobs per shard (the fixed rule: shard `s` holds jobs `s·n .. (s+1)·n`).
    pub jobs_per_shard: usize,
    /// The work.
    pub kind: Kind,
}

/// What a campaign runs.
#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    /// The blind validation suite of the gap diagnosis: one job per case.
    Blind {
        /// Cases in all.
        cases: usize,
        /// Of which without a hidden effect.
        null: usize,
        /// Of which with an effect outside the catalogue.
        outside: usize,
        /// Cases with an effect local in time, drawn after the `cases` others.
        time_local: usize,
        /// Cases of the widened time-local draw (shapes outside the scan's own, one run, every
        /// navigation run or the calibration run only), drawn after those.
        wide_time_local: usize,
        /// Cases with a temperature-driven effect whose runs have different chamber
        /// histories, drawn last.
        different_histories: usize,
        /// The navigation experiment of those cases.
        histories_experiment: PathBuf,
        /// The twin's noise identified from each case's datasets, not the noise file.
        identified_noise: bool,
        /// Navigation runs recorded per case.
        runs: Vec<String>,
        /// The "real" IMU's calibration experiment.
        calibration_experiment: PathBuf,
        /// The navigation experiment whose runs each case records.
        navigation_experiment: PathBuf,
    },
    /// The Table 1 calibration Monte Carlo: one job per seed, then the noise-free run.
    CalibrationMc {
        /// Monte Carlo seeds.
        seeds: usize,
        /// The calibration experiment (its first run).
        experiment: PathBuf,
        /// Directory of the paper's tables.
        reference_dir: PathBuf,
        /// Cut the motion after this many seconds (shortened studies, tests).
        max_duration_s: Option<f64>,
    },
    /// The replica of Table 5 as a prediction: one job per Monte Carlo sample.
    ReplicaUq {
        /// The assumptions file.
        assumptions: PathBuf,
        /// Main samples (`None`: the file's).
        samples: Option<usize>,
        /// Samples per candidate (`None`: the file's).
        candidate_samples: Option<usize>,
        /// Pick-freeze rows (`None`: the file's).
        pick_freeze: Option<usize>,
    },
    /// A list of report configurations: one job per configuration (and per noise seed).
    Reports {
        /// The configurations.
        configs: Vec<PathBuf>,
        /// Run each configuration this many times, with sensor-noise seeds K..K+N-1 (the
        /// release gate's `--baseline`); `None`: once, with the experiment files' seeds.
        noise_seeds: Option<u64>,
        /// K, the first sensor-noise seed (`first_noise_seed`, default 1): a second campaign
        /// of the same release on seeds disjoint from the first (a gate's false-failure check).
        first_noise_seed: u64,
    },
}

impl Kind {
    /// The kind's name as the file spells it.
    pub fn name(&self) -> &'static str {
        match self {
            Kind::Blind { .. } => KINDS[0],
            Kind::CalibrationMc { .. } => KINDS[1],
            Kind::ReplicaUq { .. } => KINDS[2],
            Kind::Reports { .. } => KINDS[3],
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    schema: u32,
    name: String,
    #[serde(default)]
    description: String,
    kind: String,
    seed: Option<u64>,
    jobs_per_shard: Option<usize>,
    blind: Option<BlindFile>,
    calibration_mc: Option<CalMcFile>,
    replica_uq: Option<UqFile>,
    reports: Option<ReportsFile>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct BlindFile {
    cases: Option<usize>,
    null: Option<usize>,
    outside: Option<usize>,
    time_local: Option<usize>,
    wide_time_local: Option<usize>,
    different_histories: Option<usize>,
    histories_experiment: Option<String>,
    identified_noise: Option<bool>,
    runs: Option<Vec<String>>,
    calibration_experiment: Option<String>,
    navigation_experiment: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CalMcFile {
    seeds: usize,
    experiment: Option<String>,
    reference_dir: Option<String>,
    max_duration_s: Option<f64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct UqFile {
    assumptions: Option<String>,
    samples: Option<usize>,
    candidate_samples: Option<usize>,
    pick_freeze: Option<usize>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ReportsFile {
    configs: Vec<String>,
    noise_seeds: Option<u64>,
    first_noise_seed: Option<u64>,
}

/// Reads a campaign file. Relative paths inside it are taken from the file's directory; paths
/// it leaves out default to the files of `experiments_dir`.
pub fn load_campaign(path: &Path, experiments_dir: &Path) -> Result<Campaign, CampaignError> {
    let text = std::fs::read_to_string(path).map_err(|e| CampaignError::io(path, e))?;
    parse_campaign(&text, path, experiments_dir)
}

/// Parses a campaign file's text (`path` names it in errors and anchors relative paths).
pub fn parse_campaign(
    text: &str,
    path: &Path,
    experiments_dir: &Path,
) -> Result<Campaign, CampaignError> {
    let bad = |message: String| CampaignError::Spec {
        path: path.to_owned(),
        message,
    };
    let f: File = toml::from_str(text).map_err(|e| bad(e.to_string().trim_end().to_owned()))?;
    if f.schema != 1 {
        return Err(bad(format!(
            "schema = {} is not supported (1 is)",
            f.schema
        )));
    }
    if f.name.trim().is_empty() || f.name.contains(['/', '\\']) {
        return Err(bad(format!(
            "name = '{}': give a non-empty name without slashes",
            f.name
        )));
    }
    let jobs_per_shard = f.jobs_per_shard.unwrap_or(1);
    if !(1..=100_000).contains(&jobs_per_shard) {
        return Err(bad(format!(
            "jobs_per_shard = {jobs_per_shard}: must be 1 to 100000"
        )));
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    let rel = |p: &Option<String>, default: &str| -> PathBuf {
        p.as_ref()
            .map_or_else(|| experiments_dir.join(default), |p| dir.join(p))
    };
    let present: Vec<&str> = [
        ("blind", f.blind.is_some()),
        ("calibration_mc", f.calibration_mc.is_some()),
        ("replica_uq", f.replica_uq.is_some()),
        ("reports", f.reports.is_some()),
    ]
    .iter()
    .filter(|(_, p)| *p)
    .map(|(n, _)| *n)
    .collect();
    if !KINDS.contains(&f.kind.as_str()) {
        return Err(bad(format!(
            "kind = '{}' is not a campaign kind (one of: {})",
            f.kind,
            KINDS.join(", ")
        )));
    }
    let own = f.kind.replace('-', "_");
    if let Some(other) = present.iter().find(|n| **n != own) {
        return Err(bad(format!(
            "[{other}] does not belong to a campaign of kind '{}'",
            f.kind
        )));
    }
    let kind = match f.kind.as_str() {
        "blind" => {
            let b = f.blind.unwrap_or_default();
            let kind = Kind::Blind {
                cases: b.cases.unwrap_or(30),
                null: b.null.unwrap_or(5),
                outside: b.outside.unwrap_or(3),
                time_local: b.time_local.unwrap_or(0),
                wide_time_local: b.wide_time_local.unwrap_or(0),
                different_histories: b.different_histories.unwrap_or(0),
                histories_experiment: rel(
                    &b.histories_experiment,
                    "blind/navigation_varied_histories.toml",
                ),
                identified_noise: b.identified_noise.unwrap_or(false),
                runs: b.runs.unwrap_or_else(|| vec!["nav1".into(), "nav2".into()]),
                calibration_experiment: rel(
                    &b.calibration_experiment,
                    "paper_truth_calibration.toml",
                ),
                navigation_experiment: rel(&b.navigation_experiment, "paper_navigation.toml"),
            };
            if let Kind::Blind {
                cases,
                null,
                outside,
                ..
            } = &kind
                && (*cases == 0 || null + outside > *cases || *cases > 999)
            {
                return Err(bad(format!(
                    "[blind] cases = {cases}, null = {null}, outside = {outside}: need 1 to 999 cases and null + outside <= cases"
                )));
            }
            kind
        }
        "calibration-mc" => {
            let c = f.calibration_mc.ok_or_else(|| {
                bad("kind 'calibration-mc' needs a [calibration_mc] table with `seeds`".into())
            })?;
            if !(1..=100_000).contains(&c.seeds) {
                return Err(bad(format!(
                    "[calibration_mc] seeds = {}: must be 1 to 100000",
                    c.seeds
                )));
            }
            if let Some(d) = c.max_duration_s
                && !(d.is_finite() && d > 0.0)
            {
                return Err(bad(format!(
                    "[calibration_mc] max_duration_s = {d}: must be a positive number of seconds"
                )));
            }
            Kind::CalibrationMc {
                seeds: c.seeds,
                experiment: rel(&c.experiment, "paper_calibration.toml"),
                reference_dir: rel(&c.reference_dir, "reference"),
                max_duration_s: c.max_duration_s,
            }
        }
        "replica-uq" => {
            let u = f.replica_uq.unwrap_or_default();
            Kind::ReplicaUq {
                assumptions: rel(&u.assumptions, "replica/assumptions.toml"),
                samples: u.samples,
                candidate_samples: u.candidate_samples,
                pick_freeze: u.pick_freeze,
            }
        }
        "reports" => {
            let r = f.reports.ok_or_else(|| {
                bad("kind 'reports' needs a [reports] table with `configs`".into())
            })?;
            if r.configs.is_empty() {
                return Err(bad(
                    "[reports] configs is empty: name at least one report configuration".into(),
                ));
            }
            if f.seed.is_some() {
                return Err(bad("seed: a 'reports' campaign takes its seeds from each report configuration; remove `seed`".into()));
            }
            if r.noise_seeds == Some(0) {
                return Err(bad(
                    "[reports] noise_seeds = 0: give the number of sensor-noise seeds (1 or more), or leave the key out".into(),
                ));
            }
            let first_noise_seed = match (r.first_noise_seed, r.noise_seeds) {
                (Some(0), _) => {
                    return Err(bad(
                        "[reports] first_noise_seed = 0: sensor-noise seeds start at 1".into(),
                    ));
                }
                (Some(k), None) => {
                    return Err(bad(format!(
                        "[reports] first_noise_seed = {k} without noise_seeds: give noise_seeds = N as well (the seeds are first_noise_seed .. first_noise_seed + N - 1)"
                    )));
                }
                (Some(k), Some(n)) if k.checked_add(n).is_none() => {
                    return Err(bad(format!(
                        "[reports] first_noise_seed = {k} with noise_seeds = {n} runs past the largest seed"
                    )));
                }
                (k, _) => k.unwrap_or(1),
            };
            Kind::Reports {
                configs: r.configs.iter().map(|c| dir.join(c)).collect(),
                noise_seeds: r.noise_seeds,
                first_noise_seed,
            }
        }
        other => {
            return Err(bad(format!(
                "kind = '{other}' is not a campaign kind (one of: {})",
                KINDS.join(", ")
            )));
        }
    };
    Ok(Campaign {
        name: f.name,
        description: f.description,
        seed: f.seed,
        jobs_per_shard,
        kind,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Campaign, String> {
        parse_campaign(text, Path::new("dir/c.toml"), Path::new("exp")).map_err(|e| e.to_string())
    }

    #[test]
    fn a_calibration_campaign_resolves_its_paths_and_defaults() {
        let c = parse("schema = 1\nname = \"s\"\nkind = \"calibration-mc\"\nseed = 7\njobs_per_shard = 2\n[calibration_mc]\nseeds = 4\nexperiment = \"../x.toml\"\n").unwrap();
        assert_eq!(c.seed, Some(7));
        assert_eq!(c.jobs_per_shard, 2);
        assert_eq!(
            c.kind,
            Kind::CalibrationMc {
                seeds: 4,
                experiment: PathBuf::from("dir/../x.toml"),
                reference_dir: PathBuf::from("exp/reference"),
                max_duration_s: None,
            }
        );
    }

    #[test]
    fn bad_campaign_files_are_refused_naming_the_key() {
        for (text, needle) in [
            (
                "schema = 1\nname = \"s\"\nkind = \"sweep\"\n",
                "kind = 'sweep' is not a campaign kind",
            ),
            (
                "schema = 1\nname = \"s\"\nkind = \"reports\"\n",
                "needs a [reports] table",
            ),
            (
                "schema = 1\nname = \"s\"\nkind = \"blind\"\n[replica_uq]\n",
                "[replica_uq] does not belong",
            ),
            (
                "schema = 1\nname = \"s\"\nkind = \"blind\"\njobs_per_shard = 0\n",
                "jobs_per_shard = 0",
            ),
            (
                "schema = 1\nname = \"s\"\nkind = \"blind\"\nshards = 3\n",
                "unknown field `shards`",
            ),
            (
                "schema = 1\nname = \"s\"\nkind = \"blind\"\n[blind]\ncases = 2\nnull = 3\n",
                "null + outside <= cases",
            ),
            ("schema = 2\nname = \"s\"\nkind = \"blind\"\n", "schema = 2"),
            (
                "schema = 1\nname = \"s\"\nkind = \"reports\"\nseed = 3\n[reports]\nconfigs = [\"a.toml\"]\n",
                "seed:",
            ),
            (
                "schema = 1\nname = \"s\"\nkind = \"reports\"\n[reports]\nconfigs = [\"a.toml\"]\nfirst_noise_seed = 9\n",
                "without noise_seeds",
            ),
            (
                "schema = 1\nname = \"s\"\nkind = \"reports\"\n[reports]\nconfigs = [\"a.toml\"]\nnoise_seeds = 8\nfirst_noise_seed = 0\n",
                "first_noise_seed = 0",
            ),
        ] {
            let e = parse(text).unwrap_err();
            assert!(e.contains(needle) && e.starts_with("dir/c.toml"), "{e}");
        }
    }

    #[test]
    fn noise_seeds_start_at_one_unless_first_noise_seed_says_otherwise() {
        let seeds = |extra: &str| {
            match parse(&format!(
            "schema = 1\nname = \"s\"\nkind = \"reports\"\n[reports]\nconfigs = [\"a.toml\"]\nnoise_seeds = 8\n{extra}"
        ))
        .unwrap()
        .kind
        {
            Kind::Reports {
                noise_seeds,
                first_noise_seed,
                ..
            } => (noise_seeds, first_noise_seed),
            other => panic!("{other:?}"),
        }
        };
        assert_eq!(seeds(""), (Some(8), 1));
        assert_eq!(seeds("first_noise_seed = 9\n"), (Some(8), 9));
    }
}
