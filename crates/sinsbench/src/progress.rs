//! Progress bars (hidden with `--quiet` or when stderr is not a terminal).

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar over `len` items with a message.
pub fn bar(len: u64, message: &str, quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let pb = ProgressBar::new(len);
    let style = ProgressStyle::with_template(
        "{msg:>24} [{bar:40}] {percent:>3}% {elapsed_precise} eta {eta}",
    )
    .unwrap_or_else(|_| ProgressStyle::default_bar())
    .progress_chars("=> ");
    pb.set_style(style);
    pb.set_message(message.to_string());
    pb
}

/// Progress bars for the report's steps (one bar per step).
pub struct Bars {
    quiet: bool,
    current: Option<ProgressBar>,
}

impl Bars {
    /// Bars, hidden when `quiet`.
    pub fn new(quiet: bool) -> Self {
        Self {
            quiet,
            current: None,
        }
    }
}

impl sins_report::Progress for Bars {
    fn begin(&mut self, label: &str, total: u64) {
        if let Some(b) = self.current.take() {
            b.finish_and_clear();
        }
        self.current = Some(bar(total, label, self.quiet));
    }
    fn advance(&mut self, n: u64) {
        if let Some(b) = &self.current {
            b.inc(n);
        }
    }
    fn end(&mut self) {
        if let Some(b) = self.current.take() {
            b.finish_and_clear();
        }
    }
}
