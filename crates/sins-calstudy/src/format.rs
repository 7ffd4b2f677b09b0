//! Number formatting for the Markdown report.

/// Decimals that show two significant digits of `scale` (0..=9).
pub fn decimals_for(scale: f64) -> usize {
    if !(scale.is_finite() && scale > 0.0) {
        return 3;
    }
    (1.0 - scale.log10().floor()).clamp(0.0, 9.0) as usize
}

/// `v` with `d` decimals; "—" for NaN, "∞" for infinities.
pub fn fixed(v: f64, d: usize) -> String {
    if v.is_nan() {
        "—".into()
    } else if v.is_infinite() {
        if v > 0.0 {
            "∞".into()
        } else {
            "−∞".into()
        }
    } else {
        format!("{v:.d$}")
    }
}

/// `v` with `sig` significant digits (fixed notation between 1e-4 and 1e6, else scientific).
pub fn sig(v: f64, sig: usize) -> String {
    if !v.is_finite() || v == 0.0 {
        return fixed(v, 0);
    }
    let a = v.abs();
    if !(1e-4..1e6).contains(&a) {
        return format!("{v:.p$e}", p = sig.saturating_sub(1));
    }
    let mag = a.log10().floor() as i32;
    let d = (sig as i32 - 1 - mag).max(0) as usize;
    format!("{v:.d$}")
}

/// `v` rounded to 10 significant digits and printed shortest (undoes the SI ↔ paper-unit
/// round trip: 20.000000000000004 → "20").
pub fn clean(v: f64) -> String {
    if !v.is_finite() {
        return fixed(v, 0);
    }
    format!("{v:.9e}")
        .parse::<f64>()
        .map_or_else(|_| v.to_string(), |r| r.to_string())
}

/// "yes" / "no".
pub fn yes(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats() {
        assert_eq!(decimals_for(0.00016), 5);
        assert_eq!(decimals_for(3.2), 1);
        assert_eq!(decimals_for(250.0), 0);
        assert_eq!(fixed(1.23456, 2), "1.23");
        assert_eq!(sig(0.012345, 3), "0.0123");
        assert_eq!(sig(123.45, 2), "123");
        assert_eq!(sig(2.5e-7, 2), "2.5e-7");
        assert_eq!(fixed(f64::INFINITY, 1), "∞");
        assert_eq!(clean(20.000000000000004), "20");
        assert_eq!(clean(-61.879999999999995), "-61.88");
    }
}
