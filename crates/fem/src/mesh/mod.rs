//! Triangle meshes in the plane (plane strain, thickness 1 m; coordinates in metres):
//! a structured generator, a Gmsh reader, named node, edge and element sets, and the
//! P1 → P2 conversion ([`Mesh::to_p2`]).
mod elevate;
mod graded;
pub(crate) mod msh;
mod quality;
pub(crate) mod rectangle;
mod sets;
pub(crate) mod submesh;

use std::collections::BTreeMap;

pub use graded::graded_coordinates;

use crate::element::ElementOrder;

/// An edge on which tractions act: 2 nodes (P1) or 3 (P2: end points, then the mid
/// point, Gmsh `Lin3` order). Edges found by [`Mesh::boundary_edges`] run counter-clockwise
/// around the domain, so the outward normal of `a → b` is `(b − a)` turned clockwise.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BoundaryEdge {
    pub nodes: Vec<usize>,
}

/// A triangle mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    pub order: ElementOrder,
    /// Node coordinates (m).
    pub nodes: Vec<[f64; 2]>,
    /// Node indices per triangle: 3 (P1) or 6 (P2), counter-clockwise, P2 mid-edge nodes in
    /// Gmsh order (edges 01, 12, 20).
    pub triangles: Vec<Vec<usize>>,
    /// Named node sets (sorted, no duplicates), e.g. for Dirichlet conditions.
    pub node_sets: BTreeMap<String, Vec<usize>>,
    /// Named edge sets, e.g. for tractions.
    pub edge_sets: BTreeMap<String, Vec<BoundaryEdge>>,
    /// Named element sets (indices into `triangles`, sorted, no duplicates), e.g. the
    /// soil layers of a Gmsh file's physical surfaces. A triangle may be in several sets,
    /// or in none.
    pub element_sets: BTreeMap<String, Vec<usize>>,
}

impl Mesh {
    /// Node coordinates of triangle `e`, in element node order (indices already checked).
    pub(crate) fn triangle_coordinates(&self, e: usize) -> Vec<[f64; 2]> {
        self.triangles[e].iter().map(|&n| self.nodes[n]).collect()
    }

    /// Physical position of the reference point `xi` of triangle `e` (m), e.g. to place
    /// plot samples; `None` if `e` is out of range.
    pub fn map_reference_point(&self, e: usize, xi: [f64; 2]) -> Option<[f64; 2]> {
        let tri = self.triangles.get(e)?;
        let n = self.order.shape_functions(xi);
        let mut x = [0.0; 2];
        for (&node, na) in tri.iter().zip(&n) {
            let p = self.nodes.get(node)?;
            x[0] += na * p[0];
            x[1] += na * p[1];
        }
        Some(x)
    }
}
