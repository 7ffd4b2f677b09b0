//! The paper's units and their SI factors. SI values cross crate boundaries; these units live only
//! in files and reports.

use crate::exact::ExactFactor;
use sins_nav::{ARCSEC, DEG, DEG_PER_H, UG};

/// One part per million (dimensionless).
pub const PPM: f64 = 1e-6;
/// One degree per square-root hour in rad/sqrt(s) (gyro angle random walk).
pub const DEG_PER_SQRT_H: f64 = DEG / 60.0;
/// One micro-g per square-root hertz in m/s/sqrt(s) (accelerometer velocity random walk).
pub const UG_PER_SQRT_HZ: f64 = UG;
/// One deg/h per square-root hour in rad/s/sqrt(s) (gyro bias random walk).
pub const DEG_PER_H_PER_SQRT_H: f64 = DEG_PER_H / 60.0;
/// One micro-g per square-root hour in m/s²/sqrt(s) (accelerometer bias random walk).
pub const UG_PER_SQRT_H: f64 = UG / 60.0;
/// Seconds per hour.
pub const S_PER_H: f64 = 3600.0;

/// A unit in which the paper states an error coefficient.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PaperUnit {
    /// deg/h (gyro drift).
    DegPerH,
    /// ppm (scale-factor errors).
    Ppm,
    /// arcsec (installation errors).
    Arcsec,
    /// ug = 1e-6 · 9.80665 m/s^2 (accelerometer bias).
    Ug,
    /// ug/degC (TB).
    UgPerDegC,
    /// ppm/degC (TK).
    PpmPerDegC,
    /// arcsec/degC (TM).
    ArcsecPerDegC,
}

impl PaperUnit {
    /// The unit as the paper and the reports write it, e.g. `"deg/h"`, `"ug/degC"`.
    pub fn label(self) -> &'static str {
        match self {
            PaperUnit::DegPerH => "deg/h",
            PaperUnit::Ppm => "ppm",
            PaperUnit::Arcsec => "arcsec",
            PaperUnit::Ug => "ug",
            PaperUnit::UgPerDegC => "ug/degC",
            PaperUnit::PpmPerDegC => "ppm/degC",
            PaperUnit::ArcsecPerDegC => "arcsec/degC",
        }
    }

    /// The suffix of file keys in this unit, e.g. `"deg_per_h"`, `"ug_per_degc"`.
    pub fn key_suffix(self) -> &'static str {
        match self {
            PaperUnit::DegPerH => "deg_per_h",
            PaperUnit::Ppm => "ppm",
            PaperUnit::Arcsec => "arcsec",
            PaperUnit::Ug => "ug",
            PaperUnit::UgPerDegC => "ug_per_degc",
            PaperUnit::PpmPerDegC => "ppm_per_degc",
            PaperUnit::ArcsecPerDegC => "arcsec_per_degc",
        }
    }

    /// SI value of one unit: rad/s, 1, rad, m/s^2 and their per-degC forms (the `sins-nav`
    /// constants `DEG_PER_H`, `ARCSEC`, `UG` and 1e-6 for ppm).
    pub fn si(self) -> f64 {
        match self {
            PaperUnit::DegPerH => DEG_PER_H,
            PaperUnit::Ppm | PaperUnit::PpmPerDegC => PPM,
            PaperUnit::Arcsec | PaperUnit::ArcsecPerDegC => ARCSEC,
            PaperUnit::Ug | PaperUnit::UgPerDegC => UG,
        }
    }

    /// The exact factor used for file conversion: the `f64` constants `DEG_PER_H` and `ARCSEC`
    /// taken exactly, ppm as exactly 10^-6 and ug as exactly 9.80665·10^-6 m/s^2.
    pub(crate) fn factor(self) -> ExactFactor {
        match self {
            PaperUnit::DegPerH => ExactFactor::binary(DEG_PER_H),
            PaperUnit::Ppm | PaperUnit::PpmPerDegC => ExactFactor::decimal(1, -6),
            PaperUnit::Arcsec | PaperUnit::ArcsecPerDegC => ExactFactor::binary(ARCSEC),
            PaperUnit::Ug | PaperUnit::UgPerDegC => ExactFactor::decimal(980_665, -11),
        }
    }

    /// Converts a value in this unit to SI (plain multiplication, for reports and tests).
    pub fn to_si(self, value: f64) -> f64 {
        value * self.si()
    }

    /// Converts an SI value to this unit (plain division, for reports).
    pub fn from_si(self, si: f64) -> f64 {
        si / self.si()
    }
}
