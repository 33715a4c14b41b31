//! Structured tetrahedral meshes of a box: each hexahedral cell of the grid is cut into 6
//! tetrahedra around its diagonal from the lowest to the highest corner (Kuhn's
//! subdivision), so every face of the grid is cut along the diagonal through its own
//! lowest corner in both cells that share it: the mesh is conforming.
use std::collections::BTreeMap;

use super::{face_key, TetrahedralMesh, TETRAHEDRON_FACES};
use crate::element::tet10::EDGES;
use crate::element::tetrahedron::tetrahedron_jacobian_determinant;
use crate::element::ElementOrder;
use crate::error::MeshError;
use crate::mesh::rectangle::check_coordinates;

/// The sides of a box, by axis and end: `(name, axis, at the upper end)`. `front` is the
/// largest z (toward a viewer of the x–y plane, right-handed), `back` the smallest.
const SIDES: [(&str, usize, bool); 6] = [
    ("left", 0, false),
    ("right", 0, true),
    ("bottom", 1, false),
    ("top", 1, true),
    ("back", 2, false),
    ("front", 2, true),
];

impl TetrahedralMesh {
    /// Structured mesh of the box `[xs₀, xs_last] × [ys₀, ys_last] × [zs₀, zs_last]` on the
    /// grid of the given (strictly increasing, metres) coordinates, 6 tetrahedra per cell.
    /// P2 mid-edge nodes sit at edge mid-points. Node and face sets `left`, `right` (x),
    /// `bottom`, `top` (y), `back`, `front` (z) hold each side's nodes and outward faces.
    pub fn block(
        xs: &[f64],
        ys: &[f64],
        zs: &[f64],
        order: ElementOrder,
    ) -> Result<TetrahedralMesh, MeshError> {
        check_coordinates("xs", xs)?;
        check_coordinates("ys", ys)?;
        check_coordinates("zs", zs)?;
        let axes = [xs, ys, zs];
        let cells = [xs.len() - 1, ys.len() - 1, zs.len() - 1];
        // P2 lives on the grid refined by mid-points: vertex (i, j, k) is (s i, s j, s k),
        // and the mid-point of any edge of the subdivision (grid edge, face or cell
        // diagonal) is the mean of its ends' refined indices. Every refined point is used.
        let s = match order {
            ElementOrder::P1 => 1,
            ElementOrder::P2 => 2,
        };
        let refined: Vec<Vec<f64>> = axes
            .iter()
            .map(|c| {
                let mut r = vec![c[0]];
                for w in c.windows(2) {
                    if s == 2 {
                        r.push(0.5 * (w[0] + w[1]));
                    }
                    r.push(w[1]);
                }
                r
            })
            .collect();
        let size = [refined[0].len(), refined[1].len(), refined[2].len()];
        let id = |p: [usize; 3]| (p[2] * size[1] + p[1]) * size[0] + p[0];
        let mut nodes = Vec::with_capacity(size[0] * size[1] * size[2]);
        for k in 0..size[2] {
            for j in 0..size[1] {
                for i in 0..size[0] {
                    nodes.push([refined[0][i], refined[1][j], refined[2][k]]);
                }
            }
        }
        let mut tetrahedra = Vec::with_capacity(6 * cells[0] * cells[1] * cells[2]);
        // The 6 paths from corner 000 to 111, one axis at a time.
        const PATHS: [[usize; 3]; 6] = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        for k in 0..cells[2] {
            for j in 0..cells[1] {
                for i in 0..cells[0] {
                    for path in PATHS {
                        let mut corner = [s * i, s * j, s * k];
                        let mut v = vec![corner];
                        for axis in path {
                            corner[axis] += s;
                            v.push(corner);
                        }
                        // An odd permutation of the axes gives a left-handed triad.
                        if !is_direct(&v, &nodes, id) {
                            v.swap(1, 2);
                        }
                        let mut t: Vec<usize> = v.iter().map(|&p| id(p)).collect();
                        if s == 2 {
                            for (a, b) in EDGES {
                                t.push(id(std::array::from_fn(|c| (v[a][c] + v[b][c]) / 2)));
                            }
                        }
                        tetrahedra.push(t);
                    }
                }
            }
        }
        let mut mesh = TetrahedralMesh {
            order,
            nodes,
            tetrahedra,
            node_sets: BTreeMap::new(),
            face_sets: BTreeMap::new(),
            element_sets: BTreeMap::new(),
        };
        add_sides(&mut mesh, &refined);
        Ok(mesh)
    }
}

/// Whether the triad of the first 4 refined points `v` is direct.
fn is_direct(v: &[[usize; 3]], nodes: &[[f64; 3]], id: impl Fn([usize; 3]) -> usize) -> bool {
    let x: Vec<[f64; 3]> = v.iter().map(|&p| nodes[id(p)]).collect();
    tetrahedron_jacobian_determinant(ElementOrder::P1, &x, [0.25; 3]) > 0.0
}

/// Each side's nodes and outward faces: the tetrahedron faces met once whose vertices all
/// lie on that side's plane.
fn add_sides(mesh: &mut TetrahedralMesh, refined: &[Vec<f64>]) {
    let boundary = mesh.boundary_face_owners();
    for (name, axis, upper) in SIDES {
        let plane = if upper {
            refined[axis][refined[axis].len() - 1]
        } else {
            refined[axis][0]
        };
        let on = |n: usize| mesh.nodes[n][axis] == plane;
        let set: Vec<usize> = (0..mesh.nodes.len()).filter(|&n| on(n)).collect();
        let mut faces = Vec::new();
        for (e, t) in mesh.tetrahedra.iter().enumerate() {
            for (f, vertices) in TETRAHEDRON_FACES.iter().enumerate() {
                if boundary.contains_key(&face_key(t, f)) && vertices.iter().all(|&v| on(t[v])) {
                    faces.push(mesh.boundary_face(e, f));
                }
            }
        }
        mesh.node_sets.insert(name.to_string(), set);
        mesh.face_sets.insert(name.to_string(), faces);
    }
}
