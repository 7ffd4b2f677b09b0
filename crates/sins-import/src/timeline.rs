//! From records (time, rates or increments in the body frame, SI) to dataset samples: the time
//! base, jitter statistics, dropped samples bridged, long gaps split or refused, and rates
//! integrated into increments by the description's rule.
//!
//! A record at time t carries either the increment over the interval ending at t or the rate
//! sampled at t. Missing samples are found from the sample counter when there is one, else
//! from the stamps: a step of `s` nominal intervals dt, rounded, is `round(s) - 1` missing
//! samples (a step under 1.5 dt is jitter). Bridged samples get the linear interpolation of
//! the neighbouring records' rates (or per-interval increments) and temperatures, so the angle
//! over the gap is the trapezoid estimate; they are listed in the provenance.

use sins_imu::ImuSample;
use sins_nav::Vec3;

use crate::description::{OnGap, Quantity, Rule, Stamps};
use crate::error::SourcePos;

/// One record, converted to SI and to the body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Record {
    /// Where it came from.
    pub at: SourcePos,
    /// Its time stamp (s), if the recording has one.
    pub stamp_s: Option<f64>,
    /// Its sample counter, if the recording has one.
    pub counter: Option<u64>,
    /// Gyro rate (rad/s) or angular increment (rad), body frame.
    pub gyro: Vec3,
    /// Specific force (m/s^2) or velocity increment (m/s), body frame.
    pub accel: Vec3,
    /// Temperatures (degC; NaN without).
    pub temp_degc: [f64; 3],
}

/// How records become samples.
#[derive(Clone, Copy, Debug)]
pub struct TimelineConfig {
    /// Nominal sample interval (s).
    pub dt_s: f64,
    /// Time base of the output.
    pub stamps: Stamps,
    /// Gyro channel kind and rate rule.
    pub gyro: (Quantity, Rule),
    /// Accelerometer channel kind and rate rule.
    pub accel: (Quantity, Rule),
    /// Bridge limit (samples).
    pub max_bridge: u64,
    /// Longer gaps.
    pub on_gap: OnGap,
    /// The counter wraps here.
    pub counter_modulo: Option<u64>,
    /// Start of the first interval when there are no stamps (s).
    pub start_s: f64,
}

/// What happened at a record.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Event {
    /// Samples emitted normally.
    Normal,
    /// `missing` samples bridged before this record.
    Bridged {
        /// Samples inserted.
        missing: u64,
    },
    /// A new stretch starts at this record (`missing` samples lost before it).
    Split {
        /// Samples lost.
        missing: u64,
    },
}

/// Why a record cannot be taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Refusal {
    /// The stamp does not increase.
    Backwards {
        /// Previous record's position.
        prev: SourcePos,
        /// Previous stamp (s).
        prev_t_s: f64,
        /// This stamp (s).
        t_s: f64,
    },
    /// A gap longer than the bridge limit with `on_gap = "refuse"`.
    Gap {
        /// Samples missing.
        missing: u64,
        /// Previous time (s).
        prev_t_s: f64,
        /// This time (s).
        t_s: f64,
    },
    /// The counter does not increase.
    CounterBackwards {
        /// Previous counter.
        prev: u64,
        /// This counter.
        this: u64,
    },
}

/// Time-stamp statistics of the single-interval steps (jitter), in seconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepStats {
    /// Number of single-interval steps.
    pub n: u64,
    sum: f64,
    sum_sq: f64,
    /// Shortest step (s).
    pub min_s: f64,
    /// Longest step (s).
    pub max_s: f64,
}

impl StepStats {
    fn add(&mut self, step: f64) {
        if self.n == 0 {
            self.min_s = step;
            self.max_s = step;
        }
        self.n += 1;
        self.sum += step;
        self.sum_sq += step * step;
        self.min_s = self.min_s.min(step);
        self.max_s = self.max_s.max(step);
    }

    /// Mean step (s).
    pub fn mean_s(&self) -> f64 {
        self.sum / self.n.max(1) as f64
    }

    /// Standard deviation of the steps (s).
    pub fn std_s(&self) -> f64 {
        let n = self.n.max(1) as f64;
        let m = self.sum / n;
        (self.sum_sq / n - m * m).max(0.0).sqrt()
    }
}

#[derive(Clone, Copy, Debug)]
struct Prev {
    rec: Record,
    /// Output time of the previous record (s).
    t_s: f64,
}

/// The converter: feed records in file order with [`Timeline::push`].
#[derive(Debug)]
pub struct Timeline {
    cfg: TimelineConfig,
    prev: Option<Prev>,
    /// Samples emitted in the current stretch (bridged included).
    n_out: u64,
    /// Output time of the current stretch's first emitted sample, minus n dt (nominal base).
    origin_s: f64,
    /// Records consumed in the current stretch without a stamp: their nominal index.
    index: u64,
    /// Single-interval stamp steps.
    pub steps: StepStats,
}

impl Timeline {
    /// A converter.
    pub fn new(cfg: TimelineConfig) -> Self {
        Self {
            cfg,
            prev: None,
            n_out: 0,
            origin_s: 0.0,
            index: 0,
            steps: StepStats::default(),
        }
    }

    /// Is the first record only the start of the first interval (a trapezoid rate)?
    fn opens_only(&self) -> bool {
        let trap = |(q, r): (Quantity, Rule)| q == Quantity::Rate && r == Rule::Trapezoid;
        trap(self.cfg.gyro) || trap(self.cfg.accel)
    }

    /// Take the next record; emitted samples go to `out` (in time order). Returns what
    /// happened, or why the record is refused.
    pub fn push(&mut self, rec: Record, out: &mut Vec<ImuSample>) -> Result<Event, Refusal> {
        let dt = self.cfg.dt_s;
        let Some(prev) = self.prev else {
            self.start(rec, out);
            return Ok(Event::Normal);
        };
        let missing = self.missing(&prev, &rec)?;
        let step_s = match (rec.stamp_s, prev.rec.stamp_s) {
            (Some(t), Some(p)) => t - p,
            _ => (missing + 1) as f64 * dt,
        };
        if missing == 0 && rec.stamp_s.is_some() {
            self.steps.add(step_s);
        }
        let event = if missing == 0 {
            Event::Normal
        } else if missing <= self.cfg.max_bridge {
            Event::Bridged { missing }
        } else if self.cfg.on_gap == OnGap::Split {
            self.index += missing;
            self.start(rec, out);
            return Ok(Event::Split { missing });
        } else {
            return Err(Refusal::Gap {
                missing,
                prev_t_s: prev.rec.stamp_s.unwrap_or(prev.t_s),
                t_s: rec.stamp_s.unwrap_or(prev.t_s + step_s),
            });
        };
        let n = missing + 1;
        let sub_dt = step_s / n as f64;
        for j in 1..=n {
            let w = j as f64 / n as f64;
            let lerp = |a: f64, b: f64| a + (b - a) * w;
            let here = Record {
                gyro: if j == n {
                    rec.gyro
                } else {
                    prev.rec.gyro.lerp(&rec.gyro, w)
                },
                accel: if j == n {
                    rec.accel
                } else {
                    prev.rec.accel.lerp(&rec.accel, w)
                },
                temp_degc: std::array::from_fn(|k| {
                    if j == n {
                        rec.temp_degc[k]
                    } else {
                        lerp(prev.rec.temp_degc[k], rec.temp_degc[k])
                    }
                }),
                ..rec
            };
            let before = if j == 1 {
                prev.rec
            } else {
                self.last_rec(&prev.rec, &rec, j - 1, n)
            };
            let h = match self.cfg.stamps {
                Stamps::Recorded => sub_dt,
                Stamps::Nominal => dt,
            };
            let t_s = match self.cfg.stamps {
                Stamps::Recorded => prev.t_s + sub_dt * j as f64,
                Stamps::Nominal => self.origin_s + (self.n_out as f64) * dt,
            };
            out.push(self.sample(&before, &here, h, t_s));
            self.n_out += 1;
        }
        let t_s = out.last().map_or(prev.t_s, |s| s.t_s);
        self.prev = Some(Prev { rec, t_s });
        self.index += n;
        Ok(event)
    }

    /// The interpolated record `j` of `n` between `a` and `b` (for the left end of a bridged
    /// interval).
    fn last_rec(&self, a: &Record, b: &Record, j: u64, n: u64) -> Record {
        let w = j as f64 / n as f64;
        Record {
            gyro: a.gyro.lerp(&b.gyro, w),
            accel: a.accel.lerp(&b.accel, w),
            ..*b
        }
    }

    /// Start a stretch at `rec`. With the nominal base, the next emitted sample is at
    /// `origin_s + n_out * dt`: the first record's own time when it carries an increment (or a
    /// held rate), one interval later when it only opens a trapezoid.
    fn start(&mut self, rec: Record, out: &mut Vec<ImuSample>) {
        let dt = self.cfg.dt_s;
        let t_rec = rec
            .stamp_s
            .unwrap_or(self.cfg.start_s + (self.index + 1) as f64 * dt);
        self.index += 1;
        if self.opens_only() {
            self.n_out = 0;
            self.origin_s = t_rec + dt;
        } else {
            out.push(self.sample(&rec, &rec, dt, t_rec));
            self.n_out = 1;
            self.origin_s = t_rec;
        }
        self.prev = Some(Prev { rec, t_s: t_rec });
    }

    /// Missing samples between two records.
    fn missing(&self, prev: &Prev, rec: &Record) -> Result<u64, Refusal> {
        if let (Some(t), Some(p)) = (rec.stamp_s, prev.rec.stamp_s)
            && t <= p
        {
            return Err(Refusal::Backwards {
                prev: prev.rec.at,
                prev_t_s: p,
                t_s: t,
            });
        }
        if let (Some(c), Some(p)) = (rec.counter, prev.rec.counter) {
            let jump = match self.cfg.counter_modulo {
                Some(m) if c < p => c + m - p,
                _ if c <= p => return Err(Refusal::CounterBackwards { prev: p, this: c }),
                _ => c - p,
            };
            return Ok(jump.saturating_sub(1));
        }
        match (rec.stamp_s, prev.rec.stamp_s) {
            (Some(t), Some(p)) => {
                let steps = ((t - p) / self.cfg.dt_s).round();
                Ok(if steps >= 2.0 { steps as u64 - 1 } else { 0 })
            }
            _ => Ok(0),
        }
    }

    /// The sample over the interval (before, here] of length `h` ending at `t_s`.
    fn sample(&self, before: &Record, here: &Record, h: f64, t_s: f64) -> ImuSample {
        let inc = |(q, r): (Quantity, Rule), a: &Vec3, b: &Vec3| match (q, r) {
            (Quantity::Increment, _) => *b,
            (Quantity::Rate, Rule::Hold) => b * h,
            (Quantity::Rate, Rule::Trapezoid) => (a + b) * (0.5 * h),
        };
        ImuSample {
            t_s,
            dtheta_rad: inc(self.cfg.gyro, &before.gyro, &here.gyro),
            dv_mps: inc(self.cfg.accel, &before.accel, &here.accel),
            temp_degc: here.temp_degc,
        }
    }
}
