//! The state vector of eq (8): 9 navigation error states followed by the error coefficients of
//! eqs (1)-(2) in the paper's order, and the conversion between a coefficient vector (state
//! order, SI) and [`ImuErrorParams`].

use sins_imu::{ImuErrorParams, ParamModel};

// The navigation error states `φ_N, φ_E, φ_D, δV_N, δV_E, δV_D, δL, δλ, δh` and their indices
// are the workspace's one error model's, declared once in sins-nav.
pub use sins_nav::error_model::{NAV_STATES, PHI, POS, VEL};

/// Names of all 42 states in the order of eq (8); the 30-state model uses the first 30.
pub const STATE_NAMES: [&str; 42] = [
    "phi_N", "phi_E", "phi_D", "dV_N", "dV_E", "dV_D", "dL", "dlambda", "dh", "B_gx", "B_gy",
    "B_gz", "B_ax", "B_ay", "B_az", "dK_gx", "dM_gyx", "dM_gzx", "dK_gy", "dM_gzy", "dK_gz",
    "dK_ax", "dM_ayx", "dM_azx", "dM_axy", "dK_ay", "dM_azy", "dM_axz", "dM_ayz", "dK_az", "TB_ax",
    "TB_ay", "TB_az", "TK_ax", "TK_ay", "TK_az", "TM_ayx", "TM_azx", "TM_axy", "TM_azy", "TM_axz",
    "TM_ayz",
];

/// SI unit of each state of [`STATE_NAMES`].
pub const STATE_UNITS: [&str; 42] = [
    "rad",
    "rad",
    "rad",
    "m/s",
    "m/s",
    "m/s",
    "rad",
    "rad",
    "m",
    "rad/s",
    "rad/s",
    "rad/s",
    "m/s^2",
    "m/s^2",
    "m/s^2",
    "1",
    "rad",
    "rad",
    "1",
    "rad",
    "1",
    "1",
    "rad",
    "rad",
    "rad",
    "1",
    "rad",
    "rad",
    "rad",
    "1",
    "m/s^2/degC",
    "m/s^2/degC",
    "m/s^2/degC",
    "1/degC",
    "1/degC",
    "1/degC",
    "rad/degC",
    "rad/degC",
    "rad/degC",
    "rad/degC",
    "rad/degC",
    "rad/degC",
];

/// Number of error coefficients (parameter states) of a model: 21 or 33.
pub fn n_params(model: ParamModel) -> usize {
    model.n_states() - NAV_STATES
}

/// Which error equation a coefficient enters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Row {
    /// Attitude error rows (gyro coefficients): `φ̇ = … − C δω^b`.
    Attitude,
    /// Velocity error rows (accelerometer coefficients): `δV̇ = … + C δf^b`.
    Velocity,
}

/// Which per-sample quantity multiplies column `i` of `C_b^n` for a coefficient.
/// Indices into the 13 accumulated inputs: `dθ_j` (0..3), `dv_j` (3..6), `dv_j ΔT_j` (6..9),
/// `ΔT_j h` (9..12), `h` (12).
pub(crate) const U_DT: usize = 12;

/// Column `i` of `C_b^n` and input index `u` for each of the 33 coefficients (state order),
/// so that the coefficient's column of the input matrix is `± C[:, i] · u` integrated.
pub(crate) const COLUMNS: [(Row, usize, usize); 33] = {
    use Row::{Attitude as A, Velocity as V};
    [
        (A, 0, U_DT), // B_gx
        (A, 1, U_DT), // B_gy
        (A, 2, U_DT), // B_gz
        (V, 0, U_DT), // B_ax
        (V, 1, U_DT), // B_ay
        (V, 2, U_DT), // B_az
        (A, 0, 0),    // dK_gx:  E_g(0,0) ω_x
        (A, 1, 0),    // dM_gyx: E_g(1,0) ω_x
        (A, 2, 0),    // dM_gzx: E_g(2,0) ω_x
        (A, 1, 1),    // dK_gy:  E_g(1,1) ω_y
        (A, 2, 1),    // dM_gzy: E_g(2,1) ω_y
        (A, 2, 2),    // dK_gz:  E_g(2,2) ω_z
        (V, 0, 3),    // dK_ax:  E_a(0,0) f_x
        (V, 1, 3),    // dM_ayx: E_a(1,0) f_x
        (V, 2, 3),    // dM_azx: E_a(2,0) f_x
        (V, 0, 4),    // dM_axy: E_a(0,1) f_y
        (V, 1, 4),    // dK_ay:  E_a(1,1) f_y
        (V, 2, 4),    // dM_azy: E_a(2,1) f_y
        (V, 0, 5),    // dM_axz: E_a(0,2) f_z
        (V, 1, 5),    // dM_ayz: E_a(1,2) f_z
        (V, 2, 5),    // dK_az:  E_a(2,2) f_z
        (V, 0, 9),    // TB_ax: ΔT_x
        (V, 1, 10),   // TB_ay: ΔT_y
        (V, 2, 11),   // TB_az: ΔT_z
        (V, 0, 6),    // TK_ax:  (0,0) f_x ΔT_x
        (V, 1, 7),    // TK_ay:  (1,1) f_y ΔT_y
        (V, 2, 8),    // TK_az:  (2,2) f_z ΔT_z
        (V, 1, 6),    // TM_ayx: (1,0) f_x ΔT_x
        (V, 2, 6),    // TM_azx: (2,0) f_x ΔT_x
        (V, 0, 7),    // TM_axy: (0,1) f_y ΔT_y
        (V, 2, 7),    // TM_azy: (2,1) f_y ΔT_y
        (V, 0, 8),    // TM_axz: (0,2) f_z ΔT_z
        (V, 1, 8),    // TM_ayz: (1,2) f_z ΔT_z
    ]
};

/// Mutable access to coefficient `k` (state order, 0-based among the 33) of a parameter set.
fn slot(p: &mut ImuErrorParams, k: usize) -> &mut f64 {
    match k {
        0..3 => &mut p.gyro.bias_radps[k],
        3..6 => &mut p.accel.bias_mps2[k - 3],
        6 => &mut p.gyro.scale[0],
        7 => &mut p.gyro.misalignment_rad[0],
        8 => &mut p.gyro.misalignment_rad[1],
        9 => &mut p.gyro.scale[1],
        10 => &mut p.gyro.misalignment_rad[2],
        11 => &mut p.gyro.scale[2],
        12 => &mut p.accel.scale[0],
        13 => &mut p.accel.misalignment_rad[0],
        14 => &mut p.accel.misalignment_rad[1],
        15 => &mut p.accel.misalignment_rad[2],
        16 => &mut p.accel.scale[1],
        17 => &mut p.accel.misalignment_rad[3],
        18 => &mut p.accel.misalignment_rad[4],
        19 => &mut p.accel.misalignment_rad[5],
        20 => &mut p.accel.scale[2],
        21..24 => &mut p.temperature.bias_mps2_per_degc[k - 21],
        24..27 => &mut p.temperature.scale_per_degc[k - 24],
        _ => &mut p.temperature.misalignment_rad_per_degc[(k - 27).min(5)],
    }
}

/// The coefficients of `params` as a vector in state order (SI): 21 entries for a 30-state model,
/// 33 for a 42-state model (`model` decides, not `params.model`).
pub fn params_to_vec(params: &ImuErrorParams, model: ParamModel) -> Vec<f64> {
    let mut copy = *params;
    (0..n_params(model)).map(|k| *slot(&mut copy, k)).collect()
}

/// A parameter set of `model` from a coefficient vector in state order (SI); missing trailing
/// entries (temperature coefficients of a 30-state vector) are zero.
pub fn params_from_vec(values: &[f64], model: ParamModel, reference_degc: f64) -> ImuErrorParams {
    let mut p = ImuErrorParams::ideal(model);
    p.reference_temperature_degc = reference_degc;
    for (k, v) in values.iter().enumerate().take(33) {
        *slot(&mut p, k) = *v;
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vector_round_trip_covers_every_slot_once() {
        let v: Vec<f64> = (0..33).map(|k| k as f64 + 1.0).collect();
        let p = params_from_vec(&v, ParamModel::States42, 20.0);
        assert_eq!(params_to_vec(&p, ParamModel::States42), v);
        assert_eq!(p.gyro.misalignment_rad, [8.0, 9.0, 11.0]);
        assert_eq!(
            p.accel.misalignment_rad,
            [14.0, 15.0, 16.0, 18.0, 19.0, 20.0]
        );
        assert_eq!(
            p.temperature.misalignment_rad_per_degc,
            [28.0, 29.0, 30.0, 31.0, 32.0, 33.0]
        );
        assert_eq!(params_to_vec(&p, ParamModel::States30).len(), 21);
    }

    #[test]
    fn columns_match_the_error_matrices() {
        // E_a(i,j) of coefficient k must be the entry the column table says.
        let mut v = vec![0.0; 33];
        for k in 12..21 {
            v[k] = 1.0;
            let p = params_from_vec(&v, ParamModel::States42, 0.0);
            let e = p.accel_error_matrix(&[0.0; 3]);
            let (_, i, u) = COLUMNS[k];
            assert_eq!(e[(i, u - 3)], 1.0, "coefficient {k}");
            assert_eq!(e.iter().filter(|x| **x != 0.0).count(), 1);
            v[k] = 0.0;
        }
        for k in 24..33 {
            v[k] = 1.0;
            let p = params_from_vec(&v, ParamModel::States42, 0.0);
            let e = p.accel_error_matrix(&[1.0, 1.0, 1.0]);
            let (_, i, u) = COLUMNS[k];
            assert_eq!(e[(i, u - 6)], 1.0, "coefficient {k}");
            v[k] = 0.0;
        }
        for k in 6..12 {
            v[k] = 1.0;
            let e = params_from_vec(&v, ParamModel::States42, 0.0).gyro_error_matrix();
            let (_, i, u) = COLUMNS[k];
            assert_eq!(e[(i, u)], 1.0, "coefficient {k}");
            v[k] = 0.0;
        }
    }
}
