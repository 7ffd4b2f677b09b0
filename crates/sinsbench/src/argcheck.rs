//! Value parsers for command-line options that clap's built-in parsers let through: a thread
//! count of 0, and times that are negative, zero, NaN or infinite. clap puts the option's name
//! in front of the message (`invalid value '0' for '--threads <N>': ...`) and exits with 2.

/// A positive, finite number (e.g. a duration in seconds): refuses `0`, negatives, `nan` and
/// `inf`.
pub fn positive_f64(text: &str) -> Result<f64, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number"))?;
    if !v.is_finite() {
        return Err(format!("{v} is not a finite number"));
    }
    if v <= 0.0 {
        return Err(format!("{v} must be greater than 0"));
    }
    Ok(v)
}

/// Most worker threads any option accepts.
pub const MAX_THREADS: usize = 256;

/// A worker-thread count from 1 to [`MAX_THREADS`].
pub fn threads(text: &str) -> Result<usize, String> {
    let n: usize = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a whole number of threads"))?;
    match n {
        0 => Err("0 worker threads cannot do any work; give 1 or more".to_string()),
        n if n > MAX_THREADS => Err(format!(
            "{n} threads is more than the {MAX_THREADS} allowed"
        )),
        n => Ok(n),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positive_f64_refuses_what_is_not_a_positive_finite_number() {
        assert_eq!(positive_f64("1200"), Ok(1200.0));
        assert_eq!(positive_f64("0.5"), Ok(0.5));
        for bad in ["0", "-0", "-3", "nan", "NaN", "inf", "-inf", "x", ""] {
            assert!(positive_f64(bad).is_err(), "{bad} must be refused");
        }
    }

    #[test]
    fn threads_refuses_zero_and_absurd_counts() {
        assert_eq!(threads("1"), Ok(1));
        assert_eq!(threads("16"), Ok(16));
        for bad in ["0", "-1", "257", "two", ""] {
            assert!(threads(bad).is_err(), "{bad} must be refused");
        }
    }
}
