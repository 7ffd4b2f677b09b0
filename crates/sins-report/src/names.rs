//! The names of the files a report directory holds.

/// `<run>_errors.parquet`.
pub(crate) fn track_file(run: &str) -> String {
    format!("{run}_errors.parquet")
}

/// `<run>_segments.parquet`.
pub(crate) fn segments_file(run: &str) -> String {
    format!("{run}_segments.parquet")
}

/// `<run>.rrd`.
pub(crate) fn rrd_file(run: &str) -> String {
    format!("{run}.rrd")
}

/// `<run>_<what>.png`.
pub(crate) fn plot_file(run: &str, what: &str) -> String {
    format!("{run}_{what}.png")
}
