//! Sensitivity columns: what one unit of an error term adds to the compensated increments of a
//! sample. Two families:
//!
//! - the 33 coefficients of the paper's model ([`ParamSlot`], eq 8 order), whose calibration
//!   uncertainty widens the twin's spread: a coefficient that is off by `δp` leaves
//!   `δE·Δ + δB·h` in the compensated increments (Δ the true increment, taken as the compensated
//!   one), a single body axis scaled by a per-sample scalar;
//! - the candidate effects of the catalogue (`sins_imu::EffectKind`), one column per magnitude
//!   component, evaluated by the effect itself (`EffectSpec::unit(kind, c).build(params)`) on the
//!   sample's context: compensated increments as the true motion, recorded temperatures, smoothed
//!   temperature rates.

use serde::{Deserialize, Serialize};
use sins_imu::{EffectContext, EffectKind, EffectSpec, ExtraEffect, ImuErrorParams, ParamModel};
use sins_nav::{ARCSEC, DEG_PER_H, UG, Vec3};

/// Which sensor triad a coefficient belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Triad {
    /// Gyros (angular increments).
    Gyro,
    /// Accelerometers (velocity increments).
    Accel,
}

/// What multiplies a coefficient in the increment of its axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Driver {
    /// `h` (biases).
    Interval,
    /// The true increment along axis `j` (scale factors, installation errors).
    Increment(usize),
    /// `ΔT_j h` (temperature bias coefficients).
    TempInterval(usize),
    /// `ΔT_j` times the true increment along axis `j` (TK, TM).
    TempIncrement(usize),
}

/// One coefficient of eqs (1)-(2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamSlot {
    /// The paper's name, e.g. `"dM_ayx"`.
    pub name: &'static str,
    /// Paper unit label.
    pub unit: &'static str,
    /// SI value of one paper unit.
    pub si_per_unit: f64,
    /// Sensor triad.
    pub triad: Triad,
    /// Body axis whose increment the coefficient perturbs.
    pub row: usize,
    driver: Driver,
    /// True for the 12 temperature coefficients (42-state model only).
    pub temperature: bool,
}

const PPM: f64 = 1e-6;

const fn slot(
    name: &'static str,
    unit: &'static str,
    si_per_unit: f64,
    triad: Triad,
    row: usize,
    driver: Driver,
    temperature: bool,
) -> ParamSlot {
    ParamSlot {
        name,
        unit,
        si_per_unit,
        triad,
        row,
        driver,
        temperature,
    }
}

use Driver::{Increment as Inc, Interval, TempIncrement as TInc, TempInterval as TInt};
use Triad::{Accel as A, Gyro as G};

/// The 33 coefficients in the state order of eq (8).
pub const PARAM_SLOTS: [ParamSlot; 33] = [
    slot("B_gx", "deg/h", DEG_PER_H, G, 0, Interval, false),
    slot("B_gy", "deg/h", DEG_PER_H, G, 1, Interval, false),
    slot("B_gz", "deg/h", DEG_PER_H, G, 2, Interval, false),
    slot("B_ax", "ug", UG, A, 0, Interval, false),
    slot("B_ay", "ug", UG, A, 1, Interval, false),
    slot("B_az", "ug", UG, A, 2, Interval, false),
    slot("dK_gx", "ppm", PPM, G, 0, Inc(0), false),
    slot("dM_gyx", "arcsec", ARCSEC, G, 1, Inc(0), false),
    slot("dM_gzx", "arcsec", ARCSEC, G, 2, Inc(0), false),
    slot("dK_gy", "ppm", PPM, G, 1, Inc(1), false),
    slot("dM_gzy", "arcsec", ARCSEC, G, 2, Inc(1), false),
    slot("dK_gz", "ppm", PPM, G, 2, Inc(2), false),
    slot("dK_ax", "ppm", PPM, A, 0, Inc(0), false),
    slot("dM_ayx", "arcsec", ARCSEC, A, 1, Inc(0), false),
    slot("dM_azx", "arcsec", ARCSEC, A, 2, Inc(0), false),
    slot("dM_axy", "arcsec", ARCSEC, A, 0, Inc(1), false),
    slot("dK_ay", "ppm", PPM, A, 1, Inc(1), false),
    slot("dM_azy", "arcsec", ARCSEC, A, 2, Inc(1), false),
    slot("dM_axz", "arcsec", ARCSEC, A, 0, Inc(2), false),
    slot("dM_ayz", "arcsec", ARCSEC, A, 1, Inc(2), false),
    slot("dK_az", "ppm", PPM, A, 2, Inc(2), false),
    slot("TB_ax", "ug/degC", UG, A, 0, TInt(0), true),
    slot("TB_ay", "ug/degC", UG, A, 1, TInt(1), true),
    slot("TB_az", "ug/degC", UG, A, 2, TInt(2), true),
    slot("TK_ax", "ppm/degC", PPM, A, 0, TInc(0), true),
    slot("TK_ay", "ppm/degC", PPM, A, 1, TInc(1), true),
    slot("TK_az", "ppm/degC", PPM, A, 2, TInc(2), true),
    slot("TM_ayx", "arcsec/degC", ARCSEC, A, 1, TInc(0), true),
    slot("TM_azx", "arcsec/degC", ARCSEC, A, 2, TInc(0), true),
    slot("TM_axy", "arcsec/degC", ARCSEC, A, 0, TInc(1), true),
    slot("TM_azy", "arcsec/degC", ARCSEC, A, 2, TInc(1), true),
    slot("TM_axz", "arcsec/degC", ARCSEC, A, 0, TInc(2), true),
    slot("TM_ayz", "arcsec/degC", ARCSEC, A, 1, TInc(2), true),
];

impl ParamSlot {
    /// The scalar multiplying a unit (SI) coefficient in the increment of [`Self::row`].
    #[inline]
    pub(crate) fn scalar(&self, s: &SampleInputs) -> f64 {
        let inc = match self.triad {
            Triad::Gyro => &s.dtheta_rad,
            Triad::Accel => &s.dv_mps,
        };
        match self.driver {
            Driver::Interval => s.h_s,
            Driver::Increment(j) => inc[j],
            Driver::TempInterval(j) => s.dtemp_degc[j] * s.h_s,
            Driver::TempIncrement(j) => s.dtemp_degc[j] * inc[j],
        }
    }
}

impl ParamSlot {
    /// [`Self::scalar`] of each of `inputs`, into `out` (cleared first): the same values, the
    /// driver chosen once.
    pub(crate) fn scalars(&self, inputs: &[SampleInputs], out: &mut Vec<f64>) {
        out.clear();
        let it = inputs.iter();
        match (self.driver, self.triad) {
            (Driver::Interval, _) => out.extend(it.map(|s| s.h_s)),
            (Driver::Increment(j), Triad::Gyro) => out.extend(it.map(|s| s.dtheta_rad[j])),
            (Driver::Increment(j), Triad::Accel) => out.extend(it.map(|s| s.dv_mps[j])),
            (Driver::TempInterval(j), _) => out.extend(it.map(|s| s.dtemp_degc[j] * s.h_s)),
            (Driver::TempIncrement(j), Triad::Gyro) => {
                out.extend(it.map(|s| s.dtemp_degc[j] * s.dtheta_rad[j]))
            }
            (Driver::TempIncrement(j), Triad::Accel) => {
                out.extend(it.map(|s| s.dtemp_degc[j] * s.dv_mps[j]))
            }
        }
    }
}

/// The 33 coefficients of `p` in SI, eq (8) order.
pub fn param_vector(p: &ImuErrorParams) -> [f64; 33] {
    let (g, a, t) = (&p.gyro, &p.accel, &p.temperature);
    let [gyx, gzx, gzy] = g.misalignment_rad;
    let [ayx, azx, axy, azy, axz, ayz] = a.misalignment_rad;
    let [tyx, tzx, txy, tzy, txz, tyz] = t.misalignment_rad_per_degc;
    [
        g.bias_radps.x,
        g.bias_radps.y,
        g.bias_radps.z,
        a.bias_mps2.x,
        a.bias_mps2.y,
        a.bias_mps2.z,
        g.scale.x,
        gyx,
        gzx,
        g.scale.y,
        gzy,
        g.scale.z,
        a.scale.x,
        ayx,
        azx,
        axy,
        a.scale.y,
        azy,
        axz,
        ayz,
        a.scale.z,
        t.bias_mps2_per_degc.x,
        t.bias_mps2_per_degc.y,
        t.bias_mps2_per_degc.z,
        t.scale_per_degc.x,
        t.scale_per_degc.y,
        t.scale_per_degc.z,
        tyx,
        tzx,
        txy,
        tzy,
        txz,
        tyz,
    ]
}

/// The coefficients a parameter set of `model` uses (the temperature ones only for 42 states).
pub fn slots_of(model: ParamModel) -> impl Iterator<Item = (usize, &'static ParamSlot)> {
    PARAM_SLOTS
        .iter()
        .enumerate()
        .filter(move |(_, s)| model == ParamModel::States42 || !s.temperature)
}

/// What the columns see of one sample.
#[derive(Clone, Copy, Debug)]
pub struct SampleInputs {
    /// Sample interval (s).
    pub h_s: f64,
    /// Compensated angular increment (rad), the best estimate of the true one.
    pub dtheta_rad: Vec3,
    /// Compensated velocity increment (m/s).
    pub dv_mps: Vec3,
    /// Recorded temperatures minus the parameter set's reference (degC).
    pub dtemp_degc: [f64; 3],
    /// Context handed to the catalogue's effects.
    pub ctx: EffectContext,
}

/// What a column perturbs in one sample.
pub enum Perturbation {
    /// One body axis of one triad, by a scalar.
    Axis {
        /// Triad.
        triad: Triad,
        /// Body axis.
        row: usize,
        /// Increment (rad or m/s).
        value: f64,
    },
    /// Both triads, any axes.
    Full {
        /// Angular increment (rad).
        dtheta_rad: Vec3,
        /// Velocity increment (m/s).
        dv_mps: Vec3,
    },
}

/// A column being evaluated over a run.
pub enum ColumnEval {
    /// A paper coefficient (1 SI unit).
    Param(ParamSlot),
    /// A catalogue effect of magnitude 1 SI unit on one component.
    Effect(Box<dyn ExtraEffect>),
}

impl ColumnEval {
    /// The column of component `component` of `kind` (1 SI unit), built against `params` (the
    /// thermal lag acts through the calibrated temperature coefficients).
    pub fn effect(kind: EffectKind, component: usize, params: &ImuErrorParams) -> Self {
        ColumnEval::Effect(EffectSpec::unit(kind, component).build(params))
    }

    /// The perturbation of this sample (advances a stateful effect by one sample).
    #[inline]
    pub fn perturbation(&mut self, s: &SampleInputs) -> Perturbation {
        match self {
            ColumnEval::Param(p) => Perturbation::Axis {
                triad: p.triad,
                row: p.row,
                value: p.scalar(s),
            },
            ColumnEval::Effect(e) => {
                let (dtheta_rad, dv_mps) = e.perturbation(&s.ctx);
                Perturbation::Full { dtheta_rad, dv_mps }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sins_imu::{ForwardModel, ParamModel};

    /// A unit change of each coefficient changes the forward model's raw increment by exactly
    /// the column's perturbation (to first order: the forward model is linear in each one).
    #[test]
    fn param_columns_match_the_forward_model() {
        let mut base = ImuErrorParams::ideal(ParamModel::States42);
        base.reference_temperature_degc = 20.0;
        let h = 0.005;
        let dth = Vec3::new(1e-3, -2e-3, 3e-3);
        let dv = Vec3::new(0.01, -0.02, 0.049);
        let temp = [25.0, 17.0, 31.0];
        let ctx = EffectContext::at_rest(h, h, temp);
        let s = SampleInputs {
            h_s: h,
            dtheta_rad: dth,
            dv_mps: dv,
            dtemp_degc: base.temperature_offsets_degc(&temp),
            ctx,
        };
        let (r0, v0) = ForwardModel::new(base).apply(&dth, &dv, h, &temp, &ctx);
        for (i, slot) in PARAM_SLOTS.iter().enumerate() {
            let mut p = base;
            let eps = 1e-3;
            set_param(&mut p, i, eps);
            assert_eq!(param_vector(&p)[i], eps);
            let (r1, v1) = ForwardModel::new(p).apply(&dth, &dv, h, &temp, &ctx);
            let (dr, dvv) = ((r1 - r0) / eps, (v1 - v0) / eps);
            let Perturbation::Axis { triad, row, value } =
                ColumnEval::Param(*slot).perturbation(&s)
            else {
                unreachable!()
            };
            let mut want = (Vec3::zeros(), Vec3::zeros());
            match triad {
                Triad::Gyro => want.0[row] = value,
                Triad::Accel => want.1[row] = value,
            }
            assert!(
                (dr - want.0).norm() + (dvv - want.1).norm() < 1e-12,
                "{}: {dr:?} {dvv:?} vs {want:?}",
                slot.name
            );
        }
    }

    fn set_param(p: &mut ImuErrorParams, i: usize, v: f64) {
        let mut x = param_vector(p);
        x[i] = v;
        let (g, a, t) = (&mut p.gyro, &mut p.accel, &mut p.temperature);
        g.bias_radps = Vec3::new(x[0], x[1], x[2]);
        a.bias_mps2 = Vec3::new(x[3], x[4], x[5]);
        g.scale = Vec3::new(x[6], x[9], x[11]);
        g.misalignment_rad = [x[7], x[8], x[10]];
        a.scale = Vec3::new(x[12], x[16], x[20]);
        a.misalignment_rad = [x[13], x[14], x[15], x[17], x[18], x[19]];
        t.bias_mps2_per_degc = Vec3::new(x[21], x[22], x[23]);
        t.scale_per_degc = Vec3::new(x[24], x[25], x[26]);
        t.misalignment_rad_per_degc = [x[27], x[28], x[29], x[30], x[31], x[32]];
    }
}
