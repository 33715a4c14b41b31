//! A triangle mesh extruded along z into tetrahedra: each triangle and layer make a prism,
//! cut into 3 tetrahedra. A prism's quadrilateral side over the 2D edge `(i, j)`, `i < j`
//! in the 2D numbering, is cut along the diagonal from `i` at the layer's bottom to `j` at
//! its top, whichever prism it belongs to: the two prisms sharing a side cut it alike, and
//! the mesh is conforming. With the triangle's vertices sorted, `a < b < c`, the three
//! diagonals `a₀b₁`, `a₀c₁`, `b₀c₁` meet at `a₀` and `c₁`, and the prism is
//! `a₀b₀c₀c₁`, `a₀b₀b₁c₁`, `a₀a₁b₁c₁`.
use std::collections::{BTreeMap, HashMap, HashSet};

use super::{BoundaryFace, TetrahedralMesh};
use crate::element::tet10::EDGES;
use crate::element::tetrahedron::tetrahedron_jacobian_determinant;
use crate::element::ElementOrder;
use crate::error::MeshError;
use crate::mesh::rectangle::check_coordinates;
use crate::mesh::Mesh;

/// The names of the end faces: `back` at `zs[0]`, `front` at the last z (as
/// [`TetrahedralMesh::block`] names the sides of a box).
const ENDS: [&str; 2] = ["back", "front"];

fn sorted(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

impl TetrahedralMesh {
    /// `mesh` (P1 or P2 triangles in the x–y plane) extruded along z through the planes
    /// `zs` (strictly increasing, m): one layer of prisms between consecutive planes, each
    /// cut into 3 tetrahedra conformingly (see the module). P2 tetrahedra take their
    /// mid-edge nodes from the triangles' and from mid-planes between the layers' planes.
    ///
    /// Sets: each 2D node set holds its nodes at every level; each 2D edge set becomes the
    /// face set of the same name (the outward faces over its edges); each 2D element set
    /// holds the tetrahedra of its triangles' prisms; `back` and `front` are the node and
    /// face sets of the planes `zs[0]` and `zs.last()`.
    ///
    /// Errors: fewer than 2 planes, a plane not finite or out of order, a triangle with
    /// the wrong node count or an unknown node, a flat one (named by index), a 2D set
    /// already named `back` or `front`.
    pub fn extrude(mesh: &Mesh, zs: &[f64]) -> Result<TetrahedralMesh, MeshError> {
        check_coordinates("zs", zs)?;
        let order = mesh.order;
        let per = order.nodes_per_triangle();
        let n2 = mesh.nodes.len();
        for (e, t) in mesh.triangles.iter().enumerate() {
            if t.len() != per || t.iter().any(|&n| n >= n2) {
                return Err(MeshError::BadElement {
                    element: format!("triangle {e}"),
                    reason: format!("{t:?}: a {order:?} triangle has {per} nodes below {n2}"),
                });
            }
        }
        for name in ENDS {
            let taken = mesh.node_sets.contains_key(name)
                || mesh.edge_sets.contains_key(name)
                || mesh.element_sets.contains_key(name);
            if taken {
                return Err(MeshError::invalid(
                    "mesh",
                    format!(
                        "the 2D mesh has a set named `{name}`, the name extrusion gives an \
                         end face (`back` at the first z, `front` at the last)"
                    ),
                ));
            }
        }
        // P2 adds the mid-plane of each layer; level `l` holds every 2D node at `levels[l]`.
        let s = match order {
            ElementOrder::P1 => 1,
            ElementOrder::P2 => 2,
        };
        let mut levels = vec![zs[0]];
        for w in zs.windows(2) {
            if s == 2 {
                levels.push(0.5 * (w[0] + w[1]));
            }
            levels.push(w[1]);
        }
        let id = |n: usize, level: usize| level * n2 + n;
        let nodes: Vec<[f64; 3]> = (levels.iter())
            .flat_map(|&z| mesh.nodes.iter().map(move |p| [p[0], p[1], z]))
            .collect();
        // The 2D mid-edge node of each edge (P2), by its sorted vertices.
        let mut mid2: HashMap<(usize, usize), usize> = HashMap::new();
        if s == 2 {
            for t in &mesh.triangles {
                for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                    mid2.insert(sorted(t[i], t[j]), t[3 + k]);
                }
            }
        }
        // A vertex is (2D vertex, level); the mid-point of two of them is the 2D mid-edge
        // node (or the 2D vertex, on a vertical edge) at the mean level.
        let mid = |a: (usize, usize), b: (usize, usize)| {
            let n = if a.0 == b.0 {
                a.0
            } else {
                mid2[&sorted(a.0, b.0)]
            };
            id(n, (a.1 + b.1) / 2)
        };
        let layers = zs.len() - 1;
        let mut tetrahedra = Vec::with_capacity(3 * layers * mesh.triangles.len());
        for k in 0..layers {
            let (lo, hi) = (s * k, s * (k + 1));
            for (e, t) in mesh.triangles.iter().enumerate() {
                let mut v = [t[0], t[1], t[2]];
                v.sort_unstable();
                let [a, b, c] = v;
                for mut tet in [
                    [(a, lo), (b, lo), (c, lo), (c, hi)],
                    [(a, lo), (b, lo), (b, hi), (c, hi)],
                    [(a, lo), (a, hi), (b, hi), (c, hi)],
                ] {
                    let x: Vec<[f64; 3]> = tet.iter().map(|&(n, l)| nodes[id(n, l)]).collect();
                    let det = tetrahedron_jacobian_determinant(ElementOrder::P1, &x, [0.25; 3]);
                    if !(det.is_finite() && det != 0.0) {
                        return Err(MeshError::BadElement {
                            element: format!("triangle {e}"),
                            reason: format!("its prism in layer {k} has a flat tetrahedron"),
                        });
                    }
                    // A left-handed triad is turned direct.
                    if det < 0.0 {
                        tet.swap(1, 2);
                    }
                    let mut nodes: Vec<usize> = tet.iter().map(|&(n, l)| id(n, l)).collect();
                    if s == 2 {
                        nodes.extend(EDGES.iter().map(|&(i, j)| mid(tet[i], tet[j])));
                    }
                    tetrahedra.push(nodes);
                }
            }
        }
        let mut mesh3 = TetrahedralMesh {
            order,
            nodes,
            tetrahedra,
            node_sets: BTreeMap::new(),
            face_sets: BTreeMap::new(),
            element_sets: BTreeMap::new(),
        };
        mesh3.check_elements()?;
        let all_levels = levels.len();
        for (name, set) in &mesh.node_sets {
            let extruded = (0..all_levels)
                .flat_map(|l| set.iter().map(move |&n| id(n, l)))
                .collect();
            mesh3.node_sets.insert(name.clone(), extruded);
        }
        let n_tri = mesh.triangles.len();
        for (name, set) in &mesh.element_sets {
            let mut extruded: Vec<usize> = (0..layers)
                .flat_map(|k| {
                    set.iter()
                        .flat_map(move |&e| (0..3).map(move |j| 3 * (k * n_tri + e) + j))
                })
                .collect();
            extruded.sort_unstable();
            mesh3.element_sets.insert(name.clone(), extruded);
        }
        // Boundary faces in a fixed order (by tetrahedron, then local face).
        let mut owners: Vec<(usize, usize)> = mesh3.boundary_face_owners().into_values().collect();
        owners.sort_unstable();
        let faces: Vec<(BoundaryFace, [usize; 3])> = owners
            .into_iter()
            .map(|(e, f)| {
                let face = mesh3.boundary_face(e, f);
                let v = [face.nodes[0], face.nodes[1], face.nodes[2]];
                (face, v)
            })
            .collect();
        for (name, edges) in &mesh.edge_sets {
            let pairs: HashSet<(usize, usize)> = (edges.iter())
                .filter(|e| e.nodes.len() >= 2)
                .map(|e| sorted(e.nodes[0], e.nodes[1]))
                .collect();
            // A side face has 2 distinct 2D vertices: those of the edge it stands on.
            let on = |v: &[usize; 3]| {
                let mut n: Vec<usize> = v.iter().map(|&x| x % n2).collect();
                n.sort_unstable();
                n.dedup();
                n.len() == 2 && pairs.contains(&(n[0], n[1]))
            };
            let set = (faces.iter())
                .filter(|(_, v)| on(v))
                .map(|(f, _)| f.clone())
                .collect();
            mesh3.face_sets.insert(name.clone(), set);
        }
        for (name, level) in ENDS.into_iter().zip([0, all_levels - 1]) {
            mesh3
                .node_sets
                .insert(name.to_string(), (0..n2).map(|n| id(n, level)).collect());
            let set = (faces.iter())
                .filter(|(_, v)| v.iter().all(|&x| x / n2 == level))
                .map(|(f, _)| f.clone())
                .collect();
            mesh3.face_sets.insert(name.to_string(), set);
        }
        Ok(mesh3)
    }
}
