//! Order elevation: the P2 mesh of a P1 mesh's straight-sided triangles.
use std::collections::{BTreeMap, HashMap, HashSet};

use super::{BoundaryEdge, Mesh};
use crate::element::ElementOrder;
use crate::error::MeshError;

/// A triangle side's key: its end nodes, smaller first.
fn side(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

impl Mesh {
    /// The P2 mesh of the same triangles, e.g. to run a Gmsh P1 mesh with quadratic
    /// elements. Every side gets one mid node at its mid point (sides shared by two
    /// triangles share it); the triangles keep their index and their vertices and gain the
    /// mid nodes of their sides 01, 12, 20 (the P2 node order). Existing nodes keep their
    /// index, the mid nodes are appended (in the order the triangles first reach them).
    ///
    /// - Edge sets: each edge `[a, b]` becomes `[a, b, mid]`, in its direction.
    /// - Node sets: a set gains the mid node of each edge of the edge set of the same name
    ///   when there is one (the node and edge sets of a Gmsh physical curve, or of a side
    ///   of [`Mesh::rectangle`]), else of each triangle side whose two ends are in the set.
    /// - Element sets are unchanged.
    ///
    /// The P2 triangles are as straight as the P1 ones (`det J` constant per triangle, the
    /// same), so areas and volumes are unchanged and the result passes [`Mesh::validate`]
    /// as the input did. Errors: the mesh is
    /// not P1; it fails [`Mesh::validate`]; an edge of an edge set is the side of no
    /// triangle (it would have no mid node).
    pub fn to_p2(&self) -> Result<Mesh, MeshError> {
        if self.order != ElementOrder::P1 {
            return Err(MeshError::invalid(
                "mesh order",
                format!(
                    "to_p2 converts a P1 mesh, this mesh is {:?} already",
                    self.order
                ),
            ));
        }
        self.validate()?;

        let mut nodes = self.nodes.clone();
        let mut mids: HashMap<(usize, usize), usize> = HashMap::new();
        let mut triangles = Vec::with_capacity(self.triangles.len());
        for tri in &self.triangles {
            let mut t = Vec::with_capacity(6);
            t.extend_from_slice(tri);
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                let (a, b) = (tri[i], tri[j]);
                let m = *mids.entry(side(a, b)).or_insert_with(|| {
                    let (p, q) = (self.nodes[a], self.nodes[b]);
                    nodes.push([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]);
                    nodes.len() - 1
                });
                t.push(m);
            }
            triangles.push(t);
        }

        let mut edge_sets = BTreeMap::new();
        for (name, edges) in &self.edge_sets {
            let p2 = edges
                .iter()
                .map(|e| {
                    // `validate` checked: two nodes, both in range.
                    let (a, b) = (e.nodes[0], e.nodes[1]);
                    let m = mids.get(&side(a, b)).ok_or_else(|| {
                        let (p, q) = (self.nodes[a], self.nodes[b]);
                        MeshError::invalid(
                            "edge_sets",
                            format!(
                                "edge set \"{name}\": edge [{a}, {b}], ({}, {})–({}, {}), is \
                                 the side of no triangle, so it has no P2 mid node",
                                p[0], p[1], q[0], q[1]
                            ),
                        )
                    })?;
                    Ok(BoundaryEdge {
                        nodes: vec![a, b, *m],
                    })
                })
                .collect::<Result<Vec<_>, MeshError>>()?;
            edge_sets.insert(name.clone(), p2);
        }

        let mut node_sets = BTreeMap::new();
        for (name, set) in &self.node_sets {
            let mut p2 = set.clone();
            match edge_sets.get(name) {
                Some(edges) => p2.extend(edges.iter().map(|e: &BoundaryEdge| e.nodes[2])),
                None => {
                    let members: HashSet<usize> = set.iter().copied().collect();
                    p2.extend(
                        mids.iter()
                            .filter(|((a, b), _)| members.contains(a) && members.contains(b))
                            .map(|(_, &m)| m),
                    );
                }
            }
            p2.sort_unstable();
            p2.dedup();
            node_sets.insert(name.clone(), p2);
        }

        Ok(Mesh {
            order: ElementOrder::P2,
            nodes,
            triangles,
            node_sets,
            edge_sets,
            element_sets: self.element_sets.clone(),
        })
    }
}
