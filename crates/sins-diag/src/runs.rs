//! Helpers over a set of runs shared by the diagnosis's stages: a parallel map that keeps run
//! order, interpolation of an error track, and a candidate's columns on a run's output grid.

use crate::error::DiagError;
use crate::input::RunData;
use crate::parallel::par_map;
use crate::rank::Layout;
use crate::sensitivity::{ColumnId, RunSensitivity};
use crate::validate::OutputColumns;
use sins_replay::ErrorPoint;

/// North/east of a track at `t_s`, linear between points (clamped at the ends).
pub fn track_at(points: &[ErrorPoint], t_s: f64) -> [f64; 2] {
    let k = points.partition_point(|p| p.t_s < t_s);
    match (k.checked_sub(1).and_then(|i| points.get(i)), points.get(k)) {
        (Some(a), Some(b)) if b.t_s > a.t_s => {
            let w = (t_s - a.t_s) / (b.t_s - a.t_s);
            [
                a.north_m + w * (b.north_m - a.north_m),
                a.east_m + w * (b.east_m - a.east_m),
            ]
        }
        (_, Some(b)) => [b.north_m, b.east_m],
        (Some(a), None) => [a.north_m, a.east_m],
        (None, None) => [0.0, 0.0],
    }
}

/// `f` on every run, on `threads` workers that each take the longest run not yet started
/// (a 4 h calibration run beside two 15 h runs then costs one 15 h run plus 4 h, not two 15 h
/// runs); results in run order, identical for any thread count (each run is processed alone).
pub fn par_runs<T: Send>(
    runs: &mut [RunData],
    threads: usize,
    f: impl Fn(&mut RunData) -> Result<T, DiagError> + Sync,
) -> Result<Vec<T>, DiagError> {
    // Longest first (by the real track's span), ties in run order.
    let span = |r: &RunData| match (r.track.first(), r.track.last()) {
        (Some(a), Some(b)) => b.t_s - a.t_s,
        _ => 0.0,
    };
    let mut queue: Vec<(usize, &mut RunData)> = runs.iter_mut().enumerate().collect();
    queue.sort_by(|a, b| span(b.1).total_cmp(&span(a.1)).then(a.0.cmp(&b.0)));
    let mut done = par_map(queue, threads, |(i, r)| (i, f(r)))?;
    // Back from the longest-first order to run order.
    done.sort_by_key(|(i, _)| *i);
    done.into_iter().map(|(_, r)| r).collect()
}

/// A deterministic candidate's columns on a run's output grid, per candidate unit.
pub fn output_columns(s: &RunSensitivity, l: &Layout) -> OutputColumns {
    let si = l.kind.unit().si;
    (0..l.n)
        .map(|c| match s.column(ColumnId::Effect(l.kind, c)) {
            Some(i) => (0..s.times.times_s.len())
                .map(|k| [si * s.north_m[i][k], si * s.east_m[i][k]])
                .collect(),
            None => vec![[0.0; 2]; s.times.times_s.len()],
        })
        .collect()
}
