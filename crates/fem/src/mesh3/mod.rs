//! Tetrahedral meshes for 3D analyses (P1 `Tet4`, P2 `Tet10`, Gmsh node order; y is the
//! vertical axis, as in 2D): nodes, tetrahedra, named node, face and element sets.
//! [`TetrahedralMesh::block`] builds structured ones, [`TetrahedralMesh::extrude`]
//! extrudes a triangle mesh along z, [`TetrahedralMesh::from_msh`] reads Gmsh's.
use std::collections::{BTreeMap, HashMap};

use crate::element::tetrahedron::tetrahedron_jacobian_determinant;
use crate::element::ElementOrder;
use crate::error::MeshError;

mod block;
mod extrude;
mod msh;
mod sets;
mod submesh;

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

/// The local mid-edge nodes (`Tet10`) of each face's edges 01, 12, 20, in the order of
/// [`TETRAHEDRON_FACES`] (checked against `tet10::EDGES` in this module's tests).
pub const TETRAHEDRON_FACE_MID_NODES: [[usize; 3]; 4] =
    [[5, 8, 9], [7, 8, 6], [4, 9, 7], [6, 5, 4]];

/// The vertices of face `f` of `tetrahedron`, sorted: the same key from every element that
/// shares the face.
pub(crate) fn face_key(tetrahedron: &[usize], f: usize) -> [usize; 3] {
    let mut k = TETRAHEDRON_FACES[f].map(|v| tetrahedron[v]);
    k.sort_unstable();
    k
}

impl TetrahedralMesh {
    /// Node coordinates of tetrahedron `e`, in element node order.
    pub fn tetrahedron_coordinates(&self, e: usize) -> Vec<[f64; 3]> {
        self.tetrahedra[e].iter().map(|&n| self.nodes[n]).collect()
    }

    /// Face `f` of tetrahedron `e` as a boundary face: outward (its vertices in the order
    /// of [`TETRAHEDRON_FACES`]) with its mid-edge nodes in P2.
    pub fn boundary_face(&self, e: usize, f: usize) -> BoundaryFace {
        let t = &self.tetrahedra[e];
        let mut nodes: Vec<usize> = TETRAHEDRON_FACES[f].iter().map(|&v| t[v]).collect();
        if self.order == ElementOrder::P2 {
            nodes.extend(TETRAHEDRON_FACE_MID_NODES[f].iter().map(|&m| t[m]));
        }
        BoundaryFace { nodes }
    }

    /// The boundary: each face met by one tetrahedron only, by its sorted vertices
    /// ([`face_key`]), with that tetrahedron and its local face.
    pub(crate) fn boundary_face_owners(&self) -> HashMap<[usize; 3], (usize, usize)> {
        let mut seen: HashMap<[usize; 3], Option<(usize, usize)>> = HashMap::new();
        for (e, t) in self.tetrahedra.iter().enumerate() {
            for f in 0..4 {
                seen.entry(face_key(t, f))
                    .and_modify(|owner| *owner = None)
                    .or_insert(Some((e, f)));
            }
        }
        seen.into_iter()
            .filter_map(|(k, owner)| owner.map(|o| (k, o)))
            .collect()
    }

    /// `faces` as this mesh's boundary faces, each turned outward (with its mid-edge nodes
    /// in P2) whatever the order its nodes were given in, so that a pressure pushes into
    /// the body. A face with the wrong node count or an unknown node, an interior face and
    /// a triangle that is no face of the mesh are refused, naming `faces` and the face.
    pub fn orient_boundary_faces(
        &self,
        faces: &[BoundaryFace],
    ) -> Result<Vec<BoundaryFace>, MeshError> {
        let per_face = self.order.nodes_per_triangle();
        let owners = self.boundary_face_owners();
        faces
            .iter()
            .enumerate()
            .map(|(k, face)| {
                let n = &face.nodes;
                if n.len() != per_face || n.iter().any(|&v| v >= self.nodes.len()) {
                    return Err(MeshError::invalid(
                        "faces",
                        format!(
                            "face {k} {n:?} must have {per_face} nodes below {}",
                            self.nodes.len()
                        ),
                    ));
                }
                let mut key = [n[0], n[1], n[2]];
                key.sort_unstable();
                let &(e, f) = owners.get(&key).ok_or_else(|| {
                    MeshError::invalid(
                        "faces",
                        format!(
                            "face {k} (vertices {:?}) is not on the boundary of the mesh: an \
                             interior face, or no face of a tetrahedron",
                            &n[..3]
                        ),
                    )
                })?;
                Ok(self.boundary_face(e, f))
            })
            .collect()
    }

    /// Checks every tetrahedron: the right node count, known nodes, and `det J > 0` at its
    /// vertices and centroid (an inverted or flat element is refused, named by index).
    pub fn check_elements(&self) -> Result<(), MeshError> {
        self.check_elements_labelled(&|e| format!("tetrahedron {e}"))
    }

    /// [`check_elements`](Self::check_elements), each element named by `label(e)` (a
    /// reader names its file's tags).
    pub(crate) fn check_elements_labelled(
        &self,
        label: &dyn Fn(usize) -> String,
    ) -> Result<(), MeshError> {
        let per = self.order.nodes_per_tetrahedron();
        let reference = self.order.tetrahedron_reference_nodes();
        for (e, t) in self.tetrahedra.iter().enumerate() {
            let bad = |reason: String| MeshError::BadElement {
                element: label(e),
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::tet10::EDGES;

    #[test]
    fn face_mid_nodes_sit_on_their_face_edges() {
        for (f, vertices) in TETRAHEDRON_FACES.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (vertices[k], vertices[(k + 1) % 3]);
                let m = TETRAHEDRON_FACE_MID_NODES[f][k];
                let (i, j) = EDGES[m - 4];
                assert!((i, j) == (a, b) || (i, j) == (b, a), "face {f}, edge {k}");
            }
        }
    }
}
