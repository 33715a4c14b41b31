//! Selections of a tetrahedral mesh by box (a scene's `[[boundary]]` nodes and its face
//! loads' `faces`), as `mesh/sets.rs` selects nodes and edges of a triangle mesh: a point
//! is in the box within 1e-9 of the mesh's largest side.
use super::{BoundaryFace, TetrahedralMesh};
use crate::error::MeshError;

impl TetrahedralMesh {
    /// Every boundary face (met by one tetrahedron only), outward, with its mid-edge nodes
    /// in P2, in the order of its tetrahedron and local face.
    pub fn boundary_faces(&self) -> Vec<BoundaryFace> {
        let mut owners: Vec<(usize, usize)> = self.boundary_face_owners().into_values().collect();
        owners.sort_unstable();
        owners
            .into_iter()
            .map(|(e, f)| self.boundary_face(e, f))
            .collect()
    }

    /// Nodes within the box `[min, max]`; an empty selection or a bad box is an error.
    pub fn nodes_in_box(&self, min: [f64; 3], max: [f64; 3]) -> Result<Vec<usize>, MeshError> {
        let inside = self.box_predicate(min, max)?;
        let nodes: Vec<usize> = (0..self.nodes.len())
            .filter(|&i| inside(self.nodes[i]))
            .collect();
        if nodes.is_empty() {
            return Err(empty("node", min, max));
        }
        Ok(nodes)
    }

    /// Boundary faces ([`boundary_faces`](Self::boundary_faces)) whose nodes all lie in the
    /// box (same tolerance as [`nodes_in_box`](Self::nodes_in_box)). Errors as there.
    pub fn boundary_faces_in_box(
        &self,
        min: [f64; 3],
        max: [f64; 3],
    ) -> Result<Vec<BoundaryFace>, MeshError> {
        let inside = self.box_predicate(min, max)?;
        let faces: Vec<BoundaryFace> = self
            .boundary_faces()
            .into_iter()
            .filter(|f| {
                f.nodes
                    .iter()
                    .all(|&n| self.nodes.get(n).is_some_and(|&p| inside(p)))
            })
            .collect();
        if faces.is_empty() {
            return Err(empty("boundary face", min, max));
        }
        Ok(faces)
    }

    fn box_predicate(
        &self,
        min: [f64; 3],
        max: [f64; 3],
    ) -> Result<impl Fn([f64; 3]) -> bool, MeshError> {
        if !min.iter().chain(&max).all(|v| v.is_finite()) || (0..3).any(|k| min[k] > max[k]) {
            return Err(MeshError::invalid(
                "box",
                format!("min = {min:?}, max = {max:?} must be finite with min ≤ max"),
            ));
        }
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &self.nodes {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max);
        let tol = if size.is_finite() && size > 0.0 {
            1e-9 * size
        } else {
            0.0
        };
        Ok(move |p: [f64; 3]| (0..3).all(|k| p[k] >= min[k] - tol && p[k] <= max[k] + tol))
    }
}

fn empty(what: &str, min: [f64; 3], max: [f64; 3]) -> MeshError {
    MeshError::invalid(
        "box",
        format!("no {what} lies in the box from {min:?} to {max:?}"),
    )
}
