//! Straight-line least-squares fit `y = intercept + slope · x` (the paper's four-temperature
//! baseline fits each coefficient against temperature).

/// Result of a straight-line fit.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LineFit {
    /// Slope dy/dx.
    pub slope: f64,
    /// Value at x = 0.
    pub intercept: f64,
    /// 1-sigma of the slope propagated from the 1-sigma of each y (0 when none given).
    pub slope_sigma: f64,
    /// RMS of the fit residuals `y − fit(x)`.
    pub residual_rms: f64,
}

impl LineFit {
    /// The fitted line at `x`.
    pub fn at(&self, x: f64) -> f64 {
        self.intercept + self.slope * x
    }
}

/// Ordinary least-squares line through the points `(x[i], y[i])` (every point weighted
/// equally, as the paper's baseline does); `y_sigma` (same length) gives the slope's 1-sigma
/// `sqrt(Σ (x_i − x̄)² σ_i²) / Σ (x_i − x̄)²`. `None` for fewer than two points, unequal
/// lengths, non-finite input or all x equal.
pub fn fit_line(x: &[f64], y: &[f64], y_sigma: Option<&[f64]>) -> Option<LineFit> {
    let n = x.len();
    if n < 2 || y.len() != n || y_sigma.is_some_and(|s| s.len() != n) {
        return None;
    }
    if !x.iter().chain(y).all(|v| v.is_finite()) {
        return None;
    }
    let nf = n as f64;
    let xm = x.iter().sum::<f64>() / nf;
    let ym = y.iter().sum::<f64>() / nf;
    let sxx: f64 = x.iter().map(|v| (v - xm).powi(2)).sum();
    if sxx.is_nan() || sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - xm) * (b - ym)).sum();
    let slope = sxy / sxx;
    let intercept = ym - slope * xm;
    let slope_sigma = y_sigma.map_or(0.0, |s| {
        x.iter()
            .zip(s)
            .map(|(a, si)| ((a - xm) * si).powi(2))
            .sum::<f64>()
            .sqrt()
            / sxx
    });
    let residual_rms = (x
        .iter()
        .zip(y)
        .map(|(a, b)| (b - (intercept + slope * a)).powi(2))
        .sum::<f64>()
        / nf)
        .sqrt();
    Some(LineFit {
        slope,
        intercept,
        slope_sigma,
        residual_rms,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_line_exactly_and_propagates_sigma() {
        // The baseline's geometry: four chamber points 10..40 degC plus an axis offset.
        let x = [10.5, 20.5, 30.5, 40.5];
        let y: Vec<f64> = x.iter().map(|t| 1.25 - 25.45 * (t - 20.0)).collect();
        let f = fit_line(&x, &y, Some(&[2.0; 4])).expect("fit");
        assert!((f.slope + 25.45).abs() < 1e-12, "{}", f.slope);
        assert!((f.at(20.0) - 1.25).abs() < 1e-11, "{}", f.at(20.0));
        assert!(f.residual_rms < 1e-12);
        // Σ(x − x̄)² = 500: σ_slope = 2 · sqrt(500) / 500.
        assert!((f.slope_sigma - 2.0 / 500f64.sqrt()).abs() < 1e-15);
        // A point off the line: slope moves by its leverage (x_i − x̄)/Sxx · δy.
        let mut y2 = y.clone();
        y2[3] += 1.0;
        let g = fit_line(&x, &y2, None).expect("fit");
        assert!((g.slope - f.slope - 15.0 / 500.0).abs() < 1e-12);
        assert!(fit_line(&[1.0, 1.0], &[0.0, 1.0], None).is_none());
        assert!(fit_line(&[1.0], &[0.0], None).is_none());
    }
}
