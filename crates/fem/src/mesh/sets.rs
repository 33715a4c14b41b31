//! Node and edge selections: the mesh boundary, and axis-aligned boxes (scenes name their
//! supports and loaded edges by boxes).
use std::collections::BTreeMap;

use super::{BoundaryEdge, Mesh};
use crate::error::MeshError;

impl Mesh {
    /// Edges that belong to exactly one triangle, oriented as in that triangle (so they run
    /// counter-clockwise around the domain), sorted by their first node.
    pub fn boundary_edges(&self) -> Vec<BoundaryEdge> {
        let mut edges: Vec<BoundaryEdge> = self
            .triangle_sides()
            .into_values()
            .filter(|(count, _)| *count == 1)
            .map(|(_, nodes)| BoundaryEdge { nodes })
            .collect();
        edges.sort();
        edges
    }

    /// Every triangle side, keyed by its sorted end points: how many triangles share it,
    /// and its nodes as the first of them runs through it (ends, then the P2 mid node).
    fn triangle_sides(&self) -> BTreeMap<(usize, usize), (usize, Vec<usize>)> {
        let mut sides: BTreeMap<(usize, usize), (usize, Vec<usize>)> = BTreeMap::new();
        for tri in self.triangles.iter().filter(|t| t.len() >= 3) {
            for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                let (a, b) = (tri[i], tri[j]);
                let mut nodes = vec![a, b];
                if tri.len() == 6 {
                    nodes.push(tri[3 + k]);
                }
                sides.entry((a.min(b), a.max(b))).or_insert((0, nodes)).0 += 1;
            }
        }
        sides
    }

    /// `edges` each oriented as in the one triangle it belongs to, so that it runs
    /// counter-clockwise around the domain and its outward normal is its tangent turned
    /// clockwise. Gmsh line elements keep the direction they were drawn in; a normal load
    /// needs this orientation. Errors name an edge that is not a side of exactly one
    /// triangle (an interior edge has no outside), or a P2 edge whose mid node is not that
    /// side's mid node.
    pub fn orient_boundary_edges(
        &self,
        edges: &[BoundaryEdge],
    ) -> Result<Vec<BoundaryEdge>, MeshError> {
        let sides = self.triangle_sides();
        let describe = |e: &BoundaryEdge| {
            let at = |n: usize| self.nodes.get(n).copied().unwrap_or([f64::NAN; 2]);
            let (a, b) = (at(e.nodes[0]), at(e.nodes[1]));
            format!(
                "edge {:?}, ({:.4}, {:.4})–({:.4}, {:.4}),",
                e.nodes, a[0], a[1], b[0], b[1]
            )
        };
        edges
            .iter()
            .map(|e| {
                if e.nodes.len() < 2 {
                    return Err(MeshError::invalid(
                        "edges",
                        format!("edge {:?} has fewer than 2 nodes", e.nodes),
                    ));
                }
                let (a, b) = (e.nodes[0], e.nodes[1]);
                match sides.get(&(a.min(b), a.max(b))) {
                    Some((1, side)) if side.len() == e.nodes.len() && side[2..] == e.nodes[2..] => {
                        Ok(BoundaryEdge {
                            nodes: side.clone(),
                        })
                    }
                    Some((1, _)) => Err(MeshError::invalid(
                        "edges",
                        format!(
                            "{} does not have the nodes of its triangle's side",
                            describe(e)
                        ),
                    )),
                    Some((n, _)) => Err(MeshError::invalid(
                        "edges",
                        format!(
                            "{} is shared by {n} triangles: it is not on the boundary",
                            describe(e)
                        ),
                    )),
                    None => Err(MeshError::invalid(
                        "edges",
                        format!("{} is the side of no triangle", describe(e)),
                    )),
                }
            })
            .collect()
    }

    /// Indices (sorted) of the nodes inside the closed box `[min, max]`, widened by
    /// `1e-9 ×` the mesh's bounding-box size so that nodes on the box's faces are kept
    /// despite rounding. Errors on a non-finite or inverted box, or an empty selection.
    pub fn nodes_in_box(&self, min: [f64; 2], max: [f64; 2]) -> Result<Vec<usize>, MeshError> {
        let inside = self.box_predicate(min, max)?;
        let nodes: Vec<usize> = (0..self.nodes.len())
            .filter(|&i| inside(self.nodes[i]))
            .collect();
        if nodes.is_empty() {
            return Err(MeshError::EmptyBox {
                what: "node",
                min,
                max,
            });
        }
        Ok(nodes)
    }

    /// Boundary edges (see [`boundary_edges`](Self::boundary_edges)) whose nodes all lie in
    /// the box (same tolerance as [`nodes_in_box`](Self::nodes_in_box)). Errors as there.
    pub fn boundary_edges_in_box(
        &self,
        min: [f64; 2],
        max: [f64; 2],
    ) -> Result<Vec<BoundaryEdge>, MeshError> {
        let inside = self.box_predicate(min, max)?;
        let edges: Vec<BoundaryEdge> = self
            .boundary_edges()
            .into_iter()
            .filter(|e| {
                e.nodes
                    .iter()
                    .all(|&n| self.nodes.get(n).is_some_and(|&p| inside(p)))
            })
            .collect();
        if edges.is_empty() {
            return Err(MeshError::EmptyBox {
                what: "boundary edge",
                min,
                max,
            });
        }
        Ok(edges)
    }

    fn box_predicate(
        &self,
        min: [f64; 2],
        max: [f64; 2],
    ) -> Result<impl Fn([f64; 2]) -> bool, MeshError> {
        if !min.iter().chain(&max).all(|v| v.is_finite()) || min[0] > max[0] || min[1] > max[1] {
            return Err(MeshError::invalid(
                "box",
                format!("min = {min:?}, max = {max:?} must be finite with min ≤ max"),
            ));
        }
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in &self.nodes {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let tol = if size.is_finite() && size > 0.0 {
            1e-9 * size
        } else {
            0.0
        };
        Ok(move |p: [f64; 2]| (0..2).all(|k| p[k] >= min[k] - tol && p[k] <= max[k] + tol))
    }
}
