//! Allan-deviation curves as a Rerun recording: one entity per channel and quantity on a
//! `tau_s` timeline (the averaging time, seconds), so the viewer's time-series plot shows the
//! curves against `τ` (its axis is linear: the `log10_*` entities give the log-log view).

use crate::{VizError, memory_stream, save_memory};
use std::path::Path;

/// One channel's Allan deviation (one rate unit throughout).
pub struct AllanRecord<'a> {
    /// Channel name, e.g. `gyro_x` (the entity `allan/<channel>/…`).
    pub channel: &'a str,
    /// Averaging times (s).
    pub tau_s: &'a [f64],
    /// Allan deviation.
    pub adev: &'a [f64],
    /// Lower end of its confidence interval.
    pub lo: &'a [f64],
    /// Upper end.
    pub hi: &'a [f64],
    /// The fitted model.
    pub fit: &'a [f64],
}

/// Write the curves to an `.rrd` file (aside, then renamed into place): entities
/// `allan/<channel>/{adev,lo,hi,fit}` and `allan/<channel>/log10_{adev,fit}` on the `tau_s`
/// timeline; non-finite or non-positive values are skipped.
pub fn write_allan(path: &Path, name: &str, curves: &[AllanRecord<'_>]) -> Result<(), VizError> {
    let err = |e: &dyn std::fmt::Display| VizError::Rerun {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let (rec, storage) = memory_stream(
        rerun::RecordingStreamBuilder::new("sinsbench").recording_name(name),
        path,
    )?;
    for c in curves {
        let parts: [(&str, &[f64], bool); 6] = [
            ("adev", c.adev, false),
            ("lo", c.lo, false),
            ("hi", c.hi, false),
            ("fit", c.fit, false),
            ("log10_adev", c.adev, true),
            ("log10_fit", c.fit, true),
        ];
        for (what, values, log) in parts {
            let entity = format!("allan/{}/{what}", c.channel);
            for (&t, &v) in c.tau_s.iter().zip(values) {
                if !(v > 0.0 && v.is_finite() && t.is_finite()) {
                    continue;
                }
                rec.set_duration_secs("tau_s", t);
                let y = if log { v.log10() } else { v };
                rec.log(entity.as_str(), &rerun::Scalars::single(y))
                    .map_err(|e| err(&e))?;
            }
        }
    }
    save_memory(&storage, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn allan_recording_is_written_and_verifies() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("allan.rrd");
        let tau = [0.01, 0.02, 0.04];
        let a = [1.0, 0.7, 0.5];
        let rec = AllanRecord {
            channel: "gyro_x",
            tau_s: &tau,
            adev: &a,
            lo: &a,
            hi: &a,
            fit: &a,
        };
        write_allan(&path, "test", &[rec]).expect("written");
        assert!(crate::verify_recording(&path).expect("verifies") > 0);
    }
}
