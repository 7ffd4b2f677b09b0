//! One Rerun recording per experiment: every parameter set's error track on one timeline.

use sins_harness::ErrorPoint;
use sins_harness::pipeline::RunOutcome;
use sins_nav::ARCSEC;
use sins_nav::attitude::attitude_error_ned_rad;
use sins_viz::{Annotation, NavRecording, ScalarSeries, Strip2};

/// Colour of the i-th parameter set (Okabe-Ito palette, colour-blind safe).
pub(crate) fn set_color(i: usize) -> [u8; 4] {
    const P: [[u8; 4]; 4] = [
        [230, 159, 0, 255],
        [0, 114, 178, 255],
        [0, 158, 115, 255],
        [204, 121, 167, 255],
    ];
    P[i % P.len()]
}

/// Seconds between vertices of the trajectory line strip.
const STRIP_STEP_S: usize = 10;

/// The recording of one experiment.
pub(crate) fn recording(o: &RunOutcome) -> NavRecording {
    let mut rec = NavRecording::default();
    for (i, tr) in o.tracks.iter().enumerate() {
        let t: Vec<f64> = tr.points.iter().map(|p| p.t_s).collect();
        let mut add = |entity: String, values: Vec<f64>| {
            rec.series.push(ScalarSeries {
                entity,
                times_s: t.clone(),
                values,
            })
        };
        let col = |f: &dyn Fn(&ErrorPoint) -> f64| tr.points.iter().map(f).collect::<Vec<_>>();
        let set = &tr.set;
        add(
            format!("errors/horizontal/{set}"),
            col(&|p| p.horizontal_m()),
        );
        add(format!("errors/position/north/{set}"), col(&|p| p.north_m));
        add(format!("errors/position/east/{set}"), col(&|p| p.east_m));
        add(
            format!("errors/velocity/north/{set}"),
            col(&|p| p.vel_n_mps),
        );
        add(format!("errors/velocity/east/{set}"), col(&|p| p.vel_e_mps));
        if let Some(truth) = &o.truth_attitude {
            let mut phi = [Vec::new(), Vec::new(), Vec::new()];
            let mut times = Vec::new();
            let mut k = 0usize;
            for p in &tr.points {
                while k + 1 < truth.len() && truth[k].0 < p.t_s - 1e-6 {
                    k += 1;
                }
                if let Some(&(tt, q)) = truth.get(k)
                    && (tt - p.t_s).abs() < 1e-6
                {
                    let e = attitude_error_ned_rad(&p.ned_from_body, &q) / ARCSEC;
                    for (v, x) in phi.iter_mut().zip(e.iter()) {
                        v.push(*x);
                    }
                    times.push(p.t_s);
                }
            }
            for (axis, values) in ["north", "east", "down"].into_iter().zip(phi) {
                rec.series.push(ScalarSeries {
                    entity: format!("errors/attitude/{axis}/{set}"),
                    times_s: times.clone(),
                    values,
                });
            }
        }
        rec.strips.push(Strip2 {
            entity: format!("trajectory/{set}"),
            points: tr
                .points
                .iter()
                .step_by(STRIP_STEP_S)
                .map(|p| [p.east_m as f32, p.north_m as f32])
                .collect(),
            color: set_color(i),
        });
    }
    let t: Vec<f64> = o.temperatures.iter().map(|p| p.t_s).collect();
    for (j, axis) in ["ax", "ay", "az"].into_iter().enumerate() {
        let values: Vec<f64> = o.temperatures.iter().map(|p| p.temp_degc[j]).collect();
        if values.iter().any(|v| v.is_finite()) {
            rec.series.push(ScalarSeries {
                entity: format!("temperature/{axis}"),
                times_s: t.clone(),
                values,
            });
        }
    }
    if let Some(tr) = o.tracks.first() {
        for s in &tr.stretches {
            rec.annotations.push(Annotation {
                t_s: s.start_s,
                text: format!(
                    "{} from {:.2} h to {:.2} h",
                    s.display_name(),
                    s.start_s / 3600.0,
                    s.end_s / 3600.0
                ),
            });
        }
    }
    rec
}
