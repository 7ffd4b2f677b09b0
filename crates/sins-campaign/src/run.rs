//! The campaign's steps on a directory: plan, run one shard, list what is missing, reduce, and
//! all of it in one process. A shard's result is written aside and renamed into place, so a
//! killed shard leaves nothing a reduce could take for a result; the reduce reads only those
//! files, so its bytes do not depend on how many workers ran the shards, or in which order.

use crate::CampaignError;
use crate::kinds::load_work;
use crate::manifest::{BinaryId, FORMAT, Manifest, array_syntax, config_sha256};
use crate::shard::{SetAside, ShardResult, ShardState, read_shard, set_aside, shard_path};
use crate::spec::{Campaign, parse_campaign};
use crate::work::{Work, write_text};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

/// What every step needs besides the directory: where the default experiment files live and
/// which build is running.
#[derive(Clone, Debug)]
pub struct Context {
    /// The experiments directory of the defaults.
    pub experiments_dir: PathBuf,
    /// The running build.
    pub binary: BinaryId,
}

/// A planned campaign opened for work: its manifest (checked), the campaign and its work.
pub struct Opened {
    /// The manifest.
    pub manifest: Manifest,
    /// The campaign as planned (`DIR/campaign.toml`).
    pub campaign: Campaign,
    /// Its work.
    pub work: Box<dyn Work>,
    dir: PathBuf,
}

/// What running a shard did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShardRun {
    /// It ran, in this many seconds.
    Ran(f64),
    /// Its result was already there: nothing ran.
    AlreadyDone,
}

/// The failure note of shard `s` (written when its work failed, removed when it succeeds).
pub fn failed_path(dir: &Path, s: usize) -> PathBuf {
    dir.join("shards").join(format!("shard-{s:05}.failed"))
}

fn absolute(p: &Path) -> Result<PathBuf, CampaignError> {
    std::path::absolute(p).map_err(|e| CampaignError::io(p, e))
}

/// Files a plan writes, and `slurm/` (where scripts/slurm-campaign keeps its job logs and ids,
/// created before it plans); a directory holding only these (or nothing) may be planned into.
const PLAN_FILES: [&str; 5] = [
    "campaign.toml",
    "shards",
    "sealed",
    "manifest.json",
    "slurm",
];

/// Plans the campaign of file `cfg` into `out`: writes `campaign.toml` (the file's text),
/// does the kind's one-time work (a blind suite's seal) and writes `manifest.json` last.
/// Planning the same campaign with the same build into the same directory again changes
/// nothing (a campaign resumes); anything else already in `out` is refused, never touched.
/// Returns the manifest and whether it was new.
pub fn plan(cfg: &Path, out: &Path, ctx: &Context) -> Result<(Manifest, bool), CampaignError> {
    let text = std::fs::read_to_string(cfg).map_err(|e| CampaignError::io(cfg, e))?;
    let source = absolute(cfg)?;
    let experiments_dir = absolute(&ctx.experiments_dir)?;
    let campaign = parse_campaign(&text, &source, &experiments_dir)?;
    let refuse = |message: String| CampaignError::Manifest {
        path: out.to_owned(),
        message,
    };
    if out.exists() && !out.is_dir() {
        return Err(refuse(
            "exists and is not a directory; choose another --out".into(),
        ));
    }
    let work = load_work(&campaign)?;
    let jobs = work.jobs();
    if jobs == 0 {
        return Err(CampaignError::Spec {
            path: cfg.to_owned(),
            message: "the campaign has no jobs".into(),
        });
    }
    let manifest = Manifest {
        format: FORMAT.into(),
        campaign: campaign.name.clone(),
        kind: campaign.kind.name().into(),
        source,
        experiments_dir,
        jobs,
        jobs_per_shard: campaign.jobs_per_shard,
        shards: jobs.div_ceil(campaign.jobs_per_shard),
        config_sha256: config_sha256(&text, &work.fingerprint()),
        binary: ctx.binary.clone(),
        manifest_sha256: String::new(),
    }
    .sealed();
    if out.join("manifest.json").exists() {
        let old = Manifest::read(out)?;
        if old == manifest {
            return Ok((manifest, false));
        }
        // Another campaign (another name or another file) is not "an edited input".
        if old.campaign != manifest.campaign || old.source != manifest.source {
            return Err(refuse(format!(
                "already holds campaign '{}' (planned from {}); pick another --out for campaign '{}' ({}), or remove {} first",
                old.campaign,
                old.source.display(),
                manifest.campaign,
                manifest.source.display(),
                out.display()
            )));
        }
        old.check(out, &manifest.config_sha256, &ctx.binary)?;
        return Err(refuse(format!(
            "holds campaign '{}' planned differently; choose another --out",
            old.campaign
        )));
    }
    if out.is_dir() {
        let entries = std::fs::read_dir(out).map_err(|e| CampaignError::io(out, e))?;
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if !PLAN_FILES.contains(&name.as_str()) {
                return Err(refuse(format!(
                    "is not empty and holds no campaign ('{name}' is not one of its files); choose another --out"
                )));
            }
        }
    }
    let shards = out.join("shards");
    std::fs::create_dir_all(&shards).map_err(|e| CampaignError::io(&shards, e))?;
    write_text(out, "campaign.toml", &text)?;
    work.prepare(out)?;
    write_text(out, "manifest.json", &manifest.to_text())?;
    Ok((manifest, true))
}

/// Opens a planned campaign: the manifest must be intact and match this build and the inputs
/// as they are now.
pub fn open(dir: &Path, ctx: &Context) -> Result<Opened, CampaignError> {
    let manifest = Manifest::read(dir)?;
    let copy = dir.join("campaign.toml");
    let text = std::fs::read_to_string(&copy).map_err(|e| CampaignError::io(&copy, e))?;
    let campaign = parse_campaign(&text, &manifest.source, &manifest.experiments_dir)?;
    let work = load_work(&campaign)?;
    manifest.check(dir, &config_sha256(&text, &work.fingerprint()), &ctx.binary)?;
    if work.jobs() != manifest.jobs {
        return Err(CampaignError::Manifest {
            path: dir.join("manifest.json"),
            message: format!(
                "says {} jobs, the campaign has {}",
                manifest.jobs,
                work.jobs()
            ),
        });
    }
    Ok(Opened {
        manifest,
        campaign,
        work,
        dir: dir.to_owned(),
    })
}

fn failed(dir: &Path, shards: usize) -> Vec<(usize, String)> {
    (0..shards)
        .filter_map(|s| {
            std::fs::read_to_string(failed_path(dir, s))
                .ok()
                .map(|t| (s, t.trim().to_owned()))
        })
        .collect()
}

/// How far a planned campaign is, from its files alone: the manifest (its own hash checked),
/// the shards without a usable result (a damaged one counts as missing: see [`crate::shard`])
/// and those whose last attempt failed. Neither the build nor the inputs are checked (that is
/// `open`'s job before anything runs), so a scheduler can poll it cheaply: no executable to
/// hash, no experiment to load.
pub fn status(dir: &Path) -> Result<Status, CampaignError> {
    let manifest = Manifest::read(dir)?;
    let shards = manifest.shards;
    let mut missing = Vec::new();
    let mut damaged = Vec::new();
    for s in 0..shards {
        match read_shard(dir, &manifest, s)? {
            ShardState::Done(_) => {}
            ShardState::Missing => missing.push(s),
            ShardState::Damaged(why) => {
                missing.push(s);
                damaged.push((s, why));
            }
        }
    }
    Ok(Status {
        missing,
        damaged,
        failed: failed(dir, shards),
        manifest,
    })
}

/// What [`status`] finds.
#[derive(Clone, Debug)]
pub struct Status {
    /// The manifest.
    pub manifest: Manifest,
    /// Shards without a usable result (none, or a damaged one), in order.
    pub missing: Vec<usize>,
    /// Of those, the shards whose result is damaged, with what is wrong with it.
    pub damaged: Vec<(usize, String)>,
    /// Shards whose last attempt failed, with the note it left.
    pub failed: Vec<(usize, String)>,
}

fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_owned())
        .unwrap_or_default()
}

impl Opened {
    fn check_index(&self, s: usize) -> Result<(), CampaignError> {
        if s >= self.manifest.shards {
            return Err(CampaignError::ShardOutOfRange {
                dir: self.dir.clone(),
                index: s,
                shards: self.manifest.shards,
            });
        }
        Ok(())
    }

    /// The result of shard `s`, checked against the manifest and, outcome by outcome, against
    /// its jobs ([`Work::check_outcome`]).
    fn state(&self, s: usize) -> Result<ShardState, CampaignError> {
        let f = match read_shard(&self.dir, &self.manifest, s)? {
            ShardState::Done(f) => f,
            other => return Ok(other),
        };
        for (job, o) in self.manifest.shard_jobs(s).zip(&f.outcomes) {
            if let Err(e) = self.work.check_outcome(job, o) {
                let label = self.work.job_label(job);
                return Ok(ShardState::Damaged(format!(
                    "holds an unusable outcome of job {job} ({label}): {e}"
                )));
            }
        }
        Ok(ShardState::Done(f))
    }

    /// Moves shard `s`'s result aside when it is damaged (see [`crate::shard`]), so that the
    /// shard can run again; says where it went and why.
    pub fn set_aside_damaged(&self, s: usize) -> Result<Option<SetAside>, CampaignError> {
        self.check_index(s)?;
        let ShardState::Damaged(reason) = self.state(s)? else {
            return Ok(None);
        };
        let path = shard_path(&self.dir, s);
        let kept = set_aside(&path)?;
        Ok(Some(SetAside {
            shard: s,
            path,
            kept,
            reason,
        }))
    }

    /// Runs shard `s` (its jobs in order) and writes its result; a shard whose result is
    /// already there is not run again, a damaged result is moved aside first
    /// ([`Opened::set_aside_damaged`]). A failure leaves a note beside the results (listed by
    /// the reduce) and no result.
    pub fn run_shard(&self, s: usize) -> Result<ShardRun, CampaignError> {
        self.check_index(s)?;
        if let ShardState::Done(_) = self.state(s)? {
            return Ok(ShardRun::AlreadyDone);
        }
        self.set_aside_damaged(s)?;
        let started = Instant::now();
        let range = self.manifest.shard_jobs(s);
        let mut outcomes = Vec::with_capacity(range.len());
        for job in range.clone() {
            match self.work.run_job(job, &self.dir) {
                Ok(v) => outcomes.push(v),
                Err(e) => {
                    let inner = match e {
                        CampaignError::Job { message, .. } => message,
                        other => other.to_string(),
                    };
                    let e = CampaignError::Job {
                        job,
                        message: format!("shard {s}, {}: {inner}", self.work.job_label(job)),
                    };
                    let _ = write_text(
                        &self.dir.join("shards"),
                        &format!("shard-{s:05}.failed"),
                        &format!("{e}\n"),
                    );
                    return Err(e);
                }
            }
        }
        let wall_s = started.elapsed().as_secs_f64();
        let file = ShardResult {
            manifest_sha256: self.manifest.manifest_sha256.clone(),
            shard: s,
            jobs: [range.start, range.end],
            host: hostname(),
            wall_s,
            outcomes,
        };
        let json = serde_json::to_string(&file).map_err(|e| CampaignError::BadShard {
            path: shard_path(&self.dir, s),
            message: format!("cannot serialise: {e}"),
        })?;
        write_text(
            &self.dir.join("shards"),
            &format!("shard-{s:05}.json"),
            &json,
        )?;
        let _ = std::fs::remove_file(failed_path(&self.dir, s));
        Ok(ShardRun::Ran(wall_s))
    }

    /// Shards without a usable result (none, or a damaged one), in order.
    pub fn missing(&self) -> Result<Vec<usize>, CampaignError> {
        let mut missing = Vec::new();
        for s in 0..self.manifest.shards {
            if !matches!(self.state(s)?, ShardState::Done(_)) {
                missing.push(s);
            }
        }
        Ok(missing)
    }

    /// Shards whose last attempt failed, with the note it left.
    pub fn failed(&self) -> Vec<(usize, String)> {
        failed(&self.dir, self.manifest.shards)
    }

    /// Merges every shard's result into `summary.json` and `report.md` (and the kind's
    /// figures), plus `timing.json` (per-shard wall time and host: the one file that differs
    /// between runs). Every result is checked before any is used; refuses a damaged result,
    /// naming its file and what is wrong, and a partial set, listing the missing and failed
    /// shards.
    ///
    /// The files are written into a staging directory in the campaign directory and moved into
    /// place together ([`sins_files::commit_files`]): a failed or interrupted reduce
    /// leaves the previous summary, report and timing as they were.
    pub fn reduce(&self) -> Result<Vec<String>, CampaignError> {
        let mut results = Vec::with_capacity(self.manifest.shards);
        let (mut missing, mut damaged) = (Vec::new(), Vec::new());
        for s in 0..self.manifest.shards {
            match self.state(s)? {
                ShardState::Done(f) => results.push(f),
                ShardState::Missing => missing.push(s),
                ShardState::Damaged(why) => damaged.push((s, why)),
            }
        }
        if !damaged.is_empty() {
            return Err(self.damaged_error(&damaged, &missing));
        }
        if !missing.is_empty() {
            let failed = self.failed();
            let mut list = array_syntax(&missing);
            if !failed.is_empty() {
                let notes: Vec<String> = failed.iter().map(|(s, m)| format!("{s}: {m}")).collect();
                list.push_str(&format!("; failed: {}", notes.join("; ")));
            }
            return Err(CampaignError::MissingShards {
                dir: self.dir.clone(),
                missing: list,
                missing_count: missing.len(),
                shards: self.manifest.shards,
            });
        }
        let mut outcomes = Vec::with_capacity(self.manifest.jobs);
        let mut timing = Vec::with_capacity(self.manifest.shards);
        for (s, f) in results.into_iter().enumerate() {
            timing.push(ShardTiming {
                shard: s,
                jobs: f.jobs[1] - f.jobs[0],
                host: f.host,
                wall_s: f.wall_s,
            });
            outcomes.extend(f.outcomes);
        }
        // The summary, report and timing are written into a staging directory inside DIR and
        // moved into place together: a failed or interrupted reduce leaves the previous ones.
        let stage_target = self.dir.join("reduce");
        let staging = sins_files::Temporary::dir(&stage_target)
            .map_err(|e| CampaignError::io(&stage_target, e))?;
        let mut files = self.work.reduce(outcomes, &self.dir, staging.path())?;
        write_text(staging.path(), "timing.json", &timing_json(&timing))?;
        files.push("timing.json".into());
        sins_files::commit_files(staging, &files).map_err(|e| CampaignError::io(&self.dir, e))?;
        Ok(files)
    }

    fn damaged_error(&self, damaged: &[(usize, String)], missing: &[usize]) -> CampaignError {
        let mut details: Vec<String> = damaged
            .iter()
            .map(|(s, why)| format!("{} {why}", shard_path(&self.dir, *s).display()))
            .collect();
        if !missing.is_empty() {
            details.push(format!("no result at all: {}", array_syntax(missing)));
        }
        let indices: Vec<usize> = damaged.iter().map(|(s, _)| *s).collect();
        CampaignError::DamagedShards {
            dir: self.dir.clone(),
            indices: array_syntax(&indices),
            count: damaged.len(),
            shards: self.manifest.shards,
            details: details.join("; "),
        }
    }

    /// Runs every missing shard (a damaged result is moved aside first) on `threads` workers
    /// (each takes the next shard not yet started); `done(jobs)` is called as each shard
    /// ends. Stops taking shards after the first failure and returns it.
    pub fn run_local(
        &self,
        threads: usize,
        done: &(dyn Fn(usize) + Sync),
    ) -> Result<(), CampaignError> {
        let todo = self.missing()?;
        let next = AtomicUsize::new(0);
        let stop = AtomicBool::new(false);
        let first_error: Mutex<Option<CampaignError>> = Mutex::new(None);
        std::thread::scope(|scope| {
            for _ in 0..threads.clamp(1, todo.len().max(1)) {
                scope.spawn(|| {
                    while !stop.load(Ordering::Relaxed) {
                        let Some(&s) = todo.get(next.fetch_add(1, Ordering::Relaxed)) else {
                            break;
                        };
                        match self.run_shard(s) {
                            Ok(_) => done(self.manifest.shard_jobs(s).len()),
                            Err(e) => {
                                stop.store(true, Ordering::Relaxed);
                                if let Ok(mut slot) = first_error.lock() {
                                    slot.get_or_insert(e);
                                }
                            }
                        }
                    }
                });
            }
        });
        match first_error.into_inner().ok().flatten() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

#[derive(Serialize)]
struct ShardTiming {
    shard: usize,
    jobs: usize,
    host: String,
    wall_s: f64,
}

#[derive(Serialize)]
struct TimingFile<'a> {
    shards: usize,
    total_shard_s: f64,
    longest_shard_s: f64,
    mean_shard_s: f64,
    per_shard: &'a [ShardTiming],
}

fn timing_json(t: &[ShardTiming]) -> String {
    let total: f64 = t.iter().map(|s| s.wall_s).sum();
    let f = TimingFile {
        shards: t.len(),
        total_shard_s: total,
        longest_shard_s: t.iter().map(|s| s.wall_s).fold(0.0, f64::max),
        mean_shard_s: total / t.len().max(1) as f64,
        per_shard: t,
    };
    serde_json::to_string_pretty(&f).unwrap_or_default() + "\n"
}
