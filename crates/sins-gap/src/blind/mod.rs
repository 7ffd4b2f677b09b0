//! The blind validation suite (`sinsbench blind`).
//!
//! 1. [`plan::draw_cases`] draws the cases from a suite seed: null cases (no hidden effect),
//!    cases with one in-catalogue effect (kind, component, magnitude, seed at random) and cases
//!    with an effect outside the catalogue.
//! 2. [`seal::seal`] writes each case's answer to its own manifest under `sealed/` and fixes
//!    their SHA-256 hashes in `sealed/index.json` before anything is diagnosed.
//! 3. [`suite::run_suite`] then, case by case, simulates the "real" IMU (the replica's truth
//!    plus the hidden effect): its calibration run, calibrated with the 42-state filter as a
//!    team would, and its navigation runs written as datasets; the diagnosis receives only the
//!    dataset paths, the calibrated parameter set and the noise model.
//! 4. Only then are the manifests opened, their hashes checked against the index, and the
//!    diagnoses graded ([`grade::grade`]): top-1 identification, false alarms, out-of-catalogue
//!    reports, fitted magnitudes against the truth, gap shrinkage on withheld runs, and the
//!    confusion table; for the time-local cases (steps, ramps, transients drawn after the
//!    others, [`time_local`]) whether the event was reported on its channel with its onset;
//!    the widened draw (ramps to a plateau, pulses, decaying oscillations; in one run, in every
//!    navigation run, or in the calibration run only) and the cases whose runs have different
//!    chamber histories; and the confident misattributions (a verdict that names only wrong
//!    causes).

pub mod grade;
pub mod plan;
pub mod seal;
pub mod suite;
pub mod time_local;
