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

/// `--dataset [NAME=]PATH` arguments as `(name, path)`, checked before any work: every name
/// (given, or the file stem) must be a usable run name ([`sins_config::RUN_NAME_RULE`]: it
/// becomes part of file names), and no name may be given twice.
pub fn datasets(args: &[String]) -> Result<Vec<(String, PathBuf)>> {
    let mut datasets: Vec<(String, PathBuf)> = Vec::new();
    let mut given_by_name = Vec::new();
    for d in args {
        let (name, path, named) = match d.split_once('=') {
            Some((n, p)) if !n.is_empty() => (n.to_string(), PathBuf::from(p), true),
            _ => {
                let p = PathBuf::from(d);
                let n = p
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .with_context(|| {
                        format!("--dataset {d}: not a file path; give --dataset NAME=PATH")
                    })?;
                (n, p, false)
            }
        };
        if let Err(e) = sins_config::run_name(&name) {
            if named {
                bail!("--dataset {}: {e}; rename the run", d.escape_debug());
            }
            bail!(
                "--dataset {}: the file stem is taken as the run name, and {e}; name the run with --dataset NAME={}",
                d.escape_debug(),
                d.escape_debug()
            );
        }
        if let Some(k) = datasets.iter().position(|(n, _)| n == &name) {
            let (first, first_named) = match (datasets.get(k), given_by_name.get(k)) {
                (Some((_, p)), Some(f)) => (p.display().to_string(), *f),
                _ => (String::new(), false),
            };
            if named && first_named {
                bail!(
                    "--dataset: the run name '{name}' is given twice ({first} and {}); give each run its own name",
                    path.display()
                );
            }
            bail!(
                "--dataset: two runs would be named '{name}' ({first} and {}; a run without NAME= is named after its file stem); give each its own name with --dataset NAME=PATH",
                path.display()
            );
        }
        datasets.push((name, path));
        given_by_name.push(named);
    }
    Ok(datasets)
}

/// Opens the dataset of run `name` at `path` (its header and metadata; a CSV is read through),
/// the error naming the run and the file.
pub fn open_run(name: &str, path: &std::path::Path) -> Result<sins_data::DatasetInfo> {
    let reader = sins_data::DatasetReader::open(path)
        .with_context(|| format!("run '{name}' ({})", path.display()))?;
    Ok(reader.info().clone())
}

/// Refuses run `name` (the dataset at `path`) when it has no accelerometer temperature columns
/// and the parameter set read from `params_path` is a 42-state set (its temperature terms need
/// them): `noise` and `diagnose` say it in the same words, naming the run, both files and what
/// to do (`also` adds a remedy of the command's own).
pub fn require_temperatures(
    name: &str,
    path: &std::path::Path,
    info: &sins_data::DatasetInfo,
    params: &sins_imu::ImuErrorParams,
    params_path: &std::path::Path,
    also: &str,
) -> Result<()> {
    if info.has_temperature || params.model != sins_imu::ParamModel::States42 {
        return Ok(());
    }
    bail!(
        "run '{name}' ({}): the dataset has no accelerometer temperature columns (temp_ax_degc, \
         temp_ay_degc, temp_az_degc), but the parameter set {} is a 42-state set with temperature \
         coefficients; give a 30-state set with --params (sinsbench calibrate --states 30){also}, \
         or a recording with those columns",
        path.display(),
        params_path.display()
    )
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
    fn dataset_names_are_checked_and_a_name_given_twice_is_named() {
        let args = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let ok = datasets(&args(&["a=x.csv", "dir/nav1.parquet"])).expect("valid");
        assert_eq!(ok[1].0, "nav1");
        let e = datasets(&args(&["a=x.csv", "a=y.csv"]))
            .expect_err("twice")
            .to_string();
        assert!(
            e.contains("run name 'a' is given twice") && e.contains("x.csv") && e.contains("y.csv"),
            "{e}"
        );
        let e = datasets(&args(&["d1/nav.csv", "d2/nav.csv"]))
            .expect_err("same stem")
            .to_string();
        assert!(e.contains("NAME=PATH") && e.contains("file stem"), "{e}");
        for bad in ["../../x=a.csv", "a\nb=a.csv", ".=a.csv", "my run.csv"] {
            let e = datasets(&args(&[bad])).expect_err(bad).to_string();
            assert!(
                e.contains(sins_config::RUN_NAME_RULE) && !e.contains('\n'),
                "{e}"
            );
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
