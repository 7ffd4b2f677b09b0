//! How the long steps report progress (the CLI draws bars; tests ignore it).

/// Progress of the long steps (the CLI draws bars; tests ignore it).
pub trait Progress {
    /// A step with `total` units of work starts.
    fn begin(&mut self, label: &str, total: u64);
    /// `n` more units are done.
    fn advance(&mut self, n: u64);
    /// The step ended.
    fn end(&mut self);
}
