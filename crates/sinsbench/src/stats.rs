//! Wall time and peak resident memory of this process (Linux `/proc/self/status`).

/// Peak resident set size of this process (MB), if the platform reports it.
pub fn peak_rss_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// Print `stats: wall_s=… peak_rss_mb=…` on stderr (parsed by `sinsbench bench`); a closed
/// stderr is ignored.
pub fn print(wall: std::time::Duration) {
    let rss = peak_rss_mb().map_or("unknown".to_string(), |m| format!("{m:.1}"));
    crate::out::note!("stats: wall_s={:.3} peak_rss_mb={rss}", wall.as_secs_f64());
}
