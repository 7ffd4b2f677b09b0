//! The error coefficients of eqs (1)-(2) as the paper names them, in the state order of eq (8),
//! with their file keys, paper units and place in [`ImuErrorParams`]. This one table drives the
//! parameter-file reader, both writers and [`coefficient_table`].

use crate::units::PaperUnit;
use sins_imu::ImuErrorParams;

/// The table of a parameter file a coefficient belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Section {
    /// `[gyro]`: eq (2).
    Gyro,
    /// `[accel]`: the constant part of eq (1).
    Accel,
    /// `[accel_temperature]`: the first-order temperature coefficients of eq (1).
    AccelTemperature,
}

impl Section {
    /// All sections in file order.
    pub(crate) const ALL: [Section; 3] = [Section::Gyro, Section::Accel, Section::AccelTemperature];

    /// The table name in a file.
    pub(crate) fn key(self) -> &'static str {
        match self {
            Section::Gyro => "gyro",
            Section::Accel => "accel",
            Section::AccelTemperature => "accel_temperature",
        }
    }
}

/// Where a coefficient lives inside [`ImuErrorParams`]; the group order is the file order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Slot {
    GyroBias(usize),
    GyroScale(usize),
    GyroMisalignment(usize),
    AccelBias(usize),
    AccelScale(usize),
    AccelMisalignment(usize),
    TempBias(usize),
    TempScale(usize),
    TempMisalignment(usize),
}

impl Slot {
    /// Mutable access to the SI value.
    pub(crate) fn get_mut(self, p: &mut ImuErrorParams) -> &mut f64 {
        match self {
            Slot::GyroBias(i) => &mut p.gyro.bias_radps[i],
            Slot::GyroScale(i) => &mut p.gyro.scale[i],
            Slot::GyroMisalignment(i) => &mut p.gyro.misalignment_rad[i],
            Slot::AccelBias(i) => &mut p.accel.bias_mps2[i],
            Slot::AccelScale(i) => &mut p.accel.scale[i],
            Slot::AccelMisalignment(i) => &mut p.accel.misalignment_rad[i],
            Slot::TempBias(i) => &mut p.temperature.bias_mps2_per_degc[i],
            Slot::TempScale(i) => &mut p.temperature.scale_per_degc[i],
            Slot::TempMisalignment(i) => &mut p.temperature.misalignment_rad_per_degc[i],
        }
    }

    /// The SI value.
    pub(crate) fn get(self, p: &ImuErrorParams) -> f64 {
        let mut copy = *p;
        *self.get_mut(&mut copy)
    }
}

/// One coefficient definition.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CoefficientDef {
    /// Table in the file.
    pub(crate) section: Section,
    /// Key in that table (paper symbol with the unit in the name).
    pub(crate) key: &'static str,
    /// The paper's name, e.g. `"dM_ayx"`.
    pub(crate) name: &'static str,
    /// The paper's unit.
    pub(crate) unit: PaperUnit,
    /// Place in [`ImuErrorParams`].
    pub(crate) slot: Slot,
}

const fn def(
    section: Section,
    key: &'static str,
    name: &'static str,
    unit: PaperUnit,
    slot: Slot,
) -> CoefficientDef {
    CoefficientDef {
        section,
        key,
        name,
        unit,
        slot,
    }
}

use PaperUnit as U;
use Section::{Accel as A, AccelTemperature as T, Gyro as G};
use Slot::*;

/// The 33 coefficients in the state order of eq (8): the 21 constant ones (30-state model) first,
/// then the 12 temperature coefficients (42-state model).
pub(crate) const COEFFICIENTS: [CoefficientDef; 33] = [
    def(G, "B_x_deg_per_h", "B_gx", U::DegPerH, GyroBias(0)),
    def(G, "B_y_deg_per_h", "B_gy", U::DegPerH, GyroBias(1)),
    def(G, "B_z_deg_per_h", "B_gz", U::DegPerH, GyroBias(2)),
    def(A, "B_x_ug", "B_ax", U::Ug, AccelBias(0)),
    def(A, "B_y_ug", "B_ay", U::Ug, AccelBias(1)),
    def(A, "B_z_ug", "B_az", U::Ug, AccelBias(2)),
    def(G, "dK_x_ppm", "dK_gx", U::Ppm, GyroScale(0)),
    def(G, "dM_yx_arcsec", "dM_gyx", U::Arcsec, GyroMisalignment(0)),
    def(G, "dM_zx_arcsec", "dM_gzx", U::Arcsec, GyroMisalignment(1)),
    def(G, "dK_y_ppm", "dK_gy", U::Ppm, GyroScale(1)),
    def(G, "dM_zy_arcsec", "dM_gzy", U::Arcsec, GyroMisalignment(2)),
    def(G, "dK_z_ppm", "dK_gz", U::Ppm, GyroScale(2)),
    def(A, "dK_x_ppm", "dK_ax", U::Ppm, AccelScale(0)),
    def(A, "dM_yx_arcsec", "dM_ayx", U::Arcsec, AccelMisalignment(0)),
    def(A, "dM_zx_arcsec", "dM_azx", U::Arcsec, AccelMisalignment(1)),
    def(A, "dM_xy_arcsec", "dM_axy", U::Arcsec, AccelMisalignment(2)),
    def(A, "dK_y_ppm", "dK_ay", U::Ppm, AccelScale(1)),
    def(A, "dM_zy_arcsec", "dM_azy", U::Arcsec, AccelMisalignment(3)),
    def(A, "dM_xz_arcsec", "dM_axz", U::Arcsec, AccelMisalignment(4)),
    def(A, "dM_yz_arcsec", "dM_ayz", U::Arcsec, AccelMisalignment(5)),
    def(A, "dK_z_ppm", "dK_az", U::Ppm, AccelScale(2)),
    def(T, "TB_x_ug_per_degc", "TB_ax", U::UgPerDegC, TempBias(0)),
    def(T, "TB_y_ug_per_degc", "TB_ay", U::UgPerDegC, TempBias(1)),
    def(T, "TB_z_ug_per_degc", "TB_az", U::UgPerDegC, TempBias(2)),
    def(T, "TK_x_ppm_per_degc", "TK_ax", U::PpmPerDegC, TempScale(0)),
    def(T, "TK_y_ppm_per_degc", "TK_ay", U::PpmPerDegC, TempScale(1)),
    def(T, "TK_z_ppm_per_degc", "TK_az", U::PpmPerDegC, TempScale(2)),
    def(
        T,
        "TM_yx_arcsec_per_degc",
        "TM_ayx",
        U::ArcsecPerDegC,
        TempMisalignment(0),
    ),
    def(
        T,
        "TM_zx_arcsec_per_degc",
        "TM_azx",
        U::ArcsecPerDegC,
        TempMisalignment(1),
    ),
    def(
        T,
        "TM_xy_arcsec_per_degc",
        "TM_axy",
        U::ArcsecPerDegC,
        TempMisalignment(2),
    ),
    def(
        T,
        "TM_zy_arcsec_per_degc",
        "TM_azy",
        U::ArcsecPerDegC,
        TempMisalignment(3),
    ),
    def(
        T,
        "TM_xz_arcsec_per_degc",
        "TM_axz",
        U::ArcsecPerDegC,
        TempMisalignment(4),
    ),
    def(
        T,
        "TM_yz_arcsec_per_degc",
        "TM_ayz",
        U::ArcsecPerDegC,
        TempMisalignment(5),
    ),
];

/// The coefficients of one section in file order (bias, scale, misalignment; state order within).
pub(crate) fn section_defs(section: Section) -> Vec<&'static CoefficientDef> {
    let mut defs: Vec<_> = COEFFICIENTS
        .iter()
        .filter(|d| d.section == section)
        .collect();
    defs.sort_by_key(|d| d.slot);
    defs
}

/// One coefficient of a parameter set in the paper's name and unit, for reports.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coefficient {
    /// The paper's name, e.g. `"B_gx"`, `"dM_ayx"`, `"TK_az"`.
    pub name: &'static str,
    /// The paper's unit: `"deg/h"`, `"ppm"`, `"arcsec"`, `"ug"`, `"ug/degC"`, `"ppm/degC"` or
    /// `"arcsec/degC"`.
    pub unit: &'static str,
    /// The value in that unit.
    pub value: f64,
}

/// The coefficients of `params` in the state order of eq (8) (B_g, B_a, gyro scale and
/// misalignment, accelerometer scale and misalignment, then TB, TK, TM), in paper units: 21 entries
/// for a 30-state set, 33 for a 42-state set.
pub fn coefficient_table(params: &ImuErrorParams) -> Vec<Coefficient> {
    let n = params.model.n_states() - 9;
    COEFFICIENTS
        .iter()
        .take(n)
        .map(|d| Coefficient {
            name: d.name,
            unit: d.unit.label(),
            value: d.unit.from_si(d.slot.get(params)),
        })
        .collect()
}
