//! Quadrature rules on the reference tetrahedron (volume 1/6; weights sum to 1/6), chosen
//! as for triangles (`quadrature` module docs):
//! - P1: the centroid. `B` is constant, `Bᵀ C B` exact.
//! - P2: the 4-point degree-2 rule (`a = (5 − √5)/20`, weights 1/24). `B` is linear on an
//!   affine P2 tetrahedron, so `Bᵀ C B` is quadratic and exact; its 4 points are the
//!   element's stress points.
//! - Mass: `∫ N_a N_b` is of degree 4 for P2: the 14-point degree-5 rule with positive
//!   weights (Walkington 2000, "Quadrature on simplices of arbitrary dimension", CMU
//!   report 00-CNA-023; digits recomputed from its moment equations to 1e-40).
use crate::element::ElementOrder;

/// A rule: reference points `(ξ, η, ζ)` and weights.
#[derive(Debug, Clone, Copy)]
pub struct Rule3 {
    pub points: &'static [[f64; 3]],
    pub weights: &'static [f64],
}

const P1_POINTS: [[f64; 3]; 1] = [[0.25, 0.25, 0.25]];
const P1_WEIGHTS: [f64; 1] = [1.0 / 6.0];

// (5 − √5)/20 and (5 + 3√5)/20.
const A2: f64 = 0.138_196_601_125_010_5;
const B2: f64 = 0.585_410_196_624_968_5;
const P2_POINTS: [[f64; 3]; 4] = [[A2, A2, A2], [B2, A2, A2], [A2, B2, A2], [A2, A2, B2]];
const P2_WEIGHTS: [f64; 4] = [1.0 / 24.0; 4];

// Orbits in barycentric coordinates: (a, a, a, 1 − 3a) twice and (b, b, ½ − b, ½ − b).
const A5: f64 = 0.092_735_250_310_891_22;
const WA5: f64 = 0.012_248_840_519_393_659;
const C5: f64 = 0.310_885_919_263_300_6;
const WC5: f64 = 0.018_781_320_953_002_643;
const B5: f64 = 0.045_503_704_125_649_65;
const WB5: f64 = 0.007_091_003_462_846_911;
const D5: f64 = 0.5 - B5;
const DEG5_POINTS: [[f64; 3]; 14] = [
    // (ξ, η, ζ) = (λ₁, λ₂, λ₃); λ₀ = 1 − ξ − η − ζ.
    [A5, A5, A5],
    [1.0 - 3.0 * A5, A5, A5],
    [A5, 1.0 - 3.0 * A5, A5],
    [A5, A5, 1.0 - 3.0 * A5],
    [C5, C5, C5],
    [1.0 - 3.0 * C5, C5, C5],
    [C5, 1.0 - 3.0 * C5, C5],
    [C5, C5, 1.0 - 3.0 * C5],
    // the 6 placements of the pair {b, b} among the 4 barycentric coordinates
    [B5, B5, D5],
    [B5, D5, B5],
    [D5, B5, B5],
    [B5, D5, D5],
    [D5, B5, D5],
    [D5, D5, B5],
];
const DEG5_WEIGHTS: [f64; 14] = [
    WA5, WA5, WA5, WA5, WC5, WC5, WC5, WC5, WB5, WB5, WB5, WB5, WB5, WB5,
];

/// The stiffness rule of a tetrahedron order: its points are the mesh's stress points.
pub fn stiffness_rule(order: ElementOrder) -> Rule3 {
    match order {
        ElementOrder::P1 => Rule3 {
            points: &P1_POINTS,
            weights: &P1_WEIGHTS,
        },
        ElementOrder::P2 => Rule3 {
            points: &P2_POINTS,
            weights: &P2_WEIGHTS,
        },
    }
}

/// Degree-5 rule, exact for the consistent mass `∫ N_a N_b` of affine P2 tetrahedra.
pub fn mass_rule() -> Rule3 {
    Rule3 {
        points: &DEG5_POINTS,
        weights: &DEG5_WEIGHTS,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ ξ^i η^j ζ^k over the reference tetrahedron = i! j! k! / (i + j + k + 3)!.
    fn exact(i: u32, j: u32, k: u32) -> f64 {
        let f = |n: u32| (1..=n).map(f64::from).product::<f64>();
        f(i) * f(j) * f(k) / f(i + j + k + 3)
    }

    fn integrate(rule: Rule3, i: u32, j: u32, k: u32) -> f64 {
        rule.points
            .iter()
            .zip(rule.weights)
            .map(|(p, w)| w * p[0].powi(i as i32) * p[1].powi(j as i32) * p[2].powi(k as i32))
            .sum()
    }

    #[test]
    fn tetrahedron_rules_are_exact_to_their_degree() {
        for (rule, degree) in [
            (stiffness_rule(ElementOrder::P1), 1),
            (stiffness_rule(ElementOrder::P2), 2),
            (mass_rule(), 5),
        ] {
            assert!(rule.weights.iter().all(|w| *w > 0.0));
            for i in 0..=degree {
                for j in 0..=degree - i {
                    for k in 0..=degree - i - j {
                        let (q, e) = (integrate(rule, i, j, k), exact(i, j, k));
                        assert!(
                            (q - e).abs() < 1e-16,
                            "degree {degree}: ξ^{i} η^{j} ζ^{k}: {q} vs {e}"
                        );
                    }
                }
            }
            // and not beyond: each rule misses a monomial of the next degree.
            let next = degree + 1;
            assert!((integrate(rule, next, 0, 0) - exact(next, 0, 0)).abs() > 1e-7);
        }
    }
}
