//! WGS-84 Earth model: radii of curvature, normal gravity, Earth rate and transport rate, all in
//! the NED navigation frame.

use crate::Vec3;

/// WGS-84 defining constants and derived values.
pub struct Wgs84;

impl Wgs84 {
    /// Semi-major axis (m).
    pub const A_M: f64 = 6_378_137.0;
    /// Flattening.
    pub const F: f64 = 1.0 / 298.257_223_563;
    /// First eccentricity squared.
    pub const E2: f64 = Self::F * (2.0 - Self::F);
    /// Semi-minor axis (m).
    pub const B_M: f64 = Self::A_M * (1.0 - Self::F);
    /// Earth rotation rate (rad/s).
    pub const OMEGA_IE_RADPS: f64 = 7.292_115e-5;
    /// Geocentric gravitational constant GM (m^3/s^2).
    pub const GM_M3PS2: f64 = 3.986_004_418e14;
    /// Normal gravity at the equator (m/s^2).
    pub const GAMMA_E_MPS2: f64 = 9.780_325_335_9;
    /// Normal gravity at the poles (m/s^2).
    pub const GAMMA_P_MPS2: f64 = 9.832_184_937_8;
}

/// Geodetic position: latitude and longitude in radians, height above the ellipsoid in metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geodetic {
    /// Geodetic latitude (rad), positive north.
    pub lat_rad: f64,
    /// Longitude (rad), positive east.
    pub lon_rad: f64,
    /// Height above the WGS-84 ellipsoid (m).
    pub height_m: f64,
}

impl Geodetic {
    /// Position from degrees and metres.
    pub fn from_deg(lat_deg: f64, lon_deg: f64, height_m: f64) -> Self {
        Self {
            lat_rad: lat_deg.to_radians(),
            lon_rad: lon_deg.to_radians(),
            height_m,
        }
    }

    /// North, east and down offsets (m) of `self` relative to `reference`, to first order in the
    /// angular differences (exact enough for navigation errors of a few kilometres).
    pub fn ned_offset_from_m(&self, reference: &Geodetic) -> Vec3 {
        let r = EarthAt::new(reference.lat_rad, reference.height_m);
        Vec3::new(
            (self.lat_rad - reference.lat_rad) * r.meridian_plus_h_m,
            (self.lon_rad - reference.lon_rad) * r.transverse_plus_h_m * reference.lat_rad.cos(),
            -(self.height_m - reference.height_m),
        )
    }
}

/// Meridian radius of curvature R_M (m) at geodetic latitude `lat_rad`.
pub fn meridian_radius_m(lat_rad: f64) -> f64 {
    let s2 = lat_rad.sin().powi(2);
    Wgs84::A_M * (1.0 - Wgs84::E2) / (1.0 - Wgs84::E2 * s2).powf(1.5)
}

/// Transverse (prime-vertical) radius of curvature R_N (m) at geodetic latitude `lat_rad`.
pub fn transverse_radius_m(lat_rad: f64) -> f64 {
    let s2 = lat_rad.sin().powi(2);
    Wgs84::A_M / (1.0 - Wgs84::E2 * s2).sqrt()
}

/// Normal gravity magnitude (m/s^2) at latitude `lat_rad` and height `height_m`: Somigliana's
/// closed formula on the ellipsoid with the standard second-order free-air height correction.
/// Positive down in the NED frame; it already contains the centrifugal term of Earth rotation.
pub fn normal_gravity_mps2(lat_rad: f64, height_m: f64) -> f64 {
    normal_gravity_at_sin_mps2(lat_rad.sin(), height_m)
}

/// [`normal_gravity_mps2`] at a latitude of sine `sin_lat` (a step that has the sine already
/// saves a second evaluation; glibc's `sincos` gives `sin`'s bits).
#[inline]
fn normal_gravity_at_sin_mps2(sin_lat: f64, height_m: f64) -> f64 {
    let s2 = sin_lat.powi(2);
    let a = Wgs84::A_M;
    let b = Wgs84::B_M;
    let k = (b * Wgs84::GAMMA_P_MPS2 - a * Wgs84::GAMMA_E_MPS2) / (a * Wgs84::GAMMA_E_MPS2);
    let g0 = Wgs84::GAMMA_E_MPS2 * (1.0 + k * s2) / (1.0 - Wgs84::E2 * s2).sqrt();
    let m = Wgs84::OMEGA_IE_RADPS.powi(2) * a * a * b / Wgs84::GM_M3PS2;
    let f = Wgs84::F;
    g0 * (1.0 - 2.0 / a * (1.0 + f + m - 2.0 * f * s2) * height_m
        + 3.0 / (a * a) * height_m.powi(2))
}

/// Earth rotation rate expressed in NED (rad/s): `[Ω cos L, 0, -Ω sin L]`.
pub fn earth_rate_ned_radps(lat_rad: f64) -> Vec3 {
    let (s, c) = lat_rad.sin_cos();
    Vec3::new(Wgs84::OMEGA_IE_RADPS * c, 0.0, -Wgs84::OMEGA_IE_RADPS * s)
}

/// Meridian and transverse radii of curvature `(R_M, R_N)` (m) at a latitude of sine `sin_lat`.
#[inline]
fn radii_m(sin_lat: f64) -> (f64, f64) {
    let s2 = sin_lat * sin_lat;
    let w = 1.0 - Wgs84::E2 * s2;
    let rn = Wgs84::A_M / w.sqrt();
    (rn * (1.0 - Wgs84::E2) / w, rn)
}

/// Local Earth quantities at one latitude and height, cached for a mechanization step.
#[derive(Clone, Copy, Debug)]
pub struct EarthAt {
    /// sin of latitude.
    pub sin_lat: f64,
    /// cos of latitude.
    pub cos_lat: f64,
    /// R_M + h (m).
    pub meridian_plus_h_m: f64,
    /// R_N + h (m).
    pub transverse_plus_h_m: f64,
    /// Normal gravity (m/s^2, positive down).
    pub gravity_mps2: f64,
    /// Earth rate in NED (rad/s).
    pub earth_rate_ned_radps: Vec3,
}

impl EarthAt {
    /// Evaluate the Earth model at latitude `lat_rad` and height `height_m`.
    pub fn new(lat_rad: f64, height_m: f64) -> Self {
        let (sin_lat, cos_lat) = lat_rad.sin_cos();
        let (rm, rn) = radii_m(sin_lat);
        Self {
            sin_lat,
            cos_lat,
            meridian_plus_h_m: rm + height_m,
            transverse_plus_h_m: rn + height_m,
            gravity_mps2: normal_gravity_at_sin_mps2(sin_lat, height_m),
            earth_rate_ned_radps: Vec3::new(
                Wgs84::OMEGA_IE_RADPS * cos_lat,
                0.0,
                -Wgs84::OMEGA_IE_RADPS * sin_lat,
            ),
        }
    }

    /// `R_M + h` (m) alone: [`EarthAt::new`]`(lat_rad, height_m).meridian_plus_h_m` to the
    /// bit, without the gravity and Earth rate (a mechanization step needs only this at the
    /// step's start).
    pub fn meridian_plus_h_at(lat_rad: f64, height_m: f64) -> f64 {
        let (sin_lat, _) = lat_rad.sin_cos();
        radii_m(sin_lat).0 + height_m
    }

    /// Transport rate ω_en^n (rad/s) for NED velocity `vel_ned_mps`:
    /// `[v_E/(R_N+h), -v_N/(R_M+h), -v_E tan L/(R_N+h)]`.
    pub fn transport_rate_ned_radps(&self, vel_ned_mps: &Vec3) -> Vec3 {
        let tan_lat = self.sin_lat / self.cos_lat;
        Vec3::new(
            vel_ned_mps.y / self.transverse_plus_h_m,
            -vel_ned_mps.x / self.meridian_plus_h_m,
            -vel_ned_mps.y * tan_lat / self.transverse_plus_h_m,
        )
    }

    /// Gravity vector in NED (m/s^2): `[0, 0, g]`.
    pub fn gravity_ned_mps2(&self) -> Vec3 {
        Vec3::new(0.0, 0.0, self.gravity_mps2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The step-start radius is the full model's, bit for bit, from pole to pole.
    #[test]
    fn meridian_radius_alone_equals_the_full_models() {
        for k in -900..=900 {
            let lat = f64::from(k) * 0.1f64.to_radians() + 1e-9;
            for h in [-400.0, 0.0, 60.0, 8848.0] {
                let full = EarthAt::new(lat, h).meridian_plus_h_m;
                assert_eq!(
                    EarthAt::meridian_plus_h_at(lat, h).to_bits(),
                    full.to_bits()
                );
            }
        }
    }

    /// The step's gravity, from the sine its `sincos` gave, is the standalone formula's (which
    /// evaluates `sin` alone) to the bit, at a million latitudes from pole to pole: libm's two
    /// routines agree (glibc computes both with the same kernels).
    #[test]
    fn gravity_from_the_steps_sine_equals_the_standalone_formula() {
        let mut lat = -std::f64::consts::FRAC_PI_2;
        let step = std::f64::consts::PI / 1_000_003.0;
        while lat <= std::f64::consts::FRAC_PI_2 {
            for h in [0.0, 60.0] {
                // Opaque copies: the compiler may not share one sine between the two.
                let step_g = EarthAt::new(std::hint::black_box(lat), h).gravity_mps2;
                assert_eq!(
                    step_g.to_bits(),
                    normal_gravity_mps2(std::hint::black_box(lat), h).to_bits(),
                    "latitude {lat} rad, height {h} m"
                );
            }
            lat += step;
        }
    }

    #[test]
    fn somigliana_matches_published_values() {
        // WGS-84 normal gravity on the ellipsoid: equator and pole by definition, 45 deg tabulated.
        assert!((normal_gravity_mps2(0.0, 0.0) - 9.780_325_335_9).abs() < 1e-9);
        assert!(
            (normal_gravity_mps2(std::f64::consts::FRAC_PI_2, 0.0) - 9.832_184_937_8).abs() < 1e-9
        );
        assert!((normal_gravity_mps2(45f64.to_radians(), 0.0) - 9.806_197_769).abs() < 1e-6);
        // Free-air gradient about -3.086e-6 s^-2.
        let grad = (normal_gravity_mps2(0.5, 1000.0) - normal_gravity_mps2(0.5, 0.0)) / 1000.0;
        assert!((grad + 3.086e-6).abs() < 0.01e-6, "gradient {grad}");
    }

    #[test]
    fn radii_of_curvature() {
        assert!((meridian_radius_m(0.0) - 6_335_439.327).abs() < 1e-3);
        assert!((transverse_radius_m(0.0) - Wgs84::A_M).abs() < 1e-9);
        let pole = std::f64::consts::FRAC_PI_2;
        assert!((meridian_radius_m(pole) - transverse_radius_m(pole)).abs() < 1e-6);
        let e = EarthAt::new(0.4, 100.0);
        assert!((e.meridian_plus_h_m - meridian_radius_m(0.4) - 100.0).abs() < 1e-6);
        assert!((e.transverse_plus_h_m - transverse_radius_m(0.4) - 100.0).abs() < 1e-6);
    }
}
