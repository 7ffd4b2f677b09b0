//! Exact conversion between decimal numbers in paper units and SI doubles.
//!
//! Reading `0.003 deg/h` as `0.003_f64 * DEG_PER_H` cannot reach every double: multiplying by a
//! constant whose mantissa is above one skips some results, so a calibration estimate written in
//! paper units could come back one ulp off. Instead, a paper-unit decimal is converted with a single
//! correct rounding of `decimal × factor` (the factor being an exact rational: the `f64` constant
//! for deg/h and arcsec, the exact decimal for ppm and ug), and [`format_exact`] searches for the
//! shortest decimal that converts back to the very same double. Together they make
//! write-then-read bit exact for every finite SI value.

use num_bigint::BigUint;
use std::cmp::Ordering;

/// A positive unit factor that equals `mant · 2^pow2 · 10^pow10` exactly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct ExactFactor {
    mant: u64,
    pow2: i32,
    pow10: i32,
}

impl ExactFactor {
    /// The identity factor (unit already SI, e.g. degC).
    pub(crate) const ONE: ExactFactor = ExactFactor::decimal(1, 0);

    /// The exact decimal `mant · 10^pow10` (e.g. ppm = 1e-6, ug = 980665e-11 m/s^2).
    pub(crate) const fn decimal(mant: u64, pow10: i32) -> Self {
        Self {
            mant,
            pow2: 0,
            pow10,
        }
    }

    /// The exact value of a positive, finite, normal `f64` (e.g. `DEG_PER_H`).
    pub(crate) fn binary(x: f64) -> Self {
        let (mant, pow2) = decompose(x);
        Self {
            mant,
            pow2,
            pow10: 0,
        }
    }

    /// The nearest `f64` to the factor (for first guesses).
    pub(crate) fn approx(&self) -> f64 {
        (self.mant as f64) * 2f64.powi(self.pow2) * 10f64.powi(self.pow10)
    }
}

/// `x = mant · 2^pow2` for a finite `x` (sign ignored).
fn decompose(x: f64) -> (u64, i32) {
    let bits = x.abs().to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i32;
    let frac = bits & ((1u64 << 52) - 1);
    if exp == 0 {
        (frac, -1074)
    } else {
        (frac | (1u64 << 52), exp - 1075)
    }
}

/// A decimal literal `±digits · 10^exp10`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Decimal {
    negative: bool,
    /// ASCII digits without leading zeros (empty for zero).
    digits: Vec<u8>,
    exp10: i32,
}

impl Decimal {
    /// Parses a decimal number (`-12.5e-3`, `20`, `+1_000.0`; TOML underscores allowed). Returns
    /// `None` for anything else (hex integers, `inf`, `nan`, strings, ...).
    pub(crate) fn parse(text: &str) -> Option<Self> {
        let t: String = text.trim().chars().filter(|c| *c != '_').collect();
        let (negative, rest) = match t.as_bytes().first()? {
            b'-' => (true, &t[1..]),
            b'+' => (false, &t[1..]),
            _ => (false, &t[..]),
        };
        let (mantissa, exponent) = match rest.find(['e', 'E']) {
            Some(i) => (&rest[..i], Some(&rest[i + 1..])),
            None => (rest, None),
        };
        let (int_part, frac_part) = match mantissa.find('.') {
            Some(i) => (&mantissa[..i], &mantissa[i + 1..]),
            None => (mantissa, ""),
        };
        let all_digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
        if int_part.is_empty() || !all_digits(int_part) || !all_digits(frac_part) {
            return None;
        }
        if mantissa.contains('.') && frac_part.is_empty() {
            return None;
        }
        let mut exp10: i64 = match exponent {
            Some(e) => {
                let digits = e.strip_prefix(['+', '-']).unwrap_or(e);
                if digits.is_empty() || !all_digits(digits) || digits.len() > 6 {
                    return None;
                }
                e.parse::<i64>().ok()?
            }
            None => 0,
        };
        exp10 -= frac_part.len() as i64;
        let mut digits: Vec<u8> = int_part.bytes().chain(frac_part.bytes()).collect();
        let leading = digits.iter().take_while(|d| **d == b'0').count();
        digits.drain(..leading);
        while digits.last() == Some(&b'0') {
            digits.pop();
            exp10 += 1;
        }
        let exp10 = i32::try_from(exp10).ok()?;
        Some(Self {
            negative,
            digits,
            exp10,
        })
    }

    fn is_zero(&self) -> bool {
        self.digits.is_empty()
    }

    /// The correctly rounded (half to even) double nearest to `self × factor`.
    pub(crate) fn to_f64_times(&self, factor: ExactFactor) -> f64 {
        let sign = if self.negative { -1.0 } else { 1.0 };
        if self.is_zero() {
            return sign * 0.0;
        }
        let text = format!(
            "{}e{}",
            std::str::from_utf8(&self.digits).unwrap_or("0"),
            self.exp10
        );
        let guess = text.parse::<f64>().unwrap_or(f64::NAN) * factor.approx();
        // Outside the comfortable normal range (or non-finite) the plain product is returned.
        if !guess.is_finite() || !(1e-290..=1e290).contains(&guess) {
            return sign * guess;
        }
        let mut x = guess;
        for _ in 0..64 {
            let up = x.next_up();
            let down = x.next_down();
            let odd = decompose(x).0 & 1 == 1;
            match self.cmp_midpoint(factor, x, up) {
                Ordering::Greater => {
                    x = up;
                    continue;
                }
                Ordering::Equal if odd => {
                    x = up;
                    continue;
                }
                _ => {}
            }
            match self.cmp_midpoint(factor, down, x) {
                Ordering::Less => x = down,
                Ordering::Equal if odd => x = down,
                _ => break,
            }
        }
        sign * x
    }

    /// Compares `|self| × factor` with the exact midpoint of the positive doubles `a < b`.
    fn cmp_midpoint(&self, factor: ExactFactor, a: f64, b: f64) -> Ordering {
        let (ma, ga) = decompose(a);
        let (mb, gb) = decompose(b);
        let g = ga.min(gb);
        // mid = (ma·2^(ga-g) + mb·2^(gb-g)) · 2^(g-1); the shifts are 0 or 1.
        let m = ((ma as u128) << (ga - g)) + ((mb as u128) << (gb - g));
        let digits = BigUint::parse_bytes(&self.digits, 10).unwrap_or_default();
        let mut left = digits * factor.mant;
        let mut right = BigUint::from(m);
        let k10 = self.exp10 + factor.pow10;
        let ten = BigUint::from(10u32);
        if k10 >= 0 {
            left *= ten.pow(k10.unsigned_abs());
        } else {
            right *= ten.pow(k10.unsigned_abs());
        }
        let (l2, r2) = (factor.pow2, g - 1);
        if l2 >= r2 {
            left <<= (l2 - r2) as usize;
        } else {
            right <<= (r2 - l2) as usize;
        }
        left.cmp(&right)
    }
}

/// Converts a paper-unit number text to SI with one correct rounding, or `None` when the text is
/// not a decimal number.
pub(crate) fn decimal_to_si(text: &str, factor: ExactFactor) -> Option<f64> {
    Decimal::parse(text).map(|d| d.to_f64_times(factor))
}

/// The shortest decimal text (TOML and JSON float syntax) that [`decimal_to_si`] turns back into
/// exactly `si` with `factor`. Non-finite values are written with `{:?}` (not valid in files).
pub(crate) fn format_exact(si: f64, factor: ExactFactor) -> String {
    if !si.is_finite() {
        return format!("{si:?}");
    }
    let negative = si.is_sign_negative();
    let target = si.abs();
    if target == 0.0 {
        return if negative {
            "-0.0".into()
        } else {
            "0.0".into()
        };
    }
    let hits = |d: &Decimal| d.to_f64_times(factor).to_bits() == target.to_bits();
    let p0 = target / factor.approx();
    if p0.is_finite() && p0 > 0.0 {
        for n in 1..=17usize {
            if let Some(d) = Decimal::parse(&format!("{:.*e}", n - 1, p0))
                && hits(&d)
            {
                return render(negative, &d);
            }
        }
        // The exact pre-image may need more digits than `p0` carries: search 18 and 19 digits.
        for n in 18..=19usize {
            if let Some(d) = search_digits(p0, n, target, factor) {
                return render(negative, &d);
            }
        }
    }
    // Unreachable for normal values; keep the nearest plain rendering.
    format!("{}{:?}", if negative { "-" } else { "" }, p0)
}

/// Binary search over `n`-significant-digit decimals near `p0` for one converting to `target`.
fn search_digits(p0: f64, n: usize, target: f64, factor: ExactFactor) -> Option<Decimal> {
    let text = format!("{:.*e}", n - 1, p0);
    let (mant, exp) = text.split_once('e')?;
    let m0: u128 = mant.replace('.', "").parse().ok()?;
    let exp10 = exp.parse::<i32>().ok()? - (n as i32 - 1);
    let value = |m: u128| {
        let d = Decimal::parse(&format!("{m}e{exp10}"))?;
        Some((d.to_f64_times(factor), d))
    };
    const WINDOW: u128 = 100_000;
    let (mut lo, mut hi) = (m0.saturating_sub(WINDOW), m0 + WINDOW);
    // Smallest m in [lo, hi] with value(m) >= target.
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if value(mid)?.0 >= target {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    let (v, d) = value(lo)?;
    (v.to_bits() == target.to_bits()).then_some(d)
}

/// Writes a decimal as a TOML/JSON float: plain notation for moderate exponents, else `d.ddde±x`.
fn render(negative: bool, d: &Decimal) -> String {
    let sign = if negative { "-" } else { "" };
    let digits = std::str::from_utf8(&d.digits).unwrap_or("0");
    let len = digits.len() as i32;
    let sci = len - 1 + d.exp10;
    if (-6..=15).contains(&sci) {
        if d.exp10 >= 0 {
            format!("{sign}{digits}{}.0", "0".repeat(d.exp10 as usize))
        } else if len > -d.exp10 {
            let split = (len + d.exp10) as usize;
            format!("{sign}{}.{}", &digits[..split], &digits[split..])
        } else {
            format!("{sign}0.{}{digits}", "0".repeat((-d.exp10 - len) as usize))
        }
    } else {
        let rest = if len > 1 { &digits[1..] } else { "0" };
        format!("{sign}{}.{rest}e{sci}", &digits[..1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimal_identity_matches_std_parse() {
        for s in [
            "0.1",
            "1e-7",
            "123.456",
            "9007199254740993",
            "2.5e-300",
            "-0.0",
            "17",
        ] {
            let expected: f64 = s.parse().unwrap_or(f64::NAN);
            assert_eq!(
                decimal_to_si(s, ExactFactor::ONE).map(f64::to_bits),
                Some(expected.to_bits()),
                "{s}"
            );
        }
    }

    #[test]
    fn ppm_is_exact_decimal_shift() {
        assert_eq!(decimal_to_si("20", ExactFactor::decimal(1, -6)), Some(2e-5));
        assert_eq!(
            decimal_to_si("-61.88", ExactFactor::decimal(1, -6)),
            Some(-61.88e-6)
        );
    }

    #[test]
    fn every_double_round_trips_where_plain_multiplication_cannot() {
        let factor = ExactFactor::binary(sins_nav::DEG_PER_H);
        let u = sins_nav::DEG_PER_H;
        let (mut naive_misses, mut long) = (0, 0);
        let mut x = 1.234_567e-8_f64;
        for _ in 0..20_000 {
            x = x.next_up();
            let text = format_exact(x, factor);
            assert_eq!(
                decimal_to_si(&text, factor).map(f64::to_bits),
                Some(x.to_bits()),
                "{x:e} -> {text}"
            );
            let digits = text.chars().filter(char::is_ascii_digit).count();
            long += usize::from(digits > 17);
            // The naive scheme: shortest decimal of x/u, read back as parse * u.
            let p: f64 = format!("{:e}", x / u).parse().unwrap_or(f64::NAN);
            naive_misses += usize::from((p * u).to_bits() != x.to_bits());
        }
        assert!(
            naive_misses > 0,
            "plain multiplication should miss some doubles"
        );
        assert!(long > 0, "some doubles need more than 17 digits in deg/h");
    }

    #[test]
    fn rejects_non_decimal() {
        for s in ["0x1f", "inf", "nan", "1.", ".5", "1e", "\"1\"", "", "-"] {
            assert!(Decimal::parse(s).is_none(), "{s}");
        }
    }
}
