//! The mesh of part of the triangles: what remains of a body after a region is dug out
//! (construction in stages; the forces and the state that go with it are in
//! `crate::excavation`).
use std::collections::{BTreeMap, HashMap};

use super::{BoundaryEdge, Mesh};
use crate::error::MeshError;

impl Mesh {
    /// The mesh of the triangles `elements` (indices into [`triangles`](Self::triangles),
    /// in any order, each once), with only the nodes they use, and the map from each node
    /// of `self` to its index in the submesh (`None`: the node is gone).
    ///
    /// - Triangles keep their node order and come in increasing old index: triangle `k`
    ///   of the submesh is the `k`-th smallest entry of `elements`, so its Gauss points
    ///   are those of that old triangle, in the same order (`crate::excavation`).
    /// - Nodes are the ones the kept triangles use, numbered in increasing old index (the
    ///   map is increasing on the nodes it keeps), with their coordinates.
    /// - Node sets keep their kept nodes (still sorted).
    /// - Element sets keep their kept triangles, renumbered (still sorted).
    /// - Edge sets keep the edges that are still a side of a kept triangle (every node
    ///   kept, and on P2 the side's own mid node), in their own direction, renumbered. An
    ///   edge that was a side of removed triangles only goes, even when all its nodes stay
    ///   (a P1 triangle dug out between two kept neighbours leaves both ends of its top
    ///   side): after an excavation, `edges = "top"` loads the part of the top that is
    ///   still there, never the air over the pit. The sides the excavation lays bare (its
    ///   floor and walls) join no set: name them beforehand (a Gmsh physical curve along
    ///   the future floor, interior until then) to load them; such an edge is kept, as
    ///   every edge of a set whose triangle remains, boundary or interior: a set names the
    ///   same curve of the body before and after.
    /// - A set left empty is kept, empty, under its name: a later stage that loads
    ///   `edges = "top"` after the top is gone finds a set that selects nothing (and says
    ///   so) rather than an unknown name.
    ///
    /// The result passes [`Mesh::validate`] when `self` does (checked). Errors: `self`
    /// fails [`Mesh::validate`]; `elements` is empty, or names a triangle out of range or
    /// twice (the error names `elements`, the entry and the triangle).
    pub fn submesh(&self, elements: &[usize]) -> Result<(Mesh, Vec<Option<usize>>), MeshError> {
        self.validate()?;
        let part = Part::of(
            "triangle",
            &self.triangles,
            &self.nodes,
            (&self.node_sets, &self.element_sets),
            elements,
        )?;
        let kept = &part.kept;
        let renumber = |old: &[usize]| part.renumber(old);

        // The sides of the kept triangles, keyed by their sorted ends: their P2 mid node.
        let mut sides: HashMap<(usize, usize), Option<usize>> = HashMap::new();
        for tri in self
            .triangles
            .iter()
            .zip(kept)
            .filter(|(_, k)| **k)
            .map(|t| t.0)
        {
            for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                let (a, b) = (tri[i], tri[j]);
                sides.insert((a.min(b), a.max(b)), tri.get(3 + k).copied());
            }
        }
        let is_kept_side = |edge: &BoundaryEdge| {
            // `validate` checked: 2 (P1) or 3 (P2) nodes, in range.
            let (a, b) = (edge.nodes[0], edge.nodes[1]);
            sides
                .get(&(a.min(b), a.max(b)))
                .is_some_and(|mid| *mid == edge.nodes.get(2).copied())
        };
        let edge_sets = self
            .edge_sets
            .iter()
            .map(|(name, edges)| {
                let kept_edges = edges
                    .iter()
                    .filter(|e| is_kept_side(e))
                    .map(|e| BoundaryEdge {
                        nodes: renumber(&e.nodes),
                    })
                    .collect();
                (name.clone(), kept_edges)
            })
            .collect();

        let mesh = Mesh {
            order: self.order,
            nodes: part.nodes,
            triangles: part.elements,
            node_sets: part.node_sets,
            edge_sets,
            element_sets: part.element_sets,
        };
        mesh.validate()?;
        Ok((mesh, part.node_map))
    }
}

/// Named sets of node or element indices.
type Sets = BTreeMap<String, Vec<usize>>;

/// What a submesh keeps of any mesh, triangles or tetrahedra: the chosen elements in
/// increasing old index with their nodes renumbered, the nodes they use (in increasing
/// old index), the node and element sets restricted and renumbered, and the maps.
pub(crate) struct Part<P> {
    /// Whether each old element is kept.
    pub kept: Vec<bool>,
    /// Each old node's new index (`None`: gone).
    pub node_map: Vec<Option<usize>>,
    pub nodes: Vec<P>,
    pub elements: Vec<Vec<usize>>,
    pub node_sets: Sets,
    pub element_sets: Sets,
}

impl<P: Copy> Part<P> {
    /// The part of `all` (elements of `kind`, over `nodes`) that `elements` selects (any
    /// order, each once). Errors name `elements`: empty, an entry out of range or repeated.
    pub fn of(
        kind: &str,
        all: &[Vec<usize>],
        nodes: &[P],
        (node_sets, element_sets): (&Sets, &Sets),
        elements: &[usize],
    ) -> Result<Self, MeshError> {
        if elements.is_empty() {
            return Err(MeshError::invalid(
                "elements",
                format!("selects no {kind}: a submesh needs at least one"),
            ));
        }
        let n = all.len();
        let mut kept = vec![false; n];
        for (k, &e) in elements.iter().enumerate() {
            if e >= n {
                return Err(MeshError::invalid(
                    "elements",
                    format!("entry {k} is {kind} {e}, the mesh has {n} {kind}s"),
                ));
            }
            if kept[e] {
                return Err(MeshError::invalid(
                    "elements",
                    format!("entry {k} names {kind} {e} a second time"),
                ));
            }
            kept[e] = true;
        }
        let mut element_map = vec![None; n];
        let mut node_map = vec![None; nodes.len()];
        for (e, element) in all.iter().enumerate().filter(|(e, _)| kept[*e]) {
            element_map[e] = Some(0); // numbered below
            for &v in element {
                node_map[v] = Some(0);
            }
        }
        let number = |map: &mut [Option<usize>]| {
            for (next, m) in map.iter_mut().flatten().enumerate() {
                *m = next;
            }
        };
        number(&mut element_map);
        number(&mut node_map);
        let restrict = |sets: &Sets, map: &[Option<usize>]| -> Sets {
            sets.iter()
                .map(|(name, set)| (name.clone(), set.iter().filter_map(|&i| map[i]).collect()))
                .collect()
        };
        let mut part = Self {
            nodes: (nodes.iter().zip(&node_map))
                .filter(|(_, m)| m.is_some())
                .map(|(p, _)| *p)
                .collect(),
            node_sets: restrict(node_sets, &node_map),
            element_sets: restrict(element_sets, &element_map),
            elements: Vec::with_capacity(elements.len()),
            kept,
            node_map,
        };
        part.elements = (all.iter().zip(&part.kept))
            .filter(|(_, k)| **k)
            .map(|(element, _)| part.renumber(element))
            .collect();
        Ok(part)
    }

    /// Kept nodes `old` in the new numbering.
    pub fn renumber(&self, old: &[usize]) -> Vec<usize> {
        old.iter()
            .map(|&n| self.node_map[n].expect("a kept element's nodes are kept"))
            .collect()
    }
}
