//! Crash consistency: `calibrate`, `report`, `simulate` (three runs) and `campaign reduce` killed
//! at pseudo-random moments (a fixed seed; SIGINT, SIGTERM and SIGKILL in turn), at least 20
//! times each. The run that is killed always writes a *different* set from the one in place
//! (another seed or another input), so that every file can be told apart: after every kill and
//! the cleanup the next run does ([`sins_files::sweep_stale`], what every command runs in
//! its output directories), each file of the set must be the previous one (same inode, same
//! bytes) or the new one (a new inode holding what a complete run of the killed command writes;
//! `.rrd` recordings carry fresh ids and must decode completely instead), and all files of the
//! set from the same generation: a mixed set is counted and fails the test. No temporary file or
//! staging directory may remain (the lock file, `.sinsbench.lock`, is not a temporary: the kernel
//! releases its lock with the process); a SIGINT or SIGTERM must leave nothing behind even before
//! that cleanup. A SIGKILL between two renames of a commit is completed by the cleanup (counted
//! as "rolled forward"). The counts are printed.
//!
//! The full-disk variant (root only: it mounts a 20 MB tmpfs; printed as SKIPPED otherwise)
//! fills the disk under `calibrate`, `simulate` and `campaign reduce`: exit code 2, the previous
//! set byte for byte, nothing left behind.

use crate::common;
use common::{
    Tmpfs, exe, leftovers, s, short_calibration_experiment, short_navigation_experiment,
    simulate_into,
};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Every file under `dir` (relative name, bytes); names starting with '.' other than the
/// output marker and the lock files count as leftovers and are returned separately.
fn scan(
    dir: &Path,
    prefix: &str,
    files: &mut BTreeMap<String, Vec<u8>>,
    leftovers: &mut Vec<String>,
) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().into_owned();
        let rel = format!("{prefix}{name}");
        if sins_files::lock::is_lock_file(&name) {
            // Not part of the set and not a temporary: a lock file left by a SIGKILLed run
            // blocks nothing.
            continue;
        }
        if name.starts_with('.') && name != ".sinsbench-output" {
            leftovers.push(rel);
            continue;
        }
        if e.file_type().unwrap().is_dir() {
            scan(&e.path(), &format!("{rel}/"), files, leftovers);
        } else {
            files.insert(rel, std::fs::read(e.path()).unwrap());
        }
    }
}

/// SplitMix64: the kill schedule is the same on every run of the test.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A file of an output set: inode and bytes.
type Snapshot = BTreeMap<String, (u64, Vec<u8>)>;

#[cfg(unix)]
fn inode(p: &Path) -> u64 {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(p).map(|m| m.ino()).unwrap_or(0)
}

/// The files of the set under `dir` (those `select` keeps) with their inodes.
fn snapshot(dir: &Path, select: &dyn Fn(&str) -> bool) -> Snapshot {
    let (mut files, mut left) = (BTreeMap::new(), Vec::new());
    scan(dir, "", &mut files, &mut left);
    files
        .into_iter()
        .filter(|(k, _)| select(k))
        .map(|(k, v)| (k.clone(), (inode(&dir.join(&k)), v)))
        .collect()
}

/// The leftovers under `dir` (temporaries and staging directories).
fn leftovers_under(dir: &Path) -> Vec<String> {
    let (mut files, mut left) = (BTreeMap::new(), Vec::new());
    scan(dir, "", &mut files, &mut left);
    left
}

/// The part of an output file that must not change between runs: everything but the wall times
/// at the end of `report.md` (its "Run time" section).
fn stable<'a>(name: &str, bytes: &'a [u8]) -> &'a [u8] {
    let marker = b"\n## Run time\n";
    if name.ends_with("report.md")
        && let Some(i) = bytes.windows(marker.len()).position(|w| w == marker)
    {
        return &bytes[..i];
    }
    bytes
}

/// What a kill left.
#[derive(Debug, PartialEq)]
enum Verdict {
    /// Every file of the set is the previous one.
    Old,
    /// Every file is the new one, complete.
    New,
    /// Some files old, some new.
    Mixed(String),
    /// A file missing, extra, overwritten in place or neither old nor new.
    Damaged(String),
}

/// Judges the set `now` against the previous set `good` and `fresh`, the files a complete run
/// of the killed command writes (`.rrd` excepted: they must decode).
fn judge(
    good: &Snapshot,
    now: &Snapshot,
    fresh: &BTreeMap<String, Vec<u8>>,
    root: &Path,
) -> Verdict {
    if now.keys().ne(good.keys()) {
        return Verdict::Damaged(format!(
            "files differ: {:?} vs {:?}",
            now.keys().collect::<Vec<_>>(),
            good.keys().collect::<Vec<_>>()
        ));
    }
    let (mut old, mut new) = (Vec::new(), Vec::new());
    for (name, (ino, bytes)) in now {
        let (good_ino, good_bytes) = &good[name];
        if ino == good_ino {
            if bytes != good_bytes {
                return Verdict::Damaged(format!("{name} overwritten in place"));
            }
            old.push(name.as_str());
        } else if name.ends_with(".rrd") {
            if let Err(e) = sins_viz::verify_recording(&root.join(name)) {
                return Verdict::Damaged(format!("{name}: {e}"));
            }
            new.push(name.as_str());
        } else if fresh.get(name).map(|f| stable(name, f)) == Some(stable(name, bytes)) {
            new.push(name.as_str());
        } else {
            return Verdict::Damaged(format!("{name} is neither the previous nor the new one"));
        }
    }
    match (old.is_empty(), new.is_empty()) {
        (_, true) => Verdict::Old,
        (true, false) => Verdict::New,
        (false, false) => Verdict::Mixed(format!("old {old:?}, new {new:?}")),
    }
}

#[derive(Default, Debug)]
struct Counts {
    kills: usize,
    sigkill: usize,
    sigint: usize,
    sigterm: usize,
    finished_before_kill: usize,
    replaced_by_new: usize,
    rolled_forward: usize,
    mixed: usize,
    damaged: usize,
    leftovers_after_signal: usize,
    leftovers_after_cleanup: usize,
}

/// One command under the harness: two variants that write different sets into the same place.
struct Target<'a> {
    label: &'a str,
    /// The arguments of variant 0 and variant 1.
    variants: [Vec<String>; 2],
    /// Makes the inputs of a variant current (for a campaign: its manifest and shards).
    prepare: &'a dyn Fn(usize),
    /// The directory whose files are the output set.
    outputs: &'a Path,
    /// Which names under `outputs` belong to the set.
    select: &'a dyn Fn(&str) -> bool,
    /// Where the command's temporaries go (swept by the next run).
    sweep_dir: &'a Path,
}

/// Runs `args` to the end and returns its wall time.
fn timed_run(args: &[String]) -> f64 {
    let t = Instant::now();
    let o = exe().args(args).arg("--quiet").output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    t.elapsed().as_secs_f64()
}

/// Writes each variant's set once (its reference and wall time), leaving variant 0 in place,
/// then runs the other variant at least 20 times, killing each run at a moment drawn uniformly
/// in `[0, 1.1 * full)` with SIGINT, SIGTERM and SIGKILL in turn, and judges every file of the set
/// after each kill and the next run's cleanup.
fn kill_loop(t: &Target<'_>, rng: &mut Rng) -> Counts {
    let mut reference: [BTreeMap<String, Vec<u8>>; 2] = Default::default();
    let mut full_s: f64 = 0.0;
    for v in [1, 0] {
        (t.prepare)(v);
        full_s = full_s.max(timed_run(&t.variants[v]));
        reference[v] = snapshot(t.outputs, t.select)
            .into_iter()
            .map(|(k, (_, b))| (k, b))
            .collect();
    }
    assert_ne!(
        reference[0], reference[1],
        "{}: the variants must differ",
        t.label
    );
    let mut good = snapshot(t.outputs, t.select);
    let mut in_place = 0;
    let mut c = Counts::default();
    assert!(
        leftovers_under(t.sweep_dir).is_empty() && !good.is_empty(),
        "{}: a clean good output first",
        t.label
    );
    let mut attempts = 0;
    while c.kills < 20 && attempts < 80 {
        attempts += 1;
        let v = 1 - in_place;
        (t.prepare)(v);
        let at = Duration::from_secs_f64(rng.unit() * 1.1 * full_s);
        let sig = ["INT", "TERM", "KILL"][c.kills % 3];
        let mut child = exe()
            .args(&t.variants[v])
            .arg("--quiet")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        // Wait for the moment, or for the run to end first: its wall time then becomes the
        // scale of the next moments (the machine's load changes while the test runs).
        let t0 = Instant::now();
        let mut ended = false;
        while t0.elapsed() < at {
            if child.try_wait().unwrap().is_some() {
                ended = true;
                full_s = t0.elapsed().as_secs_f64();
                break;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        let killed = if !ended && child.try_wait().unwrap().is_none() {
            Command::new("kill")
                .args(["-s", sig, &child.id().to_string()])
                .status()
                .unwrap();
            true
        } else {
            false
        };
        child.wait().unwrap();
        if killed {
            c.kills += 1;
            match sig {
                "INT" => c.sigint += 1,
                "TERM" => c.sigterm += 1,
                _ => c.sigkill += 1,
            }
            if sig != "KILL" {
                let l = leftovers_under(t.sweep_dir);
                if !l.is_empty() {
                    eprintln!("{}: SIG{sig} at {at:?} left {l:?}", t.label);
                    c.leftovers_after_signal += 1;
                }
            }
        } else {
            c.finished_before_kill += 1;
        }
        // The next run's cleanup.
        let notes = sins_files::sweep_stale(t.sweep_dir);
        if notes
            .iter()
            .any(|n| n.contains("completed the replacement"))
        {
            c.rolled_forward += 1;
        }
        let l = leftovers_under(t.sweep_dir);
        if !l.is_empty() {
            eprintln!("{}: kill at {at:?} left {l:?} after the cleanup", t.label);
            c.leftovers_after_cleanup += 1;
        }
        let now = snapshot(t.outputs, t.select);
        match judge(&good, &now, &reference[v], t.outputs) {
            Verdict::New => {
                c.replaced_by_new += 1;
                good = now;
                in_place = v;
            }
            Verdict::Old if !killed => {
                eprintln!("{}: a run that finished left the previous set", t.label);
                c.damaged += 1;
            }
            Verdict::Old => {}
            Verdict::Mixed(e) => {
                eprintln!("{}: SIG{sig} at {at:?} left a mixed set: {e}", t.label);
                c.mixed += 1;
                good = now;
            }
            Verdict::Damaged(e) => {
                eprintln!("{}: SIG{sig} at {at:?} damaged the output: {e}", t.label);
                c.damaged += 1;
                good = now;
            }
        }
    }
    eprintln!(
        "crash consistency, {}: {} kills ({} SIGINT, {} SIGTERM, {} SIGKILL; {} runs ended before \
         their kill), mixed sets {}, damaged outputs {}, leftovers after SIGINT/SIGTERM {}, \
         leftovers after the next run's cleanup {}; the new set in place after {} runs ({} of them \
         completed by the next run's cleanup after a SIGKILL during the commit)",
        t.label,
        c.kills,
        c.sigint,
        c.sigterm,
        c.sigkill,
        c.finished_before_kill,
        c.mixed,
        c.damaged,
        c.leftovers_after_signal,
        c.leftovers_after_cleanup,
        c.replaced_by_new,
        c.rolled_forward
    );
    c
}

fn strings(v: &[&str]) -> Vec<String> {
    v.iter().map(|x| (*x).to_string()).collect()
}

fn check(label: &str, c: &Counts) {
    assert!(c.kills >= 20, "{label}: {c:?}");
    assert!(
        c.sigkill >= 5 && c.sigint >= 5 && c.sigterm >= 5,
        "{label}: every signal: {c:?}"
    );
    assert_eq!(c.mixed, 0, "{label}: mixed sets: {c:?}");
    assert_eq!(c.damaged, 0, "{label}: {c:?}");
    assert_eq!(c.leftovers_after_signal, 0, "{label}: {c:?}");
    assert_eq!(c.leftovers_after_cleanup, 0, "{label}: {c:?}");
}

fn nothing(_: usize) {}
fn everything(_: &str) -> bool {
    true
}

#[test]
fn killed_report_and_calibrate_leave_the_previous_output_intact() {
    let dir = tempfile::tempdir().expect("tempdir");
    let exp = short_calibration_experiment(dir.path());
    let data = [dir.path().join("data"), dir.path().join("data2")];
    simulate_into(&exp, &data[0]);
    let o = common::run(&["simulate", &s(&exp), "--out", &s(&data[1]), "--seed", "77"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut rng = Rng(20_240_514);

    // calibrate: parameter file, history and recording in cal/, from two datasets in turn.
    let cal_dir = dir.path().join("cal");
    std::fs::create_dir_all(&cal_dir).unwrap();
    let cal_args = |d: &Path| {
        strings(&[
            "calibrate",
            "--dataset",
            &s(&d.join("cal1.parquet")),
            "--states",
            "30",
            "--out",
            &s(&cal_dir.join("cal.toml")),
        ])
    };
    let cal = kill_loop(
        &Target {
            label: "calibrate",
            variants: [cal_args(&data[0]), cal_args(&data[1])],
            prepare: &nothing,
            outputs: &cal_dir,
            select: &everything,
            sweep_dir: &cal_dir,
        },
        &mut rng,
    );

    // report: the user's own parameter files on one dataset or the other.
    let imu = common::experiments().join("imu");
    let config = |k: usize| {
        let p = dir.path().join(format!("own{k}.toml"));
        std::fs::write(
            &p,
            format!(
                "schema = 1\nname = \"own\"\n\
                 [[parameter_set]]\nkey = \"none\"\nfile = \"{}\"\n\
                 [[parameter_set]]\nkey = \"truth\"\nfile = \"{}\"\n\
                 [navigation]\ndataset = [{{ name = \"cal\", path = \"{}\" }}]\n",
                imu.join("ideal.toml").display(),
                imu.join("paper_table1.toml").display(),
                data[k].join("cal1.parquet").display()
            ),
        )
        .unwrap();
        p
    };
    let reports = dir.path().join("reports");
    let rep_args =
        |c: &Path| strings(&["report", "--config", &s(c), "--reports-dir", &s(&reports)]);
    let rep = kill_loop(
        &Target {
            label: "report",
            variants: [rep_args(&config(0)), rep_args(&config(1))],
            prepare: &nothing,
            outputs: &reports.join("own"),
            select: &everything,
            sweep_dir: &reports,
        },
        &mut rng,
    );

    check("calibrate", &cal);
    check("report", &rep);
}

/// `simulate` of a three-run experiment (seed 5 against the experiment's own seeds) and
/// `campaign reduce` (two campaigns of different seeds whose shards take turns in the directory).
#[test]
fn killed_simulate_and_campaign_reduce_leave_one_generation() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut rng = Rng(30_030_030);

    let exp = short_navigation_experiment(dir.path(), "nav.toml", 1200.0, 300.0, 120.0);
    let out = dir.path().join("D");
    let sim_args = |seed: Option<&str>| {
        let mut a = strings(&["simulate", &s(&exp), "--out", &s(&out)]);
        if let Some(seed) = seed {
            a.extend(strings(&["--seed", seed]));
        }
        a
    };
    let sim = kill_loop(
        &Target {
            label: "simulate",
            variants: [sim_args(None), sim_args(Some("5"))],
            prepare: &nothing,
            outputs: &out,
            select: &everything,
            sweep_dir: &out,
        },
        &mut rng,
    );

    // Two planned and run campaigns; their inputs take turns in one directory.
    let planned: Vec<std::path::PathBuf> = (0..2)
        .map(|k| {
            let cfg = dir.path().join(format!("c{k}.toml"));
            std::fs::write(
                &cfg,
                format!(
                    "schema = 1\nname = \"cli\"\nkind = \"calibration-mc\"\nseed = {}\n\
                     jobs_per_shard = 2\n[calibration_mc]\nseeds = 3\nexperiment = \"{}\"\n\
                     max_duration_s = 1500.0\n",
                    3 + k,
                    common::experiments()
                        .join("paper_calibration.toml")
                        .display()
                ),
            )
            .unwrap();
            let c = dir.path().join(format!("C{k}"));
            let o = common::run(&["campaign", "local", &s(&cfg), "--out", &s(&c)]);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            c
        })
        .collect();
    let camp = dir.path().join("camp");
    let prepare = |k: usize| {
        std::fs::create_dir_all(camp.join("shards")).unwrap();
        for f in ["manifest.json", "campaign.toml"] {
            std::fs::copy(planned[k].join(f), camp.join(f)).unwrap();
        }
        for e in std::fs::read_dir(planned[k].join("shards")).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), camp.join("shards").join(e.file_name())).unwrap();
        }
    };
    let outputs = |n: &str| ["summary.json", "report.md", "timing.json"].contains(&n);
    let reduce = strings(&["campaign", "reduce", &s(&camp)]);
    let red = kill_loop(
        &Target {
            label: "campaign reduce",
            variants: [reduce.clone(), reduce],
            prepare: &prepare,
            outputs: &camp,
            select: &outputs,
            sweep_dir: &camp,
        },
        &mut rng,
    );

    check("simulate", &sim);
    check("campaign reduce", &red);
}

/// What a command left on the full disk.
fn full_disk_outcome(
    label: &str,
    o: &std::process::Output,
    dir: &Path,
    before: &BTreeMap<String, Vec<u8>>,
) -> Result<bool, String> {
    let err = String::from_utf8_lossy(&o.stderr);
    let now = common::visible_files(dir);
    let left = leftovers(dir);
    if !left.is_empty() {
        return Err(format!("{label}: left {left:?}"));
    }
    match o.status.code() {
        Some(0) => Ok(false),
        Some(2) => {
            if &now != before {
                let changed: Vec<_> = now
                    .iter()
                    .filter(|(k, v)| before.get(*k) != Some(*v))
                    .map(|(k, _)| k.clone())
                    .chain(before.keys().filter(|k| !now.contains_key(*k)).cloned())
                    .collect();
                return Err(format!(
                    "{label}: exit 2 but the set changed: {changed:?}; {err}"
                ));
            }
            if !(err.contains("No space left on device")
                || err.contains("are free on the file system"))
            {
                return Err(format!("{label}: exit 2 for another reason: {err}"));
            }
            Ok(true)
        }
        c => Err(format!("{label}: exit {c:?}: {err}")),
    }
}

/// The full-disk variant: `calibrate`, `simulate` and `campaign reduce` on a 20 MB tmpfs that
/// fills up while they write. Each exits 2, naming the full disk, with the previous set byte
/// for byte (none for the first reduce) and nothing left behind. Root only (it mounts the tmpfs,
/// unmounted at the end even on failure).
#[test]
fn a_full_disk_leaves_the_previous_set_unchanged() {
    let fs = match Tmpfs::mount("20m") {
        Ok(fs) => fs,
        Err(why) => {
            eprintln!("SKIPPED a_full_disk_leaves_the_previous_set_unchanged: {why}");
            return;
        }
    };
    let dir = tempfile::tempdir().expect("tempdir");
    let filler = fs.path.join("filler");
    let mut failures = Vec::new();

    // calibrate: the previous set from one dataset, the new run on another; 64 kB free is room
    // for the parameter file, not for the history.
    let exp = short_calibration_experiment(dir.path());
    let data = [dir.path().join("data"), dir.path().join("data2")];
    simulate_into(&exp, &data[0]);
    let o = common::run(&["simulate", &s(&exp), "--out", &s(&data[1]), "--seed", "77"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let cal = fs.path.join("cal");
    std::fs::create_dir(&cal).unwrap();
    let calibrate = |d: &Path| {
        common::run(&[
            "calibrate",
            "--dataset",
            &s(&d.join("cal1.parquet")),
            "--states",
            "30",
            "--out",
            &s(&cal.join("p.toml")),
        ])
    };
    let o = calibrate(&data[0]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let before = common::visible_files(&cal);
    fs.fill(&filler, 64 * 1024);
    let o = calibrate(&data[1]);
    match full_disk_outcome("calibrate", &o, &cal, &before) {
        Ok(true) => eprintln!("full disk, calibrate: exit 2, previous set unchanged, nothing left"),
        Ok(false) => failures.push("calibrate: succeeded on a full disk".to_string()),
        Err(e) => failures.push(e),
    }
    std::fs::remove_file(&filler).unwrap();
    std::fs::remove_dir_all(&cal).unwrap();

    // simulate: three runs of about 2 MB; the disk fills once the first run is done.
    let exp = short_navigation_experiment(dir.path(), "tiny.toml", 100.0, 30.0, 10.0);
    let out = fs.path.join("D");
    simulate_into(&exp, &out);
    let before = common::visible_files(&out);
    assert_eq!(before.len(), 3);
    let mut enospc = 0;
    for trial in 0..4 {
        let nav1 = inode(&out.join("nav1.parquet"));
        let child = exe()
            .args([
                "simulate",
                &s(&exp),
                "--out",
                &s(&out),
                "--seed",
                &format!("{}", 50 + trial),
            ])
            .arg("--quiet")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let t0 = Instant::now();
        let begun = || {
            inode(&out.join("nav1.parquet")) != nav1
                || std::fs::read_dir(&out).unwrap().flatten().any(|e| {
                    e.file_type().is_ok_and(|t| t.is_dir())
                        && std::fs::read_dir(e.path()).is_ok_and(|r| {
                            r.flatten()
                                .any(|f| f.file_name().to_string_lossy().contains("nav2"))
                        })
                })
        };
        while !begun() && t0.elapsed() < Duration::from_secs(30) {
            std::thread::sleep(Duration::from_micros(200));
        }
        fs.fill(&filler, 0);
        let o = child.wait_with_output().unwrap();
        std::fs::remove_file(&filler).unwrap();
        match full_disk_outcome("simulate", &o, &out, &before) {
            Ok(true) => enospc += 1,
            Ok(false) => eprintln!("simulate trial {trial}: finished before the disk was full"),
            Err(e) => {
                failures.push(format!("trial {trial}: {e}"));
                break;
            }
        }
    }
    eprintln!(
        "full disk, simulate: {enospc} of 4 runs stopped by the full disk with the previous set unchanged"
    );
    if enospc == 0 && failures.is_empty() {
        failures.push("simulate: no run was stopped by the full disk".into());
    }
    std::fs::remove_dir_all(&out).unwrap();

    // campaign reduce: a planned, run campaign copied onto the tmpfs without a summary; 48 kB
    // free is room for summary.json, not for report.md as well.
    let cfg = dir.path().join("c.toml");
    std::fs::write(
        &cfg,
        format!(
            "schema = 1\nname = \"cli\"\nkind = \"calibration-mc\"\nseed = 3\njobs_per_shard = 2\n\
             [calibration_mc]\nseeds = 3\nexperiment = \"{}\"\nmax_duration_s = 1500.0\n",
            common::experiments()
                .join("paper_calibration.toml")
                .display()
        ),
    )
    .unwrap();
    let planned = dir.path().join("C");
    let o = common::run(&["campaign", "local", &s(&cfg), "--out", &s(&planned)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let camp = fs.path.join("camp");
    std::fs::create_dir_all(camp.join("shards")).unwrap();
    for f in ["manifest.json", "campaign.toml"] {
        std::fs::copy(planned.join(f), camp.join(f)).unwrap();
    }
    for e in std::fs::read_dir(planned.join("shards")).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), camp.join("shards").join(e.file_name())).unwrap();
    }
    let before = common::visible_files(&camp);
    fs.fill(&filler, 48 * 1024);
    let o = common::run(&["campaign", "reduce", &s(&camp)]);
    match full_disk_outcome("campaign reduce", &o, &camp, &before) {
        Ok(true) => eprintln!(
            "full disk, campaign reduce: exit 2, no summary.json or report.md, nothing left"
        ),
        Ok(false) => failures.push("campaign reduce: succeeded on a full disk".to_string()),
        Err(e) => failures.push(e),
    }
    std::fs::remove_file(&filler).unwrap();
    drop(fs);
    assert!(failures.is_empty(), "{failures:#?}");
}
