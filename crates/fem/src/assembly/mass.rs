//! Lumped (diagonal) mass `M` of eq. 11–12 (kg per metre of thickness; kg in 3D), per
//! dof: every component of a node gets the node's mass.
//!
//! - P1: row sum of the consistent mass, `m_a = ρ ∫ N_a` (= ρA/3 per vertex).
//! - P2: row sums give zero vertex masses (`∫ N_vertex = 0`), which `M⁻¹` cannot take;
//!   HRZ lumping scales the consistent diagonal instead, `m_a = m_e ∫N_a² / Σ_b ∫N_b²`
//!   (vertex 1/19 and mid node 16/57 of the element mass on affine triangles), all
//!   positive and summing to `m_e = ρ ∫ det J`. P1 tetrahedra get `m_e/4` per vertex;
//!   P2 tetrahedra `m_e/36` per vertex and `4 m_e/27` per mid-edge node, from
//!   `∫N_v² = V/70` and `∫N_e² = 8V/105` (the 14-point rule is exact on them).
//!
//! Axisymmetric (`docs/axisymmetry.md`): every integral carries `r` (kg per radian). P1:
//! the one-point rule gives `ρ r_c A / 3` per vertex (the element's mass `ρ r_c A` is exact;
//! a vertex on the axis keeps a positive mass). P2: `m_e = ρ ∫ r det J` and the HRZ
//! weights `∫ N_a² r det J` (degree 5 on affine triangles, exact with the 7-point rule).
//!
//! A density varying in space (soil layers, [`Assembly::with_point_densities`]) is taken
//! at the Gauss points and goes inside the integral: P1 `m_a = Σ_p ρ_p V_p N_a(x_p)`; P2
//! `m_e = Σ_p ρ_p V_p` over the element's points, with the same HRZ weights (they depend
//! on the shape functions only). A uniform density makes the same operations as before.
//!
//! [`Assembly::with_point_densities`]: super::Assembly::with_point_densities
use super::gauss::GaussData;
use crate::dimension::ElementMesh;
use crate::element::ElementOrder;
use crate::error::{FemError, MeshError};

/// Whether a density of 0 is accepted: not for the mass (it is inverted), yes for a
/// weight (weightless soil).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Zero {
    Refused,
    Accepted,
}

/// Checks one density per Gauss point (`n_points` of them), each finite and > 0 (or ≥ 0
/// with [`Zero::Accepted`]); errors name `densities`, the expected length, the first bad
/// index and its value.
pub(crate) fn check_densities(
    densities: &[f64],
    n_points: usize,
    zero: Zero,
) -> Result<(), FemError> {
    if densities.len() != n_points {
        return Err(FemError::invalid(
            "densities",
            format!(
                "{} values, expected {n_points}: one per Gauss point, in the order of \
                 `gauss_points`",
                densities.len()
            ),
        ));
    }
    let ok = |rho: f64| {
        rho.is_finite()
            && match zero {
                Zero::Refused => rho > 0.0,
                Zero::Accepted => rho >= 0.0,
            }
    };
    if let Some((p, rho)) = densities.iter().enumerate().find(|(_, &rho)| !ok(rho)) {
        let bound = match zero {
            Zero::Refused => "> 0 (the lumped mass is inverted)",
            Zero::Accepted => "≥ 0",
        };
        return Err(FemError::invalid(
            "densities",
            format!(
                "densities[{p}] = {rho} kg/m³ (Gauss point {p} of {n_points}) must be finite \
                 and {bound}"
            ),
        ));
    }
    Ok(())
}

/// Mass per node, `density(p)` the density (kg/m³) at Gauss point `p`.
pub(crate) fn nodal_masses<M: ElementMesh>(
    mesh: &M,
    gauss: &GaussData,
    density: impl Fn(usize) -> f64,
) -> Result<Vec<f64>, MeshError> {
    let mut m = vec![0.0; mesh.node_positions().len()];
    match mesh.order() {
        ElementOrder::P1 => {
            for p in 0..gauss.len() {
                let rho = density(p);
                let v = gauss.volumes[p];
                for (node, n, _) in gauss.point(p) {
                    m[node] += rho * v * n;
                }
            }
        }
        ElementOrder::P2 => {
            let elements = mesh.elements();
            let mut element_mass = vec![0.0; elements.len()];
            for (p, &e) in gauss.elements.iter().enumerate() {
                element_mass[e] += density(p) * gauss.volumes[p];
            }
            for (e, nodes) in elements.iter().enumerate() {
                let diag = mesh.mass_diagonal(e, gauss.geometry)?;
                let total: f64 = diag.iter().sum();
                for (&node, d) in nodes.iter().zip(diag) {
                    m[node] += element_mass[e] * d / total;
                }
            }
        }
    }
    Ok(m)
}
