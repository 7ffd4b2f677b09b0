//! A fast `sin_cos` for the hot loop (one call per axis and quadrature node). `f64::sin_cos`
//! evaluates two libm calls; this evaluates both from one argument reduction and two short
//! polynomials, to within a few units in the last place of the libm result.

/// π/2 split for Cody-Waite reduction: the high part has 33 significant bits, so `n · HI` is
/// exact for |n| < 2^20; `LO` is the rounded remainder π/2 − HI.
const PIO2_HI: f64 = 1.570_796_326_734_125_6;
/// Low part of π/2 (π/2 − `PIO2_HI`, rounded).
const PIO2_LO: f64 = 6.077_100_506_506_192e-11;
/// 1.5 · 2^52: adding and subtracting it rounds a double of magnitude < 2^51 to an integer.
const ROUND_MAGIC: f64 = 6_755_399_441_055_744.0;
/// Largest |x| for which the two-part reduction is exact to ~1e-26 absolute per multiple.
const FAST_LIMIT: f64 = 1.0e6;

/// Minimax coefficients of sin on [-π/4, π/4] (those of fdlibm's `__kernel_sin`):
/// `sin r = r + r z (S1 + S2 z + … + S6 z^5)`, z = r².
const S: [f64; 6] = [
    -0.166_666_666_666_666_32,
    0.008_333_333_333_322_49,
    -0.000_198_412_698_298_579_5,
    2.755_731_370_707_006_8e-6,
    -2.505_076_025_340_686_3e-8,
    1.589_690_995_211_55e-10,
];
/// Minimax coefficients of cos on [-π/4, π/4] (fdlibm's `__kernel_cos`):
/// `cos r = 1 − z/2 + z² (C1 + C2 z + … + C6 z^5)`.
const C: [f64; 6] = [
    0.041_666_666_666_666_6,
    -0.001_388_888_888_887_411,
    2.480_158_728_947_673e-5,
    -2.755_731_435_139_066_3e-7,
    2.087_572_321_298_175e-9,
    -1.135_964_755_778_819_5e-11,
];

/// `(sin r, cos r)` for |r| <= π/4 (polynomials in Estrin form for a short dependency chain);
/// no argument reduction, so larger |r| lose accuracy.
#[inline(always)]
pub(crate) fn sin_cos_small(r: f64) -> (f64, f64) {
    let z = r * r;
    let z2 = z * z;
    let z4 = z2 * z2;
    let ps = (S[0] + z * S[1]) + z2 * (S[2] + z * S[3]) + z4 * (S[4] + z * S[5]);
    let pc = (C[0] + z * C[1]) + z2 * (C[2] + z * C[3]) + z4 * (C[4] + z * C[5]);
    let s = r + r * z * ps;
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    // 1 − z/2 + z²·pc with the rounding error of `w` recovered (as in `__kernel_cos`).
    let c = w + (((1.0 - w) - hz) + z2 * pc);
    (s, c)
}

/// `(sin x, cos x)` for a finite `x` (rad), within about one ulp. Arguments beyond ±1e6 rad fall
/// back to the standard library.
#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() <= std::f64::consts::FRAC_PI_4 {
        return sin_cos_small(x);
    }
    if x.is_nan() || x.abs() >= FAST_LIMIT {
        return x.sin_cos();
    }
    let nf = (x * std::f64::consts::FRAC_2_PI + ROUND_MAGIC) - ROUND_MAGIC;
    let (s, c) = sin_cos_small((x - nf * PIO2_HI) - nf * PIO2_LO);
    match (nf as i64) & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// 2π in three parts (33, 33 and 53 significant bits): `n · HI` and `n · MID` are exact for
/// |n| < 2^20.
const TWO_PI_HI: f64 = 6.283_185_306_936_502_5;
/// Middle part of 2π.
const TWO_PI_MID: f64 = 2.430_840_202_521_586_4e-10;
/// Low part of 2π.
const TWO_PI_LO: f64 = 8.089_064_995_183_803e-21;
/// 1/(2π).
const INV_TWO_PI: f64 = 0.159_154_943_091_895_35;

/// Dekker's exact product: `a · b = p + e` with `p` the rounded product (no FMA needed).
#[inline(always)]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    const SPLIT: f64 = 134_217_729.0; // 2^27 + 1
    let split = |x: f64| {
        let c = SPLIT * x;
        let hi = c - (c - x);
        (hi, x - hi)
    };
    let p = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    let e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    (p, e)
}

/// `ω τ + φ` reduced modulo 2π to about [-π, π] + φ, with the product `ω τ` carried exactly:
/// the result is accurate to a few ulp of 2π for |ω τ| < 6.5e6 rad, so phases of consecutive
/// samples, each computed from its own start time, join without the ~1e-10 rad rounding of a
/// plain `ω τ + φ` after hours of vibration.
#[inline(always)]
pub(crate) fn reduced_phase(omega_radps: f64, tau_s: f64, phase_rad: f64) -> f64 {
    let (p, e) = two_prod(omega_radps, tau_s);
    let n = (p * INV_TWO_PI + ROUND_MAGIC) - ROUND_MAGIC;
    if n.is_nan() || n.abs() >= 1_048_576.0 {
        return p + phase_rad;
    }
    ((((p - n * TWO_PI_HI) - n * TWO_PI_MID) + e) - n * TWO_PI_LO) + phase_rad
}

#[cfg(test)]
mod tests {
    use super::{reduced_phase, sin_cos};

    /// Distance between two angles modulo 2π.
    fn angle_gap(a: f64, b: f64) -> f64 {
        let d = (a - b).rem_euclid(std::f64::consts::TAU);
        d.min(std::f64::consts::TAU - d)
    }

    #[test]
    fn reduced_phase_joins_consecutive_intervals_where_the_plain_product_does_not() {
        let omega = std::f64::consts::TAU / 0.1;
        let h = 0.007_812_5; // 2^-7 s: τ + h is exact below 2^45 s
        let mut worst = 0.0f64;
        let mut worst_plain = 0.0f64;
        for k in 0..2000 {
            let tau = 9_600.0 + f64::from(k) * 3.0 * h;
            let a = reduced_phase(omega, tau, 0.3);
            let b = reduced_phase(omega, tau + h, 0.3);
            let step = reduced_phase(omega, h, 0.0);
            worst = worst.max(angle_gap(b, a + step));
            let (pa, pb) = (omega * tau + 0.3, omega * (tau + h) + 0.3);
            worst_plain = worst_plain.max(angle_gap(pb, pa + omega * h));
        }
        assert!(worst < 4e-15, "reduced phase gap {worst:e}");
        assert!(
            worst_plain > 1e-11,
            "plain product gap {worst_plain:e} (test must discriminate)"
        );
        // Small arguments are untouched.
        assert_eq!(reduced_phase(2.0, 0.5, 0.25), 1.25);
    }

    #[test]
    fn matches_std_to_a_few_ulp() {
        let mut worst = 0.0f64;
        let mut x = -40.0;
        while x < 40.0 {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
            x += 0.000_731_3;
        }
        assert!(worst < 4.5e-16, "worst abs error {worst:e}");
        // Small arguments keep full relative precision.
        for x in [1e-300, 1e-12, -3e-8, 0.01] {
            let (s, c) = sin_cos(x);
            assert!((s - x.sin()).abs() <= 2.0 * f64::EPSILON * x.abs());
            assert!((c - x.cos()).abs() <= f64::EPSILON);
        }
        // Large arguments: reduced exactly enough for 1e-10 absolute.
        for x in [12_345.678_9, -9.87e5, 3.3e7] {
            let (s, c) = sin_cos(x);
            assert!(
                (s - x.sin()).abs() < 1e-10 && (c - x.cos()).abs() < 1e-10,
                "{x}"
            );
        }
    }
}
