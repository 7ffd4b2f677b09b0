//! The `replica-uq` study shipped in `experiments/replica/study/`, whose intervals the default
//! report prints, is what this build computes: two of its samples are run again and must be
//! bit-identical to the stored ones, and its summary must be the summary of its stored samples.
//! A change to the physics (a truth coefficient, the simulator, a filter, the replay) therefore
//! cannot leave a stale study in the headline unnoticed. Regenerate it with
//! `sinsbench replica-uq --out <new dir>` and replace the directory (README, "The replica as a
//! prediction").

use crate::common;

use common::experiments;
use sins_uq::sample::{Job, all_jobs, run_jobs, study_name};

#[test]
fn the_shipped_study_is_what_this_build_computes() {
    let e = experiments();
    let study = sins_report::load_uq_study(&e.join("replica/assumptions.toml")).unwrap();
    let dir = e.join("replica/study");
    let jobs = all_jobs(&study.set);
    // Every stored sample is there, and the summary is theirs.
    let stored: Vec<_> = jobs
        .iter()
        .map(|&j| {
            let name = study_name(&study.set, j);
            let path = sins_report::sample_path(&dir, &name, j.index());
            sins_report::read_sample(&path)
                .unwrap()
                .unwrap_or_else(|| panic!("{}: missing from the shipped study", path.display()))
        })
        .collect();
    let summary = sins_uq::summary::summarize(&study.set, &stored, &study.paper).unwrap();
    let shipped: sins_uq::summary::UqSummary =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        serde_json::to_value(&summary.cells).unwrap(),
        serde_json::to_value(&shipped.cells).unwrap(),
        "summary.json is not the summary of the stored samples"
    );
    assert_eq!(shipped.samples, study.set.samples);
    // The point replica (30-state set on the ramp) and the first sample of a candidate with a
    // stable-temperature 30-state calibration and an extra effect, run again.
    let candidate = jobs
        .iter()
        .position(|&j| study_name(&study.set, j).contains('+'))
        .expect("a candidate with an effect");
    let picks = [0, candidate];
    let again: Vec<Job> = picks.iter().map(|&k| jobs[k]).collect();
    let results = run_jobs(&study.base, &study.set, &again, 2, &|_| {}, &|_, _| {});
    for (&k, r) in picks.iter().zip(results) {
        let now = r.unwrap();
        let then = &stored[k];
        assert_eq!(
            serde_json::to_string(&now).unwrap(),
            serde_json::to_string(then).unwrap(),
            "sample {}-{:05} differs from the shipped study: the physics changed; regenerate \
             experiments/replica/study (sinsbench replica-uq --out <new dir>)",
            then.study,
            then.index
        );
    }
}
