//! Tetrahedral meshes for 3D analyses (P1 `Tet4`, P2 `Tet10`, Gmsh node order; y is the
//! vertical axis, as in 2D): nodes, tetrahedra, named node, face and element sets.
//! [`TetrahedralMesh::block`] builds structured ones, [`TetrahedralMesh::from_msh`] reads
//! Gmsh's.
use std::collections::BTreeMap;

use crate::element::tetrahedron::tetrahedron_jacobian_determinant;
use crate::element::ElementOrder;
use crate::error::MeshError;

mod block;
mod msh;

/// A boundary triangle: its 3 vertices (P1) or 3 vertices then the mid-edge nodes of its
/// edges 01, 12, 20 (P2), counter-clockwise seen from outside the body (outward normal).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BoundaryFace {
    pub nodes: Vec<usize>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct TetrahedralMesh {
    pub order: ElementOrder,
    /// Node coordinates (m).
    pub nodes: Vec<[f64; 3]>,
    /// Node indices per tetrahedron: 4 (P1) or 10 (P2), in Gmsh order with a direct
    /// vertex triad (`element::tetrahedron`).
    pub tetrahedra: Vec<Vec<usize>>,
    /// Named node sets (sorted, no duplicates), e.g. for Dirichlet conditions.
    pub node_sets: BTreeMap<String, Vec<usize>>,
    /// Named face sets, e.g. for tractions and pressures.
    pub face_sets: BTreeMap<String, Vec<BoundaryFace>>,
    /// Named element sets (indices into `tetrahedra`, sorted), e.g. soil layers.
    pub element_sets: BTreeMap<String, Vec<usize>>,
}

/// The faces of a tetrahedron as local vertex indices, each counter-clockwise seen from
/// outside a tetrahedron whose vertex triad is direct: face `f` is opposite vertex `f`.
pub const TETRAHEDRON_FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

impl TetrahedralMesh {
    /// Node coordinates of tetrahedron `e`, in element node order.
    pub fn tetrahedron_coordinates(&self, e: usize) -> Vec<[f64; 3]> {
        self.tetrahedra[e].iter().map(|&n| self.nodes[n]).collect()
    }

    /// Checks every tetrahedron: the right node count, known nodes, and `det J > 0` at its
    /// vertices and centroid (an inverted or flat element is refused, named by index).
    pub fn check_elements(&self) -> Result<(), MeshError> {
        let per = self.order.nodes_per_tetrahedron();
        let reference = self.order.tetrahedron_reference_nodes();
        for (e, t) in self.tetrahedra.iter().enumerate() {
            let bad = |reason: String| MeshError::BadElement {
                element: format!("tetrahedron {e}"),
                reason,
            };
            if t.len() != per {
                return Err(bad(format!(
                    "{} nodes, a {:?} tetrahedron has {per}",
                    t.len(),
                    self.order
                )));
            }
            if let Some(n) = t.iter().find(|&&n| n >= self.nodes.len()) {
                return Err(bad(format!(
                    "node {n} of {} does not exist",
                    self.nodes.len()
                )));
            }
            let x = self.tetrahedron_coordinates(e);
            for xi in reference[..4].iter().chain([&[0.25; 3]]) {
                let det = tetrahedron_jacobian_determinant(self.order, &x, *xi);
                if !(det.is_finite() && det > 0.0) {
                    return Err(bad(format!(
                        "det J = {det:e} at reference point {xi:?}: inverted or flat"
                    )));
                }
            }
        }
        Ok(())
    }
}
