#![doc = include_str!("../README.md")]

mod description;
mod error;
mod plan;
mod psins;
mod source;
mod timeline;
mod units;

use std::io::Read;
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};
use sins_data::{ColumnSet, DatasetMeta, DatasetWriter, SampleBatch};
use sins_imu::ImuSample;
use sins_nav::Geodetic;

pub use description::{
    Axes, Binary, ByteOrder, Channels, ColumnRef, DEFAULT_MAX_BRIDGE_SAMPLES, Delimited,
    Description, Field, Format, OnGap, Quantity, Rule, SegmentSpan, Site, Stamps, Temperature,
    Time,
};
pub use error::{ImportError, SourcePos};
pub use psins::PsinsHeader;
pub use timeline::{Event, StepStats};
pub use units::ARCSEC_RAD;

/// Label of the rows that no `[[segments]]` span covers.
pub const UNLABELLED: &str = "unlabelled";

/// At most this many bridged gaps are listed in the metadata (the report lists them all).
const MAX_LISTED_BRIDGES: usize = 50;

/// What to import.
#[derive(Clone, Copy, Debug)]
pub struct ImportRequest<'a> {
    /// The recording.
    pub source: &'a Path,
    /// How to read it.
    pub description: &'a Description,
    /// Where the description came from (named in its errors; the source for built-in formats).
    pub description_file: &'a Path,
    /// The description's text, stored in the provenance.
    pub description_text: &'a str,
    /// The dataset to write (`.parquet` or `.csv`); further stretches go beside it as
    /// `<stem>_part<N>.<ext>`.
    pub out: &'a Path,
}

/// A gap bridged or split.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GapEvent {
    /// The record after the gap.
    pub at: SourcePos,
    /// Output time of the first sample after the gap start (s).
    pub t_s: f64,
    /// Samples missing.
    pub missing: u64,
    /// True when bridged, false when the run was split there.
    pub bridged: bool,
}

/// One dataset written.
#[derive(Clone, Debug, PartialEq)]
pub struct Stretch {
    /// The file.
    pub path: PathBuf,
    /// Rows.
    pub rows: u64,
    /// First and last sample time (s).
    pub t_first_s: f64,
    /// Last sample time (s).
    pub t_last_s: f64,
}

/// What an import did.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportReport {
    /// SHA-256 of the source file as it is (hex).
    pub source_sha256: String,
    /// Source size (bytes).
    pub source_bytes: u64,
    /// Records read from the source.
    pub records: u64,
    /// Nominal rate (Hz).
    pub rate_hz: f64,
    /// Where the rate came from.
    pub rate_from: String,
    /// Time base of the datasets.
    pub stamps: Stamps,
    /// Single-interval stamp steps (jitter), when the recording has stamps.
    pub steps: StepStats,
    /// Gaps bridged or split, in file order.
    pub gaps: Vec<GapEvent>,
    /// Conversions applied.
    pub conversions: Vec<String>,
    /// The datasets written.
    pub stretches: Vec<Stretch>,
    /// The PSINS header, for PSINS files.
    pub psins: Option<PsinsHeader>,
}

impl ImportReport {
    /// Samples inserted by bridging.
    pub fn bridged_samples(&self) -> u64 {
        self.gaps
            .iter()
            .filter(|g| g.bridged)
            .map(|g| g.missing)
            .sum()
    }

    /// One line on the stamps: jitter statistics, or "no stamps".
    pub fn stamps_line(&self) -> String {
        let s = &self.steps;
        if s.n == 0 {
            return format!("no time stamps: t = t0 + k / {} Hz", self.rate_hz);
        }
        let dt = 1.0 / self.rate_hz;
        format!(
            "{} single steps: mean {:.9} s ({:+.1} ppm of 1/{} Hz), std {:.3e} s ({:.2} % of \
             the interval), min {:.6} s, max {:.6} s",
            s.n,
            s.mean_s(),
            (s.mean_s() / dt - 1.0) * 1e6,
            self.rate_hz,
            s.std_s(),
            100.0 * s.std_s() / dt,
            s.min_s,
            s.max_s
        )
    }

    /// One line on the gaps.
    pub fn gaps_line(&self) -> String {
        let bridged: Vec<&GapEvent> = self.gaps.iter().filter(|g| g.bridged).collect();
        let splits = self.gaps.len() - bridged.len();
        let mut line = format!(
            "{} gap(s) bridged ({} samples inserted), {} split(s)",
            bridged.len(),
            self.bridged_samples(),
            splits
        );
        for g in self.gaps.iter().take(MAX_LISTED_BRIDGES) {
            line.push_str(&format!(
                "; {} at {} (t = {:.4} s): {} missing",
                if g.bridged { "bridged" } else { "split" },
                g.at,
                g.t_s,
                g.missing
            ));
        }
        if self.gaps.len() > MAX_LISTED_BRIDGES {
            line.push_str(&format!(
                "; and {} more",
                self.gaps.len() - MAX_LISTED_BRIDGES
            ));
        }
        line
    }
}

/// SHA-256 (hex) and size of a file.
pub fn sha256_file(path: &Path) -> Result<(String, u64), ImportError> {
    let io = |e| ImportError::Io {
        file: path.to_path_buf(),
        action: "reading for the SHA-256",
        source: e,
    };
    let mut f = std::fs::File::open(path).map_err(io)?;
    let mut h = Sha256::new();
    let mut buf = vec![0u8; 1 << 20];
    let mut n_bytes = 0u64;
    loop {
        let n = match f.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(io(e)),
        };
        h.update(&buf[..n]);
        n_bytes += n as u64;
    }
    Ok((
        h.finalize().iter().map(|b| format!("{b:02x}")).collect(),
        n_bytes,
    ))
}

/// The path of stretch `k` (0-based) beside `out`.
pub fn stretch_path(out: &Path, k: usize) -> PathBuf {
    if k == 0 {
        return out.to_path_buf();
    }
    let stem = out
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let ext = out
        .extension()
        .map_or_else(String::new, |e| format!(".{}", e.to_string_lossy()));
    out.with_file_name(format!("{stem}_part{}{ext}", k + 1))
}

/// Import a recording; `progress` gets `(pass, records)` now and then (pass 0: survey, 1:
/// writing).
pub fn import(
    req: &ImportRequest<'_>,
    progress: &mut dyn FnMut((u8, u64)),
) -> Result<ImportReport, ImportError> {
    let plan = plan::Plan::new(req.source, req.description, req.description_file)?;
    let psins = match plan.desc.format {
        Format::Psins => Some(psins::open(req.source, req.description)?.0),
        _ => None,
    };
    // Pass 1: check everything, count the stretches, find the gaps; the SHA-256 of the file is
    // taken on a second thread meanwhile (it reads the file once more, mostly from the cache).
    let mut gaps = Vec::new();
    let mut bounds: Vec<(u64, f64, f64)> = Vec::new();
    let (survey, hash) = std::thread::scope(|scope| {
        let hash = scope.spawn(|| sha256_file(req.source));
        let survey = plan.run(
            req.source,
            &mut |k, s| {
                count(&mut bounds, k, s);
                Ok(())
            },
            &mut |at, t_s, e| gaps.push(gap_event(at, t_s, e)),
            &mut |n| progress((0, n)),
        );
        let hash = hash.join().unwrap_or_else(|_| {
            Err(ImportError::Io {
                file: req.source.to_path_buf(),
                action: "reading for the SHA-256",
                source: std::io::Error::other("the hashing thread failed"),
            })
        });
        (survey, hash)
    });
    let (timeline, records) = survey?;
    let (sha, n_bytes) = hash?;
    if bounds.iter().all(|b| b.0 == 0) {
        return Err(ImportError::Record {
            file: req.source.to_path_buf(),
            at: SourcePos::default(),
            reason: "no samples (an empty file, or only a header)".to_string(),
        });
    }
    let mut report = ImportReport {
        source_sha256: sha,
        source_bytes: n_bytes,
        records,
        rate_hz: plan.rate_hz,
        rate_from: plan.rate_from.clone(),
        stamps: plan.desc.time.stamps,
        steps: timeline.steps,
        gaps,
        conversions: plan.conversions.clone(),
        stretches: Vec::new(),
        psins,
    };
    // Pass 2: write every stretch aside, then rename them all into place.
    let labels = labels(&plan.desc);
    let mut writers: Vec<DatasetWriter> = Vec::new();
    let mut batch = SampleBatch::default();
    let columns = ColumnSet {
        temperature: plan.desc.temperature.is_some(),
        segment: !plan.desc.segments.is_empty(),
        reference: false,
    };
    for (k, _) in bounds.iter().enumerate() {
        let meta = metadata(req, &plan, &report, k, bounds.len())?;
        writers.push(DatasetWriter::create(
            stretch_path(req.out, k),
            &meta,
            columns,
            &labels,
        )?);
    }
    let mut current = 0usize;
    plan.run(
        req.source,
        &mut |k, s| {
            if k != current {
                flush(&mut writers[current], &mut batch)?;
                current = k;
            }
            batch.samples.extend_from_slice(s);
            if columns.segment {
                let seg = batch.segment_index.get_or_insert_with(Vec::new);
                seg.extend(s.iter().map(|x| label_of(&plan.desc, &labels, x.t_s)));
            }
            if batch.samples.len() >= 1 << 16 {
                flush(&mut writers[current], &mut batch)?;
            }
            Ok(())
        },
        &mut |_, _, _| {},
        &mut |n| progress((1, n)),
    )?;
    flush(&mut writers[current], &mut batch)?;
    for (k, w) in writers.into_iter().enumerate() {
        let summary = w.finish()?;
        report.stretches.push(Stretch {
            path: summary.path,
            rows: summary.n_rows,
            t_first_s: bounds[k].1,
            t_last_s: bounds[k].2,
        });
    }
    Ok(report)
}

fn count(bounds: &mut Vec<(u64, f64, f64)>, k: usize, s: &[ImuSample]) {
    while bounds.len() <= k {
        bounds.push((0, f64::NAN, f64::NAN));
    }
    if let (Some(a), Some(b)) = (s.first(), s.last()) {
        let e = &mut bounds[k];
        if e.0 == 0 {
            e.1 = a.t_s;
        }
        e.0 += s.len() as u64;
        e.2 = b.t_s;
    }
}

fn gap_event(at: SourcePos, t_s: f64, e: Event) -> GapEvent {
    let (missing, bridged) = match e {
        Event::Bridged { missing } => (missing, true),
        Event::Split { missing } => (missing, false),
        Event::Normal => (0, false),
    };
    GapEvent {
        at,
        t_s,
        missing,
        bridged,
    }
}

fn flush(w: &mut DatasetWriter, batch: &mut SampleBatch) -> Result<(), ImportError> {
    if !batch.samples.is_empty() {
        w.write_batch(batch)?;
    }
    batch.samples.clear();
    if let Some(s) = batch.segment_index.as_mut() {
        s.clear();
    }
    Ok(())
}

fn labels(d: &Description) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for s in &d.segments {
        if !out.contains(&s.label) {
            out.push(s.label.clone());
        }
    }
    if !out.is_empty() && !out.iter().any(|l| l == UNLABELLED) {
        out.push(UNLABELLED.to_string());
    }
    out
}

fn label_of(d: &Description, labels: &[String], t_s: f64) -> u16 {
    let name = d
        .segments
        .iter()
        .find(|s| s.from_s <= t_s && t_s < s.to_s)
        .map_or(UNLABELLED, |s| s.label.as_str());
    labels.iter().position(|l| l == name).unwrap_or(0) as u16
}

/// The dataset metadata of stretch `k` of `n`: rate, site, description, provenance.
fn metadata(
    req: &ImportRequest<'_>,
    plan: &plan::Plan,
    report: &ImportReport,
    k: usize,
    n: usize,
) -> Result<DatasetMeta, ImportError> {
    let d = &plan.desc;
    let site = d.site.ok_or_else(|| {
        ImportError::desc(
            req.description_file,
            "site",
            "the [site] table (latitude_deg, longitude_deg, height_m) is required: navigation \
             and the Earth-rate checks need it",
        )
    })?;
    let file_name = req.source.file_name().map_or_else(
        || req.source.display().to_string(),
        |f| f.to_string_lossy().into_owned(),
    );
    let text = |v: &toml::Value| match v {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    };
    let description = d
        .description
        .clone()
        .or_else(|| d.metadata.get("description").map(text))
        .unwrap_or_else(|| format!("imported from {file_name}"));
    let mut meta = DatasetMeta::new(
        plan.rate_hz,
        Geodetic::from_deg(site.latitude_deg, site.longitude_deg, site.height_m),
        description,
    );
    for (key, v) in &d.metadata {
        if key != "description" {
            meta.extra.insert(key.clone(), text(v));
        }
    }
    let mut put = |k: &str, v: String| {
        meta.extra.insert(k.to_string(), v);
    };
    put(
        "time_base",
        match d.time.stamps {
            Stamps::Nominal => "nominal".into(),
            Stamps::Recorded => "recorded".into(),
        },
    );
    put("import.source_file", file_name);
    put("import.source_sha256", report.source_sha256.clone());
    put("import.source_bytes", report.source_bytes.to_string());
    put("import.description", req.description_text.to_string());
    put("import.conversions", report.conversions.join("; "));
    put(
        "import.rate",
        format!("{} Hz ({})", plan.rate_hz, plan.rate_from),
    );
    put("import.stamps", report.stamps_line());
    put("import.gaps", report.gaps_line());
    put("import.stretch", format!("{} of {n}", k + 1));
    Ok(meta)
}
