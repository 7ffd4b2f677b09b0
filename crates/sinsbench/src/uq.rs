//! `sinsbench replica-uq`: the replica of Table 5 as a validated prediction (Monte Carlo over
//! the declared assumptions, sensitivity, V&V 20 against the paper, the gap diagnosis).

use crate::out::say;
use crate::{defaults, progress};
use anyhow::{Context, Result, bail};
use sha2::{Digest, Sha256};
use sins_report::{
    UqStudy, load_uq_study, read_sample, sample_path, write_sample, write_uq_outputs,
};
use sins_uq::sample::{Job, SampleOutcome, all_jobs, job_work, run_jobs, study_name};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Arguments of `replica-uq`.
#[derive(clap::Args)]
pub struct Args {
    /// The assumptions file (TOML): every input the paper does not fix, with a distribution and
    /// a justification, and the candidate explanations of the replica-vs-paper gap. Default:
    /// experiments/replica/assumptions.toml.
    #[arg(long)]
    pub assumptions: Option<PathBuf>,
    /// Output directory: samples/ (one JSON per sample), summary.json, report.md,
    /// intervals.png, sensitivity.png. An existing directory is resumed (its samples reused)
    /// only when it holds the same study (manifest.json).
    #[arg(long, default_value = "reports/replica_uq")]
    pub out: PathBuf,
    /// Main Monte Carlo samples (default: the file's `samples`, sized for about 20 minutes on
    /// 2 cores). More samples shrink the intervals' bootstrap error roughly as 1/sqrt(N).
    #[arg(long, value_parser = clap::value_parser!(u64).range(4..))]
    pub samples: Option<u64>,
    /// Samples of every candidate of the gap diagnosis (default: each candidate's `samples`).
    #[arg(long, value_parser = clap::value_parser!(u64).range(2..))]
    pub candidate_samples: Option<u64>,
    /// Rows of the pick-freeze design for grouped first-order and total Sobol indices (default:
    /// the file's `pick_freeze_samples`; 0 = none). Costs (groups + 1) samples per row (8 with
    /// the shipped file), reuses the first main samples, so at most --samples.
    #[arg(long)]
    pub pick_freeze: Option<u64>,
    /// Master seed (default: the file's `seed`). Same seed, same file: byte-identical summary.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Worker threads (one sample each; results do not depend on it).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u64).range(1..=256))]
    pub threads: u64,
    /// Run only shard I of K (`I/K`, 0-based): the samples whose position in the study's fixed
    /// job list is I modulo K. Shards share --out (a shared file system); the summary is written
    /// by whichever run finds every sample present, or by --summarize-only.
    #[arg(long, value_parser = parse_shard)]
    pub shard: Option<(usize, usize)>,
    /// Run nothing: summarise the samples in --out (fails, listing what is missing, unless
    /// every sample is there).
    #[arg(long)]
    pub summarize_only: bool,
}

fn parse_shard(text: &str) -> Result<(usize, usize), String> {
    let (i, k) = text.split_once('/').ok_or("expected I/K, e.g. 0/4")?;
    let i: usize = i
        .trim()
        .parse()
        .map_err(|_| format!("shard index '{i}' is not a whole number"))?;
    let k: usize = k
        .trim()
        .parse()
        .map_err(|_| format!("shard count '{k}' is not a whole number"))?;
    if k == 0 || i >= k {
        return Err(format!(
            "shard index must be in 0..{k} and the count at least 1"
        ));
    }
    Ok((i, k))
}

/// Run `replica-uq`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    let path = args
        .assumptions
        .clone()
        .unwrap_or_else(|| defaults::experiments_dir().join("replica/assumptions.toml"));
    let mut study = load_uq_study(&path)?;
    apply_overrides(&mut study, &args)?;
    prepare_out(&args.out, &manifest(&path, &study)?)?;
    let jobs = all_jobs(&study.set);
    let missing: Vec<Job> = jobs
        .iter()
        .enumerate()
        .filter(|(k, _)| args.shard.is_none_or(|(i, n)| k % n == i))
        .map(|(_, j)| *j)
        .filter(|j| !sample_path(&args.out, &study_name(&study.set, *j), j.index()).exists())
        .collect();
    if !args.summarize_only && !missing.is_empty() {
        run_missing(&study, &missing, &args, quiet)?;
    }
    let (outcomes, absent) = collect(&study, &jobs, &args.out)?;
    if !absent.is_empty() {
        let head: Vec<String> = absent.iter().take(8).cloned().collect();
        if args.summarize_only || args.shard.is_none() {
            bail!(
                "{} of {} samples are missing in {} (e.g. {}); run the missing shards first",
                absent.len(),
                jobs.len(),
                args.out.display(),
                head.join(", ")
            );
        }
        say!(
            "shard done; {} of {} samples still missing (other shards); then run with --summarize-only",
            absent.len(),
            jobs.len()
        )?;
        return Ok(());
    }
    let summary = sins_uq::summary::summarize(&study.set, &outcomes, &study.paper)?;
    write_uq_outputs(&args.out, &summary)?;
    say!("{}", sins_report::uq_table_for_report(&summary).trim_end())?;
    if let Some(g) = &summary.gap {
        say!(
            "gap diagnosis: chosen {} on {}; median shrinkage on withheld cells {:.0} %",
            g.chosen,
            g.choose_on.join(", "),
            g.median_shrinkage_percent
        )?;
    }
    say!(
        "wrote {} (summary.json, report.md, intervals.png, sensitivity.png, samples/)",
        args.out.display()
    )?;
    Ok(())
}

fn apply_overrides(study: &mut UqStudy, args: &Args) -> Result<()> {
    if let Some(n) = args.samples {
        study.set.samples = n as usize;
    }
    if let Some(n) = args.candidate_samples {
        for c in &mut study.set.candidates {
            c.samples = n as usize;
        }
    }
    if let Some(s) = args.seed {
        study.set.seed = s;
    }
    if let Some(n) = args.pick_freeze {
        study.set.pick_freeze_samples = n as usize;
    }
    study
        .set
        .validate()
        .context("--samples / --candidate-samples / --pick-freeze")?;
    Ok(())
}

/// What a sample depends on: the assumptions file and everything it reads, the seed and the
/// binary's version (a directory of samples from another study is never mixed in).
fn manifest(path: &Path, study: &UqStudy) -> Result<String> {
    let mut h = Sha256::new();
    h.update(std::fs::read(path).with_context(|| path.display().to_string())?);
    h.update(format!(
        "{:?}{:?}{:?}",
        study.base.calibration, study.base.navigation, study.base.replay.output_interval_s
    ));
    h.update(format!(
        "seed {} version {}",
        study.set.seed,
        env!("CARGO_PKG_VERSION")
    ));
    let digest: String = h.finalize().iter().map(|b| format!("{b:02x}")).collect();
    Ok(format!(
        "{{\n  \"study\": \"{}\",\n  \"sha256\": \"{digest}\"\n}}\n",
        study.name
    ))
}

/// Creates the output directory or checks that it holds the same study; never moves or
/// overwrites anything else.
fn prepare_out(out: &Path, manifest: &str) -> Result<()> {
    let file = out.join("manifest.json");
    if out.exists() && !out.is_dir() {
        bail!(
            "{}: exists and is not a directory; choose another --out",
            out.display()
        );
    }
    if out.is_dir() {
        match std::fs::read_to_string(&file) {
            Ok(m) if m == manifest => return Ok(()),
            Ok(_) => bail!(
                "{}: holds samples of another study or seed (manifest.json differs); choose another --out or remove it",
                out.display()
            ),
            Err(_) if std::fs::read_dir(out)?.next().is_some() => {
                bail!(
                    "{}: not empty and not a replica-uq directory (no manifest.json); choose another --out",
                    out.display()
                )
            }
            Err(_) => {}
        }
    }
    std::fs::create_dir_all(out.join("samples")).with_context(|| out.display().to_string())?;
    sins_files::write_file_atomically(&file, manifest.as_bytes())
        .with_context(|| format!("writing {}", file.display()))?;
    Ok(())
}

fn run_missing(study: &UqStudy, jobs: &[Job], args: &Args, quiet: bool) -> Result<()> {
    let work: u64 = jobs
        .iter()
        .map(|j| job_work(&study.base, &study.set, *j))
        .sum();
    let bar = progress::bar(work, &format!("replica-uq {} samples", jobs.len()), quiet);
    let write_error: Mutex<Option<anyhow::Error>> = Mutex::new(None);
    let results = run_jobs(
        &study.base,
        &study.set,
        jobs,
        args.threads as usize,
        &|n| bar.inc(n),
        &|_, o: &SampleOutcome| {
            if let Err(e) = write_sample(&args.out, o)
                && let Ok(mut slot) = write_error.lock()
            {
                slot.get_or_insert(e.into());
            }
        },
    );
    bar.finish_and_clear();
    if let Some(e) = write_error.into_inner().ok().flatten() {
        return Err(e);
    }
    for r in results {
        r?;
    }
    Ok(())
}

fn collect(study: &UqStudy, jobs: &[Job], out: &Path) -> Result<(Vec<SampleOutcome>, Vec<String>)> {
    let mut outcomes = Vec::new();
    let mut absent = Vec::new();
    for &j in jobs {
        let p = sample_path(out, &study_name(&study.set, j), j.index());
        match read_sample(&p)? {
            Some(o) => outcomes.push(o),
            None => absent.push(
                p.file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default(),
            ),
        }
    }
    Ok((outcomes, absent))
}
