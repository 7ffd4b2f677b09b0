//! Gauss-Legendre quadrature on the unit interval, 1 to 8 nodes.
//!
//! The tables hold nodes `u_i = (1 + x_i)/2` in [0, 1] and weights `w_i/2` (summing to 1), where
//! `x_i`, `w_i` are the classical nodes and weights on [-1, 1]. They were computed with 60-digit
//! arithmetic (Newton iteration on the Legendre polynomials) and are printed with 21 significant
//! digits, so every entry is the correctly rounded f64. An n-node rule integrates polynomials of
//! degree 2n - 1 exactly: `∫_a^b f ≈ (b - a) Σ w_i f(a + u_i (b - a))`.

/// Largest supported number of nodes.
pub const MAX_NODES: usize = 8;

/// `(node in [0, 1], weight)` pairs for n = 1..=8 nodes, weights summing to 1.
const RULES: [&[(f64, f64)]; MAX_NODES] = [
    &[(0.5, 1.0)],
    &[(0.2113248654051871, 0.5), (0.7886751345948129, 0.5)],
    &[
        (0.11270166537925831, 0.2777777777777778),
        (0.5, 0.4444444444444444),
        (0.8872983346207417, 0.2777777777777778),
    ],
    &[
        (0.06943184420297371, 0.17392742256872692),
        (0.33000947820757187, 0.32607257743127305),
        (0.6699905217924281, 0.32607257743127305),
        (0.9305681557970263, 0.17392742256872692),
    ],
    &[
        (0.046910077030668004, 0.11846344252809454),
        (0.23076534494715845, 0.23931433524968324),
        (0.5, 0.28444444444444444),
        (0.7692346550528415, 0.23931433524968324),
        (0.953089922969332, 0.11846344252809454),
    ],
    &[
        (0.03376524289842399, 0.08566224618958518),
        (0.16939530676686773, 0.1803807865240693),
        (0.38069040695840156, 0.23395696728634552),
        (0.6193095930415985, 0.23395696728634552),
        (0.8306046932331322, 0.1803807865240693),
        (0.966234757101576, 0.08566224618958518),
    ],
    &[
        (0.025446043828620736, 0.06474248308443485),
        (0.12923440720030277, 0.13985269574463832),
        (0.2970774243113014, 0.19091502525255946),
        (0.5, 0.2089795918367347),
        (0.7029225756886985, 0.19091502525255946),
        (0.8707655927996972, 0.13985269574463832),
        (0.9745539561713793, 0.06474248308443485),
    ],
    &[
        (0.019855071751231884, 0.05061426814518813),
        (0.10166676129318664, 0.11119051722668724),
        (0.2372337950418355, 0.15685332293894363),
        (0.4082826787521751, 0.181341891689181),
        (0.591717321247825, 0.181341891689181),
        (0.7627662049581645, 0.15685332293894363),
        (0.8983332387068134, 0.11119051722668724),
        (0.9801449282487681, 0.05061426814518813),
    ],
];

/// The `n`-node Gauss-Legendre rule on [0, 1] as `(node, weight)` pairs, or `None` unless
/// `1 <= n <= 8`.
pub fn gauss_legendre_unit(n: usize) -> Option<&'static [(f64, f64)]> {
    n.checked_sub(1).and_then(|i| RULES.get(i)).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_are_exact_to_degree_2n_minus_1_and_not_beyond() {
        for n in 1..=MAX_NODES {
            let rule = gauss_legendre_unit(n).unwrap();
            assert_eq!(rule.len(), n);
            for deg in 0..2 * n {
                let q: f64 = rule.iter().map(|&(u, w)| w * u.powi(deg as i32)).sum();
                let exact = 1.0 / (deg as f64 + 1.0);
                assert!(
                    (q - exact).abs() < 4e-16,
                    "n={n} deg={deg}: {:e}",
                    q - exact
                );
            }
            let deg = 2 * n;
            let q: f64 = rule.iter().map(|&(u, w)| w * u.powi(deg as i32)).sum();
            assert!(
                (q - 1.0 / (deg as f64 + 1.0)).abs() > 1e-11,
                "n={n} too exact"
            );
        }
        assert!(gauss_legendre_unit(0).is_none());
        assert!(gauss_legendre_unit(9).is_none());
    }
}
