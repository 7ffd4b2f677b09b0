//! Plausibility limits: physical bounds beyond which an experiment or parameter file value cannot
//! describe a real inertial navigation system on the Earth, so that a typo or a unit error (a
//! scale factor of 1e300 ppm, a run of 1e12 s, a sample rate of 1e9 Hz, a chamber at a million
//! degC) is refused with an error naming the key, instead of being simulated until the disk is
//! full.
//!
//! Coefficient limits are ten times the largest value a physically working IMU of any grade
//! plausibly has (low-grade MEMS sets the largest values; the navigation-grade laser-gyro IMU of
//! the paper is orders of magnitude below every one of them), so that no real device is refused.
//! The dataset readers of `sins-data` apply the same site, temperature and full-scale limits to
//! every row.

use crate::units::PaperUnit;
use sins_imu::EffectKind;

/// Highest accepted sample rate (Hz). Navigation-grade IMUs deliver increments at 100 Hz to
/// 2 kHz; 10 kHz is five times the fastest, and keeps a 15 h run at 540 M rows.
pub const MAX_SAMPLE_RATE_HZ: f64 = 10_000.0;

/// Longest accepted run (s): 366 days. No INS test campaign records continuously for longer; a
/// longer value is a unit error (and at 10 kHz it would already be 3.2e11 rows, far beyond any
/// disk). The free-space check of `simulate` guards the practical limit.
pub const MAX_RUN_DURATION_S: f64 = 366.0 * 86_400.0;

/// Most motion segments a program may expand to (a `scheme` with `repeat` expands to two segments
/// per step and repetition): a million segments is about 60 MB of program, far more than any
/// turntable schedule.
pub const MAX_MOTION_SEGMENTS: usize = 1_000_000;

/// Lowest accepted temperature (degC): the cold end of the extended military storage and
/// operating range (-55 degC) with margin. Chambers, sensor offsets and thermometers must stay in
/// [`MIN_TEMPERATURE_DEGC`, `MAX_TEMPERATURE_DEGC`].
pub const MIN_TEMPERATURE_DEGC: f64 = -60.0;

/// Highest accepted temperature (degC): the maximum junction temperature of the electronics of
/// an IMU (125 degC); no sensor works above it.
pub const MAX_TEMPERATURE_DEGC: f64 = 125.0;

/// Lowest accepted height above the ellipsoid (m): the deepest ocean floor (Challenger Deep,
/// about 10.9 km below sea level, where the geoid is within 100 m of the ellipsoid) rounded down
/// to -12 km. Deep-submergence vehicles carry navigation-grade INS, so any height between that
/// and the surface is physically possible; below it the site is inside the solid Earth.
pub const MIN_HEIGHT_M: f64 = -12_000.0;

/// Highest accepted height above the ellipsoid (m): 100 km, the Kármán line. Above it the
/// vehicle is a spacecraft, outside the normal-gravity model of the navigation equations.
pub const MAX_HEIGHT_M: f64 = 100_000.0;

/// Gyro full-scale range assumed for a navigation-grade IMU (deg/s): ±1000 deg/s, the range of
/// tactical and navigation IMUs such as the HG1700 and LN-200 class (ring-laser navigation
/// units specify less). A gyro saturates there, so an angular increment over one sample interval
/// `dt` cannot exceed this rate times `dt`; turntable and vibration rates of an experiment must
/// stay within it too (the paper's largest, pattern 3, peaks at 628 deg/s about z).
pub const GYRO_FULL_SCALE_DEG_PER_S: f64 = 1000.0;

/// Accelerometer full-scale range assumed for a navigation-grade IMU (g = 9.80665 m/s^2): ±60 g,
/// the input range of the quartz flexure accelerometers (QA-2000 class) of navigation-grade
/// IMUs like the paper's; a velocity increment over one sample interval `dt` cannot exceed
/// 60 g times `dt`.
pub const ACCEL_FULL_SCALE_G: f64 = 60.0;

/// The largest physically plausible magnitude of a coefficient of the paper's model, in its
/// paper unit; files are refused beyond [`COEFFICIENT_LIMIT_FACTOR`] times it.
///
/// | unit | largest plausible | who has it |
/// |---|---|---|
/// | deg/h (gyro bias) | 3600 deg/h = 1 deg/s | turn-on bias of low-grade MEMS gyros |
/// | ppm (scale-factor error) | 10 000 ppm = 1 % | uncalibrated MEMS sensors |
/// | arcsec (misalignment) | 3600 arcsec = 1 deg | an unaligned sensor mount |
/// | ug (accelerometer bias) | 100 000 ug = 0.1 g | low-grade MEMS zero-g offset |
/// | ug/degC (TB) | 1000 ug/degC = 1 mg/degC | MEMS zero-g temperature drift |
/// | ppm/degC (TK) | 1000 ppm/degC = 0.1 %/degC | MEMS sensitivity temperature drift |
/// | arcsec/degC (TM) | 100 arcsec/degC | a plastic mount that moves 1 deg over 36 degC |
pub fn largest_plausible(unit: PaperUnit) -> f64 {
    match unit {
        PaperUnit::DegPerH => 3600.0,
        PaperUnit::Ppm => 10_000.0,
        PaperUnit::Arcsec => 3600.0,
        PaperUnit::Ug => 100_000.0,
        PaperUnit::UgPerDegC => 1000.0,
        PaperUnit::PpmPerDegC => 1000.0,
        PaperUnit::ArcsecPerDegC => 100.0,
    }
}

/// How far beyond the largest plausible value a coefficient may go before a file is refused.
pub const COEFFICIENT_LIMIT_FACTOR: f64 = 10.0;

/// The limit of a coefficient in `unit` (its paper unit): [`COEFFICIENT_LIMIT_FACTOR`] times
/// [`largest_plausible`].
pub fn coefficient_limit(unit: PaperUnit) -> f64 {
    COEFFICIENT_LIMIT_FACTOR * largest_plausible(unit)
}

/// The largest physically plausible magnitude of one component of an extra effect, in the
/// effect's unit ([`EffectKind::unit`]); files are refused beyond [`COEFFICIENT_LIMIT_FACTOR`]
/// times it. Each is set by the worst sensor class (MEMS) or the worst installation, far above
/// the navigation-grade [`EffectKind::typical_magnitude`].
pub fn effect_largest_plausible(kind: EffectKind) -> f64 {
    match kind {
        // MEMS accelerometers: up to ~100 ug/degC^2 of curvature.
        EffectKind::AccelBiasQuadraticTemp => 100.0,
        // MEMS gyros: 0.03 deg/s/degC = 108 deg/h/degC.
        EffectKind::GyroBiasTemp => 100.0,
        // Steep gradients across a MEMS die: ~1 mg per degC/min.
        EffectKind::AccelBiasTempRate => 1000.0,
        // MEMS gyro bias under thermal transients: ~10 deg/h per degC/min.
        EffectKind::GyroBiasTempRate => 10.0,
        // A massive, insulated IMU: one hour from case to proof mass.
        EffectKind::ThermalLag => 3600.0,
        // MEMS accelerometers: ~0.1 % of full scale nonlinearity, ~1000 ug/g^2.
        EffectKind::AccelQuadratic | EffectKind::AccelCrossCoupling => 1000.0,
        // The size of an IMU: proof masses at most ~100 mm from the navigation centre.
        EffectKind::SizeEffect => 100.0,
        // MEMS gyro scale-factor asymmetry: up to 1 %.
        EffectKind::GyroScaleAsymmetry => 10_000.0,
        // MEMS gyros: ~0.1 deg/s/g = 360 deg/h/g.
        EffectKind::GyroGSensitivity => 360.0,
        // Separate gyro and accelerometer buses: up to 100 ms of skew.
        EffectKind::AccelTimeOffset => 100.0,
        // MEMS gyro rate random walk: ~100 deg/h/sqrt(h).
        EffectKind::GyroBiasRandomWalk => 100.0,
        // MEMS accelerometer bias random walk: ~1000 ug/sqrt(h).
        EffectKind::AccelBiasRandomWalk => 1000.0,
        // As large as a MEMS gyro bias.
        EffectKind::GyroBiasOscillation => 3600.0,
        // As large as a MEMS accelerometer bias.
        EffectKind::AccelBiasStep
        | EffectKind::AccelBiasTransient
        | EffectKind::AccelBiasPlateau
        | EffectKind::AccelBiasPulse
        | EffectKind::AccelBiasDecayingOscillation => 100_000.0,
        // As large as a MEMS gyro bias.
        EffectKind::GyroBiasStep
        | EffectKind::GyroBiasTransient
        | EffectKind::GyroBiasPlateau
        | EffectKind::GyroBiasPulse
        | EffectKind::GyroBiasDecayingOscillation => 3600.0,
        // A MEMS bias drifting over its whole range within an hour.
        EffectKind::GyroBiasRamp => 3600.0,
        EffectKind::AccelBiasRamp => 100_000.0,
    }
}

/// The limit of one component of an extra effect in its unit: [`COEFFICIENT_LIMIT_FACTOR`] times
/// [`effect_largest_plausible`].
pub fn effect_limit(kind: EffectKind) -> f64 {
    COEFFICIENT_LIMIT_FACTOR * effect_largest_plausible(kind)
}

/// Limits of the `[imu.noise]` values of an experiment (10x the largest plausible, MEMS):
/// `(key, limit in the key's unit, largest plausible described)`.
pub const NOISE_LIMITS: [(&str, f64, &str); 5] = [
    (
        "gyro_arw_deg_per_sqrt_h",
        10.0,
        "1 deg/sqrt(h), a low-grade MEMS gyro",
    ),
    (
        "gyro_bias_instability_deg_per_h",
        1000.0,
        "100 deg/h, a low-grade MEMS gyro",
    ),
    (
        "gyro_quantum_arcsec",
        1000.0,
        "100 arcsec, a coarse pulse readout",
    ),
    (
        "accel_vrw_ug_per_sqrt_hz",
        10_000.0,
        "1000 ug/sqrt(Hz), a low-grade MEMS accelerometer",
    ),
    (
        "accel_bias_instability_ug",
        10_000.0,
        "1000 ug, a low-grade MEMS accelerometer",
    ),
];

/// Limit of `thermometer_noise_degc` (degC): 10x the 1 degC of the coarsest on-chip sensors.
pub const MAX_THERMOMETER_NOISE_DEGC: f64 = 10.0;

/// True when `t_degc` is a temperature an IMU can have ([`MIN_TEMPERATURE_DEGC`] to
/// [`MAX_TEMPERATURE_DEGC`]).
pub fn temperature_ok(t_degc: f64) -> bool {
    (MIN_TEMPERATURE_DEGC..=MAX_TEMPERATURE_DEGC).contains(&t_degc)
}

/// True when `height_m` is on or in the Earth ([`MIN_HEIGHT_M`] to [`MAX_HEIGHT_M`]).
pub fn height_ok(height_m: f64) -> bool {
    (MIN_HEIGHT_M..=MAX_HEIGHT_M).contains(&height_m)
}

/// "outside -60..125 degC", for messages.
pub fn temperature_range_text() -> String {
    format!(
        "outside the {MIN_TEMPERATURE_DEGC}..{MAX_TEMPERATURE_DEGC} degC an IMU can work at \
         (extended military range)"
    )
}

/// "outside -12000..100000 m", for messages.
pub fn height_range_text() -> String {
    format!(
        "outside {MIN_HEIGHT_M}..{MAX_HEIGHT_M} m above the ellipsoid (from the deepest ocean \
         floor to the edge of space): not a place on the Earth"
    )
}
