//! The import plan: the description resolved against the source (columns found, unit factors,
//! axes, rate), and the record loop shared by the survey pass and the writing pass.

use std::path::Path;

use sins_imu::ImuSample;
use sins_nav::{Mat3, Vec3};

use crate::description::{Description, Format, Quantity, Stamps};
use crate::error::{ImportError, SourcePos};
use crate::source::Source;
use crate::timeline::{Event, Record, Refusal, Timeline, TimelineConfig};
use crate::units::{Sensor, body_from_sensor, channel_factors, temperature_affine, time_factor};

/// Where [`Plan::run`] sends the samples it emits: the stretch's index and a batch of samples.
pub type SampleSink<'a> = dyn FnMut(usize, &[ImuSample]) -> Result<(), ImportError> + 'a;

/// How many stamps the rate estimate looks at when `time.rate_hz` is not given.
pub const RATE_ESTIMATE_RECORDS: usize = 1001;

/// The description resolved for one source file.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The effective description (for PSINS files: the header's values filled in).
    pub desc: Description,
    /// Nominal rate (Hz) and where it came from.
    pub rate_hz: f64,
    /// Where the rate came from.
    pub rate_from: String,
    /// Conversions applied, for the provenance record.
    pub conversions: Vec<String>,
    /// The description file (named in column errors).
    desc_file: std::path::PathBuf,
    gyro_factor: [f64; 3],
    accel_factor: [f64; 3],
    body_from_sensor: Mat3,
    time_factor: f64,
    temp_affine: (f64, f64),
}

/// Indices of the fields in a source's wanted list.
struct Slots {
    time: Option<usize>,
    counter: Option<usize>,
    gyro: usize,
    accel: usize,
    temp: Option<(usize, usize)>,
}

impl Plan {
    /// Resolve `user` for `file` (reads the PSINS header, and the first stamps when the rate
    /// must be estimated).
    pub fn new(file: &Path, user: &Description, desc_file: &Path) -> Result<Self, ImportError> {
        let desc = match user.format {
            Format::Psins => crate::psins::open(file, user)?.2,
            _ => user.clone(),
        };
        let missing =
            |key: &str| ImportError::desc(desc_file, key, format!("the [{key}] table is required"));
        let gyro = desc.gyro.as_ref().ok_or_else(|| missing("gyro"))?;
        let accel = desc.accel.as_ref().ok_or_else(|| missing("accel"))?;
        let (gyro_factor, gnote) = channel_factors(desc_file, Sensor::Gyro, gyro)?;
        let (accel_factor, anote) = channel_factors(desc_file, Sensor::Accel, accel)?;
        let (r, axes_note) = body_from_sensor(desc_file, &desc.axes)?;
        let tf = time_factor(desc_file, &desc.time.unit)?;
        let temp_affine = match &desc.temperature {
            Some(t) => {
                if !(t.columns.len() == 1 || t.columns.len() == 3) {
                    return Err(ImportError::desc(
                        desc_file,
                        "temperature.columns",
                        "give one column (all three accelerometers) or three (x, y, z)",
                    ));
                }
                temperature_affine(desc_file, &t.unit)?
            }
            None => (1.0, 0.0),
        };
        if desc.time.stamps == Stamps::Recorded && desc.time.column.is_none() {
            return Err(ImportError::desc(
                desc_file,
                "time.stamps",
                "\"recorded\" needs a time stamp column (time.column)",
            ));
        }
        let mut conversions = vec![gnote, anote, axes_note];
        for (sensor, ch) in [("gyro", gyro), ("accel", accel)] {
            if ch.quantity == Quantity::Rate {
                conversions.push(format!(
                    "{sensor} rates to increments by the {:?} rule",
                    ch.rule
                ));
            }
        }
        let mut plan = Self {
            desc,
            rate_hz: f64::NAN,
            rate_from: String::new(),
            conversions,
            desc_file: desc_file.to_path_buf(),
            gyro_factor,
            accel_factor,
            body_from_sensor: r,
            time_factor: tf,
            temp_affine,
        };
        (plan.rate_hz, plan.rate_from) = plan.rate(file, desc_file)?;
        Ok(plan)
    }

    /// The nominal rate: given, or the median step of the first stamps.
    fn rate(&self, file: &Path, desc_file: &Path) -> Result<(f64, String), ImportError> {
        if let Some(r) = self.desc.time.rate_hz {
            if !(r.is_finite() && r > 0.0) {
                return Err(ImportError::desc(
                    desc_file,
                    "time.rate_hz",
                    format!("{r} is not a positive rate"),
                ));
            }
            let from = match self.desc.format {
                Format::Psins => "the PSINS header's sampling interval",
                _ => "time.rate_hz",
            };
            return Ok((r, from.to_string()));
        }
        if self.desc.time.column.is_none() {
            return Err(ImportError::desc(
                desc_file,
                "time.rate_hz",
                "without a time column the nominal rate must be given",
            ));
        }
        let (mut src, slots) = self.open(file)?;
        let mut stamps = Vec::new();
        let mut v = Vec::new();
        while stamps.len() < RATE_ESTIMATE_RECORDS && src.next(&mut v)?.is_some() {
            stamps.push(v[slots.time.unwrap_or(0)] * self.time_factor);
        }
        let mut steps: Vec<f64> = stamps.windows(2).map(|w| w[1] - w[0]).collect();
        steps.retain(|s| *s > 0.0);
        steps.sort_by(f64::total_cmp);
        let Some(&median) = steps.get(steps.len() / 2) else {
            return Err(ImportError::desc(
                desc_file,
                "time.rate_hz",
                "too few increasing stamps to estimate the rate; give time.rate_hz",
            ));
        };
        // The mean of the single-interval steps (within the jitter band of the median):
        // symmetric jitter averages out, gaps stay out.
        let single: Vec<f64> = steps
            .iter()
            .copied()
            .filter(|s| (s / median - 1.0).abs() < 0.45)
            .collect();
        let mean = single.iter().sum::<f64>() / single.len() as f64;
        Ok((
            round_significant(1.0 / mean, 9),
            format!(
                "mean single step of the first {} stamps, to 9 significant digits",
                stamps.len()
            ),
        ))
    }

    /// Open the source and ask for the fields the plan needs.
    fn open(&self, file: &Path) -> Result<(Source, Slots), ImportError> {
        let d = &self.desc;
        let mut src = match d.format {
            Format::Psins => crate::psins::open(file, d)?.1,
            Format::Delimited => {
                let default = crate::description::Delimited {
                    delimiter: ",".into(),
                    header: true,
                    comment: None,
                    skip_lines: 0,
                };
                Source::delimited(file, d.delimited.as_ref().unwrap_or(&default))?
            }
            Format::Binary => {
                let b = d.binary.as_ref().ok_or_else(|| {
                    ImportError::desc(file, "binary", "format = \"binary\" needs a [binary] table")
                })?;
                Source::binary(file, b)?
            }
        };
        let mut fields: Vec<(usize, String)> = Vec::new();
        let mut add = |src: &Source, key: String, c: &crate::description::ColumnRef| {
            let i = src.resolve(&key, c).map_err(|e| match e {
                ImportError::Description { key, reason, .. } => ImportError::Description {
                    file: self.desc_file.clone(),
                    key,
                    reason: format!("{reason} [in {}]", file.display()),
                },
                other => other,
            })?;
            fields.push((i, format!("{key} ({c})")));
            Ok::<usize, ImportError>(fields.len() - 1)
        };
        let time = match &d.time.column {
            Some(c) => Some(add(&src, "time.column".into(), c)?),
            None => None,
        };
        let counter = match &d.time.counter {
            Some(c) => Some(add(&src, "time.counter".into(), c)?),
            None => None,
        };
        let mut triad = |key: &str, cols: &[crate::description::ColumnRef]| {
            let mut first = 0;
            for (k, c) in cols.iter().enumerate() {
                let slot = add(&src, format!("{key}.columns[{k}]"), c)?;
                if k == 0 {
                    first = slot;
                }
            }
            Ok::<usize, ImportError>(first)
        };
        let gyro = triad(
            "gyro",
            &d.gyro.as_ref().map_or(Vec::new(), |g| g.columns.to_vec()),
        )?;
        let accel = triad(
            "accel",
            &d.accel.as_ref().map_or(Vec::new(), |a| a.columns.to_vec()),
        )?;
        let temp = match &d.temperature {
            Some(t) => Some((triad("temperature", &t.columns)?, t.columns.len())),
            None => None,
        };
        src.want(fields)?;
        Ok((
            src,
            Slots {
                time,
                counter,
                gyro,
                accel,
                temp,
            },
        ))
    }

    fn timeline_config(&self) -> TimelineConfig {
        let d = &self.desc;
        let kind = |c: &Option<crate::description::Channels>| {
            c.as_ref()
                .map_or((Quantity::Increment, Default::default()), |c| {
                    (c.quantity, c.rule)
                })
        };
        TimelineConfig {
            dt_s: 1.0 / self.rate_hz,
            stamps: d.time.stamps,
            gyro: kind(&d.gyro),
            accel: kind(&d.accel),
            max_bridge: d.time.max_bridge_samples,
            on_gap: d.time.on_gap,
            counter_modulo: d.time.counter_modulo,
            start_s: d.time.start_s,
        }
    }

    /// Run the record loop over `file`: every emitted sample goes to `sink` with the index of
    /// its stretch, every bridge or split to `events`; `progress` gets the record count now
    /// and then. Returns the converter (its stamp statistics) and the records read.
    pub fn run(
        &self,
        file: &Path,
        sink: &mut SampleSink<'_>,
        events: &mut dyn FnMut(SourcePos, f64, Event),
        progress: &mut dyn FnMut(u64),
    ) -> Result<(Timeline, u64), ImportError> {
        let (mut src, slots) = self.open(file)?;
        let mut records = 0u64;
        let mut timeline = Timeline::new(self.timeline_config());
        let (mut v, mut out) = (Vec::new(), Vec::with_capacity(64));
        let mut stretch = 0usize;
        while let Some(at) = src.next(&mut v)? {
            records += 1;
            let rec = self.record(at, &v, &slots);
            out.clear();
            let event = timeline
                .push(rec, &mut out)
                .map_err(|r| refusal(file, at, r, self.desc.time.max_bridge_samples))?;
            if let Event::Split { .. } = event {
                stretch += 1;
            }
            if event != Event::Normal {
                events(at, out.first().map_or(f64::NAN, |s| s.t_s), event);
            }
            sink(stretch, &out)?;
            if at.record % (1 << 16) == 0 {
                progress(at.record);
            }
        }
        Ok((timeline, records))
    }

    fn record(&self, at: SourcePos, v: &[f64], s: &Slots) -> Record {
        let triad = |k: usize, f: &[f64; 3]| {
            self.body_from_sensor * Vec3::new(v[k] * f[0], v[k + 1] * f[1], v[k + 2] * f[2])
        };
        let temp_degc = match s.temp {
            Some((k, 1)) => [self.temp_affine.0 * v[k] + self.temp_affine.1; 3],
            Some((k, _)) => {
                std::array::from_fn(|j| self.temp_affine.0 * v[k + j] + self.temp_affine.1)
            }
            None => [f64::NAN; 3],
        };
        Record {
            at,
            stamp_s: s.time.map(|k| v[k] * self.time_factor),
            counter: s.counter.map(|k| v[k].max(0.0) as u64),
            gyro: triad(s.gyro, &self.gyro_factor),
            accel: triad(s.accel, &self.accel_factor),
            temp_degc,
        }
    }
}

fn refusal(file: &Path, at: SourcePos, r: Refusal, limit: u64) -> ImportError {
    match r {
        Refusal::Backwards {
            prev,
            prev_t_s,
            t_s,
        } => ImportError::TimeBackwards {
            file: file.to_path_buf(),
            at,
            prev_record: prev.record,
            prev_t_s,
            t_s,
        },
        Refusal::Gap {
            missing,
            prev_t_s,
            t_s,
        } => ImportError::Gap {
            file: file.to_path_buf(),
            at,
            missing,
            prev_t_s,
            t_s,
            limit,
        },
        Refusal::CounterBackwards { prev, this } => ImportError::Record {
            file: file.to_path_buf(),
            at,
            reason: format!(
                "the sample counter goes from {prev} to {this}; it must increase (set \
                 time.counter_modulo if it wraps)"
            ),
        },
    }
}

/// `x` rounded to `digits` significant digits (the rate estimated from stamps carries their
/// rounding: 99.99999999999991 Hz is 100 Hz).
fn round_significant(x: f64, digits: usize) -> f64 {
    format!("{x:.*e}", digits.saturating_sub(1))
        .parse()
        .unwrap_or(x)
}
