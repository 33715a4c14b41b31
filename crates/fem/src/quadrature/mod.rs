//! Quadrature rules on the reference triangle (area 1/2; weights sum to 1/2) and on the
//! unit interval (weights sum to 1).
//!
//! Choice of the stiffness ("Gauss point") rule, which also fixes where stresses live:
//! - P1: one point at the centroid. `B` is constant, so `Bᵀ C B` is integrated exactly.
//! - P2: the 3-point degree-2 rule. `B` is linear on an affine P2 triangle, so `Bᵀ C B` is
//!   quadratic and integrated exactly; on curved (isoparametric) triangles `∂N/∂x · det J`
//!   is still quadratic, so `Σ_p V_p B_pᵀ σ` for a constant `σ` stays exact (patch test).
//!   `det J` is at most quadratic too, so `Σ V_p` is the exact area.
//!
//! The lumped mass needs `∫ N_a²` (degree 4 for P2): it uses the 7-point degree-5 rule.
//!
//! Rules on the reference tetrahedron, for 3D meshes: [`tetrahedron`].
use crate::element::ElementOrder;

pub mod tetrahedron;

/// A rule: reference points `(ξ, η)` and weights.
#[derive(Debug, Clone, Copy)]
pub struct Rule {
    pub points: &'static [[f64; 2]],
    pub weights: &'static [f64],
}

const P1_POINTS: [[f64; 2]; 1] = [[1.0 / 3.0, 1.0 / 3.0]];
const P1_WEIGHTS: [f64; 1] = [0.5];

const P2_POINTS: [[f64; 2]; 3] = [
    [1.0 / 6.0, 1.0 / 6.0],
    [2.0 / 3.0, 1.0 / 6.0],
    [1.0 / 6.0, 2.0 / 3.0],
];
const P2_WEIGHTS: [f64; 3] = [1.0 / 6.0; 3];

// Radon's 7-point degree-5 rule: a = (6 − √15)/21, b = (6 + √15)/21, weights (per unit
// area) 9/40 and (155 ∓ √15)/1200. Written in decimals because `sqrt` is not const.
const SQRT15: f64 = 3.872_983_346_207_417;
const A5: f64 = (6.0 - SQRT15) / 21.0;
const B5: f64 = (6.0 + SQRT15) / 21.0;
const WA5: f64 = (155.0 - SQRT15) / 2400.0;
const WB5: f64 = (155.0 + SQRT15) / 2400.0;
const DEG5_POINTS: [[f64; 2]; 7] = [
    [1.0 / 3.0, 1.0 / 3.0],
    [A5, A5],
    [1.0 - 2.0 * A5, A5],
    [A5, 1.0 - 2.0 * A5],
    [B5, B5],
    [1.0 - 2.0 * B5, B5],
    [B5, 1.0 - 2.0 * B5],
];
const DEG5_WEIGHTS: [f64; 7] = [9.0 / 80.0, WA5, WA5, WA5, WB5, WB5, WB5];

/// The stiffness rule of an element order: its points are the mesh's Gauss points.
pub fn stiffness_rule(order: ElementOrder) -> Rule {
    match order {
        ElementOrder::P1 => Rule {
            points: &P1_POINTS,
            weights: &P1_WEIGHTS,
        },
        ElementOrder::P2 => Rule {
            points: &P2_POINTS,
            weights: &P2_WEIGHTS,
        },
    }
}

/// Degree-5 rule, exact for the consistent mass `∫ N_a N_b` of affine P2 triangles.
pub fn mass_rule() -> Rule {
    Rule {
        points: &DEG5_POINTS,
        weights: &DEG5_WEIGHTS,
    }
}

// 3-point Gauss-Legendre on [0, 1] (degree 5): exact for `∫ N_a ds` on straight P2 edges.
const GL3_POINTS: [f64; 3] = [
    0.5 - 0.387_298_334_620_741_7, // 0.5 − √(3/5)/2
    0.5,
    0.5 + 0.387_298_334_620_741_7,
];
const GL3_WEIGHTS: [f64; 3] = [5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0];

/// Gauss-Legendre points and weights on `[0, 1]` for edge integrals.
pub fn edge_rule() -> (&'static [f64], &'static [f64]) {
    (&GL3_POINTS, &GL3_WEIGHTS)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ ξ^i η^j over the reference triangle = i! j! / (i + j + 2)!.
    fn exact(i: u32, j: u32) -> f64 {
        let f = |n: u32| (1..=n).map(f64::from).product::<f64>();
        f(i) * f(j) / f(i + j + 2)
    }

    fn integrate(rule: Rule, i: u32, j: u32) -> f64 {
        rule.points
            .iter()
            .zip(rule.weights)
            .map(|(p, w)| w * p[0].powi(i as i32) * p[1].powi(j as i32))
            .sum()
    }

    #[test]
    fn triangle_rules_are_exact_to_their_degree() {
        for (rule, degree) in [
            (stiffness_rule(ElementOrder::P1), 1),
            (stiffness_rule(ElementOrder::P2), 2),
            (mass_rule(), 5),
        ] {
            for i in 0..=degree {
                for j in 0..=degree - i {
                    let (q, e) = (integrate(rule, i, j), exact(i, j));
                    assert!(
                        (q - e).abs() < 1e-15,
                        "degree {degree}: ξ^{i} η^{j}: {q} vs {e}"
                    );
                }
            }
        }
        // and not beyond: the P2 rule misses a cubic, so "degree 2" is the real claim.
        let r = stiffness_rule(ElementOrder::P2);
        assert!((integrate(r, 3, 0) - exact(3, 0)).abs() > 1e-4);
    }

    #[test]
    fn edge_rule_is_exact_to_degree_five() {
        let (p, w) = edge_rule();
        for k in 0..=5 {
            let q: f64 = p.iter().zip(w).map(|(s, w)| w * s.powi(k)).sum();
            assert!((q - 1.0 / f64::from(k as u32 + 1)).abs() < 1e-15, "s^{k}");
        }
    }
}
