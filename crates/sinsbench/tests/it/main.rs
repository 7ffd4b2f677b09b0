//! The integration tests of `sinsbench`, one test binary: each module was its own binary, and
//! every one linked the crate's whole dependency tree again (up to 150 MB each where polars and
//! rerun come along; 95 test binaries took gigabytes of CI disk).
#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is its failure message

mod calibrate;
mod campaign;
mod campaign_damaged;
mod cli;
mod closed_pipe;
mod common;
mod crash;
mod gate_baseline;
mod gate_files;
mod layering;
mod messages;
mod module_cycles;
mod noise_roundtrip;
mod output_sets;
mod outputs;
mod plausibility;
mod refuse;
mod replica_uq;
mod report;
mod shipped_study;
