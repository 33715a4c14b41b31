//! The mesh of part of the tetrahedra: what remains of a 3D body after a region is dug out
//! (construction in stages), as `mesh/submesh.rs` is for triangles; the forces and the
//! state that go with it are in `crate::excavation`.
use std::collections::HashSet;

use super::{face_key, BoundaryFace, TetrahedralMesh};
use crate::error::MeshError;
use crate::mesh::submesh::Part;

impl TetrahedralMesh {
    /// The mesh of the tetrahedra `elements` (indices into
    /// [`tetrahedra`](Self::tetrahedra), in any order, each once), with only the nodes they
    /// use, and the map from each node of `self` to its index in the submesh (`None`: the
    /// node is gone). As [`Mesh::submesh`](crate::Mesh::submesh):
    ///
    /// - Tetrahedra keep their node order and come in increasing old index, so their
    ///   Gauss points are those of the old ones, in the same order (`crate::excavation`).
    /// - Nodes are the ones the kept tetrahedra use, in increasing old index.
    /// - Node and element sets keep their kept members, renumbered (still sorted).
    /// - Face sets keep the faces that are still a face of a kept tetrahedron, in their
    ///   own orientation, renumbered: after an excavation `faces = "top"` loads what is
    ///   left of the top, never the air over the pit. The faces the excavation lays bare
    ///   join no set (name them beforehand, as a Gmsh physical surface, to load them).
    /// - A set left empty is kept, empty, under its name.
    ///
    /// The result passes [`check_elements`](Self::check_elements) when `self` does
    /// (checked). Errors: `self` fails it; `elements` is empty, or names a tetrahedron out
    /// of range or twice (the error names `elements`, the entry and the tetrahedron).
    pub fn submesh(
        &self,
        elements: &[usize],
    ) -> Result<(TetrahedralMesh, Vec<Option<usize>>), MeshError> {
        self.check_elements()?;
        let part = Part::of(
            "tetrahedron",
            &self.tetrahedra,
            &self.nodes,
            (&self.node_sets, &self.element_sets),
            elements,
        )?;
        // Every face of a kept tetrahedron, by its sorted vertices: the mid-edge nodes of
        // a P2 face follow from its vertices' edges, kept with the tetrahedron.
        let faces: HashSet<[usize; 3]> = (self.tetrahedra.iter().zip(&part.kept))
            .filter(|(_, k)| **k)
            .flat_map(|(t, _)| (0..4).map(move |f| face_key(t, f)))
            .collect();
        let is_kept_face = |face: &BoundaryFace| {
            let mut key = [face.nodes[0], face.nodes[1], face.nodes[2]];
            key.sort_unstable();
            faces.contains(&key) && face.nodes.iter().all(|&n| part.node_map[n].is_some())
        };
        let face_sets = (self.face_sets.iter())
            .map(|(name, set)| {
                let kept = (set.iter())
                    .filter(|f| f.nodes.len() >= 3 && is_kept_face(f))
                    .map(|f| BoundaryFace {
                        nodes: part.renumber(&f.nodes),
                    })
                    .collect();
                (name.clone(), kept)
            })
            .collect();
        let mesh = TetrahedralMesh {
            order: self.order,
            nodes: part.nodes,
            tetrahedra: part.elements,
            node_sets: part.node_sets,
            face_sets,
            element_sets: part.element_sets,
        };
        mesh.check_elements()?;
        Ok((mesh, part.node_map))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::ElementOrder;

    /// A 2 × 1 × 1 block of P2 tetrahedra, its x < 1 half kept.
    fn half() -> (TetrahedralMesh, TetrahedralMesh, Vec<Option<usize>>) {
        let mesh =
            TetrahedralMesh::block(&[0.0, 1.0, 2.0], &[0.0, 1.0], &[0.0, 1.0], ElementOrder::P2)
                .expect("block");
        let left: Vec<usize> = (0..mesh.tetrahedra.len())
            .filter(|&e| {
                let c = mesh.tetrahedron_coordinates(e);
                c.iter().map(|p| p[0]).sum::<f64>() < c.len() as f64
            })
            .collect();
        let (sub, map) = mesh.submesh(&left).expect("submesh");
        (mesh, sub, map)
    }

    #[test]
    fn a_half_block_keeps_its_nodes_faces_and_volume() {
        let (mesh, sub, map) = half();
        // P2 nodes on a 5 × 3 × 3 lattice for the half, of 5 × 3 × 3 → (2·1+1)³ = 27.
        assert_eq!(sub.nodes.len(), 27);
        assert_eq!(sub.tetrahedra.len(), mesh.tetrahedra.len() / 2);
        // The map is increasing on the kept nodes, and sends each to its own position.
        let kept: Vec<usize> = map.iter().flatten().copied().collect();
        assert!(kept.windows(2).all(|w| w[0] < w[1]));
        for (old, new) in map.iter().enumerate() {
            if let Some(new) = new {
                assert_eq!(sub.nodes[*new], mesh.nodes[old]);
            }
        }
        // The right face (x = 2) is gone; the left one (x = 0) is whole: 2 × 1 of its
        // triangles' area; the top keeps the half over x < 1.
        let area = |m: &TetrahedralMesh, name: &str| -> f64 {
            m.face_sets[name]
                .iter()
                .map(|f| {
                    let [a, b, c] = [f.nodes[0], f.nodes[1], f.nodes[2]].map(|n| m.nodes[n]);
                    let (u, v) = (
                        [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
                        [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
                    );
                    let n = [
                        u[1] * v[2] - u[2] * v[1],
                        u[2] * v[0] - u[0] * v[2],
                        u[0] * v[1] - u[1] * v[0],
                    ];
                    0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
                })
                .sum()
        };
        assert!(sub.face_sets["right"].is_empty());
        assert!((area(&sub, "left") - 1.0).abs() < 1e-14);
        assert!((area(&mesh, "top") - 2.0).abs() < 1e-14);
        assert!((area(&sub, "top") - 1.0).abs() < 1e-14);
        // Every kept face is a boundary face of the submesh, outward as before.
        let boundary = sub.boundary_faces();
        for f in &sub.face_sets["top"] {
            assert!(boundary.contains(f), "{f:?} is not a boundary face");
        }
        assert!(sub.node_sets["right"].is_empty());
    }

    #[test]
    fn bad_selections_are_named() {
        let mesh = TetrahedralMesh::block(&[0.0, 1.0], &[0.0, 1.0], &[0.0, 1.0], ElementOrder::P1)
            .expect("block");
        let n = mesh.tetrahedra.len();
        for (elements, needle) in [
            (vec![], "selects no tetrahedron"),
            (vec![n], "is tetrahedron"),
            (vec![0, 0], "a second time"),
        ] {
            let e = mesh.submesh(&elements).expect_err("refused");
            assert!(e.to_string().contains(needle), "{e}");
            assert!(e.to_string().contains("elements"), "{e}");
        }
    }
}
