//! Value parsers for command-line options that clap's built-in parsers let through: a thread
//! count of 0, and times that are negative, zero, NaN or infinite. clap puts the option's name
//! in front of the message (`invalid value '0' for '--threads <N>': ...`) and exits with 2.
//! Also the `--dataset [NAME=]PATH` lists of `diagnose` and `noise`.

use anyhow::{Context, Result, bail};
use std::path::PathBuf;

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

/// `--dataset [NAME=]PATH` arguments as `(name, path)`; two runs with one name are refused.
pub fn datasets(args: &[String]) -> Result<Vec<(String, PathBuf)>> {
    let mut datasets = Vec::new();
    for d in args {
        let (name, path) = match d.split_once('=') {
            Some((n, p)) if !n.is_empty() => (n.to_string(), PathBuf::from(p)),
            _ => {
                let p = PathBuf::from(d);
                let n = p
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .with_context(|| format!("--dataset {d}: not a file path"))?;
                (n, p)
            }
        };
        if datasets.iter().any(|(n, _): &(String, PathBuf)| n == &name) {
            bail!("--dataset: two runs are named '{name}'; name them with NAME=PATH");
        }
        datasets.push((name, path));
    }
    Ok(datasets)
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
