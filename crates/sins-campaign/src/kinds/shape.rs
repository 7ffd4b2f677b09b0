//! The shape of each kind's outcome: what a shard's result file alone can tell (it parses, its
//! arrays have their fixed lengths). Needs only the outcome types, not the work that makes them,
//! so a reader of shard results (the fuzz target among them) builds without the report writers.

use sins_calstudy::McRunOutcome;
use sins_uq::sample::SampleOutcome;

/// Checks that `outcome` has the shape of an outcome of the campaign kind named `kind`; a kind's
/// `Work::check_outcome` checks it against its job. An unknown kind checks nothing (the
/// manifest holding it cannot be opened).
pub fn check_shape(kind: &str, outcome: &serde_json::Value) -> Result<(), String> {
    match kind {
        "blind" => parse::<sins_diag::report::Diagnosis>(outcome).map(drop),
        "calibration-mc" => calibration_mc(&parse(outcome)?),
        "replica-uq" => replica_uq(&parse(outcome)?),
        "reports" => parse::<sins_harness::summary::Summary>(outcome).map(drop),
        _ => Ok(()),
    }
}

/// An outcome as its kind's type, or what does not parse.
pub(crate) fn parse<T: serde::de::DeserializeOwned>(
    outcome: &serde_json::Value,
) -> Result<T, String> {
    T::deserialize(outcome).map_err(|e| format!("does not parse ({e})"))
}

/// An array's length against the one it must have.
pub(crate) fn check_len(name: &str, len: usize, want: usize, what: &str) -> Result<(), String> {
    if len == want {
        return Ok(());
    }
    Err(format!("{name} has {len} values where {what} has {want}"))
}

/// Coefficients of the 42-state filter (eq 8): the length of every per-seed estimate.
const COEFFICIENTS_42: usize = 33;
/// Coefficients of the 30-state filter (the first 21 of eq 8).
const COEFFICIENTS_30: usize = 21;
/// States of the 42-state filter (9 navigation states and the coefficients).
const STATES: usize = 42;

/// Every array of a seed's outcome has the length of a 42-state calibration's (Table 1's
/// assembly indexes them by state).
pub fn calibration_mc(o: &McRunOutcome) -> Result<(), String> {
    let what = "a 42-state calibration";
    check_len("estimate", o.outcome.estimate.len(), COEFFICIENTS_42, what)?;
    check_len("error", o.outcome.error.len(), COEFFICIENTS_42, what)?;
    check_len("sigma", o.outcome.sigma.len(), COEFFICIENTS_42, what)?;
    check_len("sigma_ratio", o.outcome.sigma_ratio.len(), STATES, what)?;
    check_len("initial_sigma_si", o.initial_sigma_si.len(), STATES, what)?;
    check_len("final_sigma_si", o.final_sigma_si.len(), STATES, what)?;
    check_len("estimate_si", o.estimate_si.len(), COEFFICIENTS_42, what)
}

/// The arrays of a sample whose lengths are fixed: each filter's coefficient errors, and at
/// least one navigation run.
pub fn replica_uq(o: &SampleOutcome) -> Result<(), String> {
    check_len(
        "error42",
        o.error42.len(),
        COEFFICIENTS_42,
        "a 42-state set",
    )?;
    check_len(
        "error30",
        o.error30.len(),
        COEFFICIENTS_30,
        "a 30-state set",
    )?;
    if o.max_horizontal_m.is_empty() {
        return Err("max_horizontal_m holds no navigation run".into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_checks_the_shape_of_its_outcomes() {
        for kind in crate::spec::KINDS {
            assert!(
                check_shape(kind, &serde_json::Value::Null).is_err(),
                "{kind}"
            );
        }
    }

    #[test]
    fn the_lengths_are_those_of_the_42_state_filter() {
        assert_eq!(sins_calstudy::units::PARAMS.len(), COEFFICIENTS_42);
    }
}
