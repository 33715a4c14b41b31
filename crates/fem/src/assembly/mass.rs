//! Lumped (diagonal) mass `M` of eq. 11–12 (kg per metre of thickness), per dof: both
//! components of a node get the node's mass.
//!
//! - P1: row sum of the consistent mass, `m_a = ρ ∫ N_a` (= ρA/3 per vertex).
//! - P2: row sums give zero vertex masses (`∫ N_vertex = 0`), which `M⁻¹` cannot take;
//!   HRZ lumping scales the consistent diagonal instead, `m_a = m_e ∫N_a² / Σ_b ∫N_b²`
//!   (vertex 1/19 and mid node 16/57 of the element mass on affine triangles), all
//!   positive and summing to `m_e = ρ ∫ det J`.
//!
//! Axisymmetric (`docs/axisymmetry.md`): every integral carries `r` (kg per radian). P1:
//! the one-point rule gives `ρ r_c A / 3` per vertex (the element's mass `ρ r_c A` is exact;
//! a vertex on the axis keeps a positive mass). P2: `m_e = ρ ∫ r det J` and the HRZ
//! weights `∫ N_a² r det J` (degree 5 on affine triangles, exact with the 7-point rule).
use super::gauss::GaussData;
use crate::element::{map_point, ElementOrder};
use crate::error::MeshError;
use crate::mesh::Mesh;
use crate::quadrature::mass_rule;

/// Mass per node.
pub(crate) fn nodal_masses(
    mesh: &Mesh,
    gauss: &GaussData,
    density: f64,
) -> Result<Vec<f64>, MeshError> {
    let mut m = vec![0.0; mesh.nodes.len()];
    match mesh.order {
        ElementOrder::P1 => {
            for p in 0..gauss.len() {
                let v = gauss.volumes[p];
                for (node, n, _) in gauss.point(p) {
                    m[node] += density * v * n;
                }
            }
        }
        ElementOrder::P2 => {
            let mut element_mass = vec![0.0; mesh.triangles.len()];
            for (p, &e) in gauss.elements.iter().enumerate() {
                element_mass[e] += density * gauss.volumes[p];
            }
            let rule = mass_rule();
            for (e, tri) in mesh.triangles.iter().enumerate() {
                let coords = mesh.triangle_coordinates(e);
                let mut diag = [0.0; 6];
                for (xi, w) in rule.points.iter().zip(rule.weights) {
                    let mp = map_point(mesh.order, &coords, *xi).ok_or_else(|| {
                        MeshError::element(
                            format!("triangle {e}"),
                            format!("det J ≤ 0 at mass quadrature point {xi:?}"),
                        )
                    })?;
                    let weight = gauss.geometry.weight(mp.position);
                    for (d, n) in diag.iter_mut().zip(&mp.shape) {
                        *d += w * mp.det_j * n * n * weight;
                    }
                }
                let total: f64 = diag.iter().sum();
                for (&node, d) in tri.iter().zip(diag) {
                    m[node] += element_mass[e] * d / total;
                }
            }
        }
    }
    Ok(m)
}
