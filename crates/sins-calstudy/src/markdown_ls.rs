//! Section 5 of the report: the least-squares baseline and the Table 3 comparison.

use crate::format::{clean, decimals_for, fixed, sig};
use crate::study::Study;
use sins_config::markdown::Align::{Left, Right};
use sins_config::markdown::Table;
use std::fmt::Write;

/// Append the least-squares section.
pub(crate) fn least_squares(o: &mut String, s: &Study) {
    let l = &s.ls_baseline;
    let t = &s.table3;
    let _ = writeln!(
        o,
        "## 5. Least-squares baseline vs the proposed method (Table 3)\n"
    );
    let _ = writeln!(
        o,
        "`{}`: a 30-state calibration at each stable chamber temperature ({:.2} h calibrated in all, plus {} h settling per point, not simulated), then a straight line of each constant against the mean temperature of the accelerometer that scales it.\n",
        l.experiment, l.calibrated_h, l.settling_h
    );
    let mut table = Table::new([
        "run",
        "seed",
        "chamber (degC)",
        "T_x",
        "T_y",
        "T_z",
        "max |error|/σ vs truth at T",
    ])
    .align(&[Left, Right, Right, Right, Right, Right, Right]);
    for p in &l.points {
        let m = p.mean_temp_degc;
        table.row([
            p.run.to_string(),
            p.seed.to_string(),
            p.chamber_degc.to_string(),
            format!("{:.2}", m[0]),
            format!("{:.2}", m[1]),
            format!("{:.2}", m[2]),
            format!("{:.2}", p.max_abs_z),
        ]);
    }
    o.push_str(&table.render());
    let _ = writeln!(
        o,
        "\nRegressor: eq (1) multiplies column j of the temperature matrix by accelerometer j's temperature, so each installation error dM_a(i,j) (axis j's input seen by accelerometer i) is fitted against T_j, like the bias and scale factor of accelerometer j. At stable temperatures every accelerometer sits at chamber + its constant offset, so the slope is the same whichever accelerometer's temperature is used; only the intercept (the constant at the reference temperature) depends on the choice.\n"
    );
    let mut table = Table::new([
        "coefficient",
        "unit",
        "fitted constant",
        "regressor",
        "slope",
        "1σ",
        "constant at T_ref",
        "residual RMS",
    ])
    .align(&[Left, Left, Left, Left, Right, Right, Right, Right]);
    for c in &l.coefficients {
        let d = decimals_for(c.slope_sigma);
        table.row([
            c.name.to_string(),
            c.unit.to_string(),
            c.constant.to_string(),
            c.regressor.to_string(),
            fixed(c.slope, d),
            fixed(c.slope_sigma, d),
            sig(c.constant_at_reference, 4),
            sig(c.residual_rms, 2),
        ]);
    }
    o.push_str(&table.render());
    let _ = writeln!(
        o,
        "\nTable 3 on the same truth IMU (the paper's proposed-method values as the truth). Proposed: one 42-state calibration of `{}` (seed {}); least squares: one run per temperature point. Each error is a single draw: compare it with its 1σ (seed {} has the same sensor noise as the Monte Carlo's seed {}, whose errors are in section 1).\n",
        t.proposed_experiment, t.proposed_seed, t.proposed_seed, t.proposed_seed
    );
    let mut table = Table::new([
        "coefficient",
        "unit",
        "truth",
        "proposed (ours)",
        "LS (ours)",
        "paper proposed",
        "paper LS",
        "proposed − truth",
        "LS − truth",
    ])
    .align(&[Left, Left, Right, Right, Right, Right, Right, Right, Right]);
    for e in &t.entries {
        let d = decimals_for(e.proposed_sigma.min(e.ls_sigma));
        table.row([
            e.name.to_string(),
            e.unit.to_string(),
            clean(e.truth),
            format!("{} ± {}", fixed(e.proposed, d), fixed(e.proposed_sigma, d)),
            format!("{} ± {}", fixed(e.ls, d), fixed(e.ls_sigma, d)),
            e.paper_proposed.to_string(),
            e.paper_ls.to_string(),
            fixed(e.proposed_error, d),
            fixed(e.ls_error, d),
        ]);
    }
    o.push_str(&table.render());
    // The total row is written by hand: its empty cells have always been `| |`, where the
    // table would write `|  |`.
    let _ = writeln!(
        o,
        "| calibration time | h | | {:.1} | {:.1} | 4.2 | 28.8 | | |",
        t.proposed_time_h, t.ls_time_h
    );
    let _ = writeln!(
        o,
        "\nThe proposed method is closer to the truth for {} of 12 coefficients. RMS of error/σ: proposed {}, least squares {}; RMS of error/truth: proposed {}, least squares {}. Calibration time: {:.1} h against {:.1} h.\n",
        t.proposed_closer,
        fixed(t.proposed_rms_z, 2),
        fixed(t.ls_rms_z, 2),
        sig(t.proposed_rms_relative, 2),
        sig(t.ls_rms_relative, 2),
        t.proposed_time_h,
        t.ls_time_h
    );
    let data = l.calibrated_h / t.proposed_time_h;
    let ratio = t.ls_time_h / t.proposed_time_h;
    let _ = writeln!(
        o,
        "The least-squares 1σ is a median {} of the proposed one, with {} times the calibrated data ({:.1} h against {:.1} h; σ ∝ 1/√time predicts {}). In the {:.1} h the baseline takes, the proposed 4.2 h calibration fits {} times. The simulated IMU is exactly linear in temperature and fully settled at every point, the baseline's ideal case: the paper's large LS departures from its proposed values (e.g. TB_az −29.38 against −25.45 ug/degC) are not reproduced by such an IMU, so they must come from effects this model leaves out (incomplete settling, thermal gradients, non-linear temperature dependence); the paper does not say which.\n",
        sig(t.median_sigma_ratio_ls_over_proposed, 2),
        sig(data, 3),
        l.calibrated_h,
        t.proposed_time_h,
        sig(data.sqrt().recip(), 2),
        t.ls_time_h,
        sig(ratio, 3)
    );
}
