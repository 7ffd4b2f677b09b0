//! `sinsbench import`: a real recording, as it comes, into a sinsbench dataset.

use crate::out::say;
use crate::progress;
use anyhow::{Result, bail};
use sins_import::{Description, ImportReport, ImportRequest, Stamps};
use std::path::{Path, PathBuf};

/// Arguments of `import`.
#[derive(clap::Args, Clone)]
pub struct Args {
    /// The recording (text or binary, gzip-compressed or not).
    pub source: PathBuf,
    /// The description of the recording (TOML: layout, time base, channel units, axes, site;
    /// see docs/import.md and experiments/import/ for the public recordings'). Not needed
    /// with --format psins.
    #[arg(long, short = 'd', required_unless_present = "format")]
    pub description: Option<PathBuf>,
    /// A named format that describes itself: `psins` (the PSINS compact .imu text format,
    /// whose header gives period, site, attitude and count scales). With --description too,
    /// the description adds or overrides the site, segments, metadata and time rules.
    #[arg(long, value_enum)]
    pub format: Option<NamedFormat>,
    /// The dataset to write (.parquet or .csv). Further stretches after long gaps (with
    /// time.on_gap = "split") go beside it as <stem>_part2, _part3, ...
    #[arg(long)]
    pub out: PathBuf,
}

/// A format that carries its own description.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum NamedFormat {
    /// PSINS compact `.imu` text.
    Psins,
}

/// Run `import`.
pub fn run(args: Args, quiet: bool) -> Result<()> {
    // Writing a dataset is this command's main cost: keep the Parquet writer's pages.
    crate::malloc::tune();
    let (mut desc, text, desc_file) = match &args.description {
        Some(p) => {
            let (d, t) = Description::load(p)?;
            (d, t, p.clone())
        }
        None => (
            Description::psins(),
            "format = \"psins\"\n".to_string(),
            args.source.clone(),
        ),
    };
    if let Some(NamedFormat::Psins) = args.format {
        desc.format = sins_import::Format::Psins;
    }
    check_target(&args.source, &args.out)?;
    crate::outputs::sweep(args.out.parent().unwrap_or(Path::new(".")));
    let bar = progress::bar(2, "import (check, write)", quiet);
    let report = sins_import::import(
        &ImportRequest {
            source: &args.source,
            description: &desc,
            description_file: &desc_file,
            description_text: &text,
            out: &args.out,
        },
        &mut |(pass, _)| bar.set_position(u64::from(pass)),
    )?;
    bar.finish_and_clear();
    print_report(&args.source, &report)
}

/// Refuses to write over the source, over a directory, or over an existing file that is not a
/// dataset an earlier `import` wrote.
fn check_target(source: &Path, out: &Path) -> Result<()> {
    crate::outputs::check_file_target(out, "dataset")?;
    if !out.exists() {
        return Ok(());
    }
    if let (Ok(a), Ok(b)) = (source.canonicalize(), out.canonicalize())
        && a == b
    {
        bail!(
            "{}: --out is the recording itself; choose another path",
            out.display()
        );
    }
    let ours = sins_data::DatasetReader::open(out)
        .map(|r| r.info().meta.extra.contains_key("import.source_sha256"))
        .unwrap_or(false);
    if !ours {
        bail!(
            "{}: exists and is not a dataset written by `sinsbench import`; it is left untouched \
             (choose another path or remove it)",
            out.display()
        );
    }
    Ok(())
}

fn print_report(source: &Path, r: &ImportReport) -> Result<()> {
    say!(
        "{}: {} records, sha256 {}",
        source.display(),
        r.records,
        r.source_sha256
    )?;
    if let Some(h) = &r.psins {
        say!(
            "  PSINS header: attitude {:?} deg, site {:?}, interval {} ms, g {} m/s^2, scales {:?} \
             arcsec and {:?} ug*s per count",
            h.attitude_deg,
            h.site,
            h.interval_ms,
            h.g_mps2,
            h.gyro_arcsec,
            h.accel_ug_s
        )?;
    }
    say!("  rate {} Hz ({})", r.rate_hz, r.rate_from)?;
    say!(
        "  time base: {}",
        match r.stamps {
            Stamps::Nominal => "nominal (t = t0 + k / rate; navigation uses 1/rate)",
            Stamps::Recorded => "recorded stamps (navigation uses each sample's own interval)",
        }
    )?;
    say!("  stamps: {}", r.stamps_line())?;
    say!("  gaps: {}", r.gaps_line())?;
    for c in &r.conversions {
        say!("  conversion: {c}")?;
    }
    for s in &r.stretches {
        say!(
            "wrote {} ({} samples, t = {:.3} .. {:.3} s)",
            s.path.display(),
            s.rows,
            s.t_first_s,
            s.t_last_s
        )?;
    }
    Ok(())
}
