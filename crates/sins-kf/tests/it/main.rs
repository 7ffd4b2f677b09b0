//! The integration tests of `sins-kf`, one test binary: each module was its own binary, and
//! every one linked the crate's whole dependency tree again (up to 150 MB each where polars and
//! rerun come along; 95 test binaries took gigabytes of CI disk).
#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is its failure message

mod batch;
mod common;
mod leading;
mod paper_noise_free;
mod paper_noisy;
mod refuse;
mod thirty_state;
