//! IMU error parameters in SI units. Files carry them in the paper's units (deg/h, ppm, arcsec,
//! ug and their per-degC forms); conversion happens in `sins-config`, never here.

use sins_nav::Vec3;

/// Which of the paper's parameter sets a [`ImuErrorParams`] represents.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ParamModel {
    /// 30-state filter: navigation errors plus 21 constant coefficients, no temperature terms.
    States30,
    /// 42-state filter: the 30-state set plus the 12 accelerometer temperature coefficients.
    States42,
}

impl ParamModel {
    /// Number of Kalman-filter states of this model (9 navigation + coefficients).
    pub fn n_states(self) -> usize {
        match self {
            ParamModel::States30 => 30,
            ParamModel::States42 => 42,
        }
    }
}

/// Gyro error coefficients of eq (2).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct GyroParams {
    /// Constant drift B_g along x, y, z (rad/s).
    pub bias_radps: Vec3,
    /// Scale-factor errors δK_g along x, y, z (dimensionless, 1 ppm = 1e-6).
    pub scale: Vec3,
    /// Installation errors `[δM_gyx, δM_gzx, δM_gzy]` (rad), the lower triangle of eq (2).
    pub misalignment_rad: [f64; 3],
}

/// Accelerometer error coefficients of eq (1) at the reference temperature.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct AccelParams {
    /// Constant bias B_a along x, y, z (m/s^2).
    pub bias_mps2: Vec3,
    /// Scale-factor errors δK_a along x, y, z (dimensionless).
    pub scale: Vec3,
    /// Installation errors in state-vector order (eq 8):
    /// `[δM_ayx, δM_azx, δM_axy, δM_azy, δM_axz, δM_ayz]` (rad).
    pub misalignment_rad: [f64; 6],
}

/// The 12 first-order accelerometer temperature coefficients of eq (1).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct TemperatureCoeffs {
    /// TB_a: bias per degC along x, y, z (m/s^2/degC).
    pub bias_mps2_per_degc: Vec3,
    /// TK_a: scale-factor error per degC along x, y, z (1/degC).
    pub scale_per_degc: Vec3,
    /// TM_a in state-vector order `[TM_ayx, TM_azx, TM_axy, TM_azy, TM_axz, TM_ayz]` (rad/degC).
    pub misalignment_rad_per_degc: [f64; 6],
}

/// A complete parameter set: what a calibration estimates and what compensation applies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuErrorParams {
    /// Which parameter set this is; a 30-state set has all temperature coefficients zero.
    pub model: ParamModel,
    /// Gyro coefficients (eq 2).
    pub gyro: GyroParams,
    /// Accelerometer coefficients at the reference temperature (eq 1).
    pub accel: AccelParams,
    /// Accelerometer temperature coefficients (eq 1); zero for [`ParamModel::States30`].
    pub temperature: TemperatureCoeffs,
    /// Temperature (degC) at which the temperature terms vanish: ΔT = T - this. The paper writes
    /// eq (6) with T itself, i.e. a reference of 0 degC, which is the default.
    pub reference_temperature_degc: f64,
}

impl ImuErrorParams {
    /// An error-free IMU (all coefficients zero) of the given model.
    pub fn ideal(model: ParamModel) -> Self {
        Self {
            model,
            gyro: GyroParams::default(),
            accel: AccelParams::default(),
            temperature: TemperatureCoeffs::default(),
            reference_temperature_degc: 0.0,
        }
    }

    /// Gyro error matrix E_g of eq (2) (lower triangular: δK on the diagonal, δM below).
    pub fn gyro_error_matrix(&self) -> sins_nav::Mat3 {
        let g = &self.gyro;
        let [yx, zx, zy] = g.misalignment_rad;
        sins_nav::Mat3::new(g.scale.x, 0.0, 0.0, yx, g.scale.y, 0.0, zx, zy, g.scale.z)
    }

    /// Accelerometer error matrix E_a(ΔT) of eq (1) for accelerometer temperature offsets
    /// `dt_degc` = T_j - T_ref (degC): `[δK_a + δM_a] + [TK_a + TM_a] ∘ ΔT`, where, following the
    /// paper's convention (eqs 1 and 4), **column j of the temperature matrix is multiplied by the
    /// temperature offset of accelerometer j**.
    pub fn accel_error_matrix(&self, dt_degc: &[f64; 3]) -> sins_nav::Mat3 {
        let a = &self.accel;
        let t = &self.temperature;
        let [yx, zx, xy, zy, xz, yz] = a.misalignment_rad;
        let [tyx, tzx, txy, tzy, txz, tyz] = t.misalignment_rad_per_degc;
        let [dx, dy, dz] = *dt_degc;
        sins_nav::Mat3::new(
            a.scale.x + t.scale_per_degc.x * dx,
            xy + txy * dy,
            xz + txz * dz,
            yx + tyx * dx,
            a.scale.y + t.scale_per_degc.y * dy,
            yz + tyz * dz,
            zx + tzx * dx,
            zy + tzy * dy,
            a.scale.z + t.scale_per_degc.z * dz,
        )
    }

    /// Accelerometer bias B_a + TB_a ∘ ΔT (m/s^2) for temperature offsets `dt_degc` (degC).
    pub fn accel_bias_mps2(&self, dt_degc: &[f64; 3]) -> Vec3 {
        let tb = &self.temperature.bias_mps2_per_degc;
        self.accel.bias_mps2 + Vec3::new(tb.x * dt_degc[0], tb.y * dt_degc[1], tb.z * dt_degc[2])
    }

    /// Temperature offsets ΔT_j = T_j - T_ref (degC) for thermometer readings `temp_degc`.
    pub fn temperature_offsets_degc(&self, temp_degc: &[f64; 3]) -> [f64; 3] {
        let r = self.reference_temperature_degc;
        [temp_degc[0] - r, temp_degc[1] - r, temp_degc[2] - r]
    }

    /// True when every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        let v = |x: &Vec3| x.iter().all(|c| c.is_finite());
        let a = |x: &[f64]| x.iter().all(|c| c.is_finite());
        v(&self.gyro.bias_radps)
            && v(&self.gyro.scale)
            && a(&self.gyro.misalignment_rad)
            && v(&self.accel.bias_mps2)
            && v(&self.accel.scale)
            && a(&self.accel.misalignment_rad)
            && v(&self.temperature.bias_mps2_per_degc)
            && v(&self.temperature.scale_per_degc)
            && a(&self.temperature.misalignment_rad_per_degc)
            && self.reference_temperature_degc.is_finite()
    }
}
