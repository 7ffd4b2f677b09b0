//! The catalogue of candidate effects laid out for the fit: the deterministic kinds as columns
//! of the candidate block, the random processes as walks on a sensor triad.

use crate::rank::Layout;
use crate::sensitivity::ColumnId;
use sins_imu::effects::Sensor;
use sins_imu::{EffectKind, Linearity};

/// The catalogue as fit columns.
pub(crate) struct Catalogue {
    /// Deterministic candidates: their columns among the candidate columns.
    pub layouts: Vec<Layout>,
    /// Every candidate column with the SI value of one candidate unit.
    pub columns: Vec<(ColumnId, f64)>,
    /// Random-walk candidates: kind and first bias axis (0 gyro, 3 accelerometer).
    pub walks: Vec<(EffectKind, usize)>,
}

/// Lay out `kinds`: deterministic ones as columns, random processes as walks.
pub(crate) fn catalogue(kinds: &[EffectKind]) -> Catalogue {
    let mut c = Catalogue {
        layouts: Vec::new(),
        columns: Vec::new(),
        walks: Vec::new(),
    };
    for &k in kinds {
        match k.linearity() {
            Linearity::RandomProcess => {
                c.walks
                    .push((k, if k.sensor() == Sensor::Gyro { 0 } else { 3 }));
            }
            _ => {
                c.layouts.push(Layout {
                    kind: k,
                    first: c.columns.len(),
                    n: k.n_components(),
                });
                for comp in 0..k.n_components() {
                    c.columns.push((ColumnId::Effect(k, comp), k.unit().si));
                }
            }
        }
    }
    c
}
