//! `sinsbench campaign`: a campaign of independent runs split into shards, run in one process
//! (`local`) or one shard at a time anywhere that sees the directory (`shard`, e.g. as Slurm
//! array tasks through scripts/slurm-campaign), then reduced to the same bytes.

use crate::out::{note, say};
use crate::{defaults, progress};
use anyhow::Result;
use sins_campaign::{BinaryId, Context, Opened, ShardRun, array_syntax};
use std::path::{Path, PathBuf};

/// Arguments of `campaign`.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    step: Step,
}

#[derive(clap::Subcommand)]
enum Step {
    /// Plan a campaign file (experiments/campaigns/*.toml) into DIR: DIR/manifest.json (hash
    /// of the configuration and everything it reads, hash of this build, shard count),
    /// DIR/campaign.toml, DIR/shards/ (and a blind suite's sealed answers). Planning the same
    /// campaign into the same DIR again changes nothing.
    Plan {
        /// The campaign file.
        config: PathBuf,
        /// The campaign directory (on storage every worker sees).
        #[arg(long)]
        out: PathBuf,
    },
    /// Run shard I of a planned campaign and write DIR/shards/shard-IIIII.json (aside, then
    /// renamed). A finished shard is not run again; a damaged result (empty, truncated, of the
    /// wrong shape) is kept aside as shard-IIIII.json.damaged-N and the shard runs again; a
    /// manifest that does not match this build or the inputs as they are now is refused. In a Slurm array: --index $SLURM_ARRAY_TASK_ID;
    /// in a Kubernetes indexed job: --index $JOB_COMPLETION_INDEX.
    Shard {
        /// The campaign directory.
        dir: PathBuf,
        /// Shard index, 0-based.
        #[arg(long)]
        index: usize,
    },
    /// Merge every shard's result into DIR/summary.json and DIR/report.md (byte-identical
    /// however the shards were run) and DIR/timing.json. Refuses a partial set, listing the
    /// missing and failed shards.
    Reduce {
        /// The campaign directory.
        dir: PathBuf,
    },
    /// Say how far a campaign is. With --missing, print only the shards without a usable
    /// result (none, or a damaged one) in Slurm array syntax (`0-3,7`; an empty line when
    /// none), for resubmission.
    Status {
        /// The campaign directory.
        dir: PathBuf,
        /// Print the missing shards only.
        #[arg(long)]
        missing: bool,
    },
    /// Plan, run every missing shard on this machine's cores (progress bar) and reduce.
    Local {
        /// The campaign file.
        config: PathBuf,
        /// The campaign directory.
        #[arg(long)]
        out: PathBuf,
        /// Worker threads, one shard each (default: this machine's cores; results do not
        /// depend on it).
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..=256))]
        threads: Option<u64>,
    },
}

fn context() -> Result<Context> {
    Ok(Context {
        experiments_dir: defaults::experiments_dir(),
        binary: BinaryId::current(env!("CARGO_PKG_VERSION"))?,
    })
}

/// Run `campaign`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    // `status` needs no context: it reads the files only (no executable to hash).
    match args.step {
        Step::Plan { config, out } => plan(&config, &out, &context()?),
        Step::Shard { dir, index } => {
            // No sweep of DIR/shards here: shards of other nodes write there at the same time, and
            // whether their process lives can only be told on their own node. A temporary left
            // by a SIGKILLed shard is a hidden file the reduce never reads.
            let opened = sins_campaign::open(&dir, &context()?)?;
            let label = opened
                .manifest
                .shard_jobs(index)
                .map(|j| opened.work.job_label(j))
                .collect::<Vec<_>>()
                .join(", ");
            if let Some(aside) = opened.set_aside_damaged(index)? {
                note!("note: {aside}");
            }
            match opened.run_shard(index)? {
                ShardRun::Ran(s) => say!("shard {index} ({label}) done in {s:.1} s"),
                ShardRun::AlreadyDone => say!("shard {index} ({label}) was already done"),
            }
        }
        Step::Reduce { dir } => {
            crate::outputs::sweep(&dir);
            let opened = sins_campaign::open(&dir, &context()?)?;
            sins_files::lock::lock_output(&dir, None)?;
            reduce(&opened, &dir)
        }
        Step::Status { dir, missing } => {
            let sins_campaign::Status {
                manifest: m,
                missing: todo,
                damaged,
                failed,
            } = sins_campaign::status(&dir)?;
            if missing {
                return say!("{}", array_syntax(&todo));
            }
            say!(
                "campaign '{}' ({}): {} jobs in {} shards of {}; {} done, {} missing{}",
                m.campaign,
                m.kind,
                m.jobs,
                m.shards,
                m.jobs_per_shard,
                m.shards - todo.len(),
                todo.len(),
                if todo.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", array_syntax(&todo))
                }
            )?;
            for (s, why) in damaged {
                say!(
                    "shard {s} counts as missing: {} {why}; `sinsbench campaign shard {} --index {s}` keeps it aside and runs the shard again",
                    sins_campaign::shard_path(&dir, s).display(),
                    dir.display()
                )?;
            }
            for (s, note) in failed {
                say!("shard {s} failed last time: {note}")?;
            }
            Ok(())
        }
        Step::Local {
            config,
            out,
            threads,
        } => {
            let ctx = context()?;
            plan(&config, &out, &ctx)?;
            sins_files::lock::lock_output(&out, None)?;
            let opened = sins_campaign::open(&out, &ctx)?;
            let todo = opened.missing()?;
            for s in &todo {
                if let Some(aside) = opened.set_aside_damaged(*s)? {
                    note!("note: {aside}");
                }
            }
            let left: usize = todo
                .iter()
                .map(|s| opened.manifest.shard_jobs(*s).len())
                .sum();
            let bar = progress::bar(
                left as u64,
                &format!("{} jobs", opened.manifest.campaign),
                quiet,
            );
            let threads = threads.map_or_else(
                || std::thread::available_parallelism().map_or(1, |n| n.get()),
                |t| t as usize,
            );
            let result = opened.run_local(threads, &|jobs| bar.inc(jobs as u64));
            bar.finish_and_clear();
            result?;
            reduce(&opened, &out)
        }
    }
}

fn plan(config: &Path, out: &Path, ctx: &Context) -> Result<()> {
    crate::outputs::sweep(out);
    let (m, fresh) = sins_campaign::plan(config, out, ctx)?;
    say!(
        "{} campaign '{}' ({}): {} jobs in {} shards in {}",
        if fresh { "planned" } else { "already planned:" },
        m.campaign,
        m.kind,
        m.jobs,
        m.shards,
        out.display()
    )
}

/// Reduces into `dir` (whose lock this process holds): summary, report and timing replace the
/// previous ones together or not at all.
fn reduce(opened: &Opened, dir: &Path) -> Result<()> {
    let unchanged = format!(
        "the previous summary.json, report.md and timing.json in {} are unchanged",
        dir.display()
    );
    sins_files::set_interrupt_note(Some(unchanged.clone()));
    let had_previous = dir.join("summary.json").exists();
    let files = opened.reduce().map_err(|e| {
        let e = anyhow::Error::from(e);
        if had_previous {
            e.context(format!("campaign not reduced; {unchanged}"))
        } else {
            e
        }
    })?;
    say!(
        "campaign '{}': reduced {} shards into {} ({})",
        opened.manifest.campaign,
        opened.manifest.shards,
        dir.display(),
        files.join(", ")
    )
}
