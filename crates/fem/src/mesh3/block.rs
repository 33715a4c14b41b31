//! Structured tetrahedral meshes of a box: each hexahedral cell of the grid is cut into 6
//! tetrahedra around its diagonal from the lowest to the highest corner (Kuhn's
//! subdivision), so every face of the grid is cut along the diagonal through its own
//! lowest corner in both cells that share it: the mesh is conforming.
use std::collections::{BTreeMap, HashMap};

use super::{BoundaryFace, TetrahedralMesh, TETRAHEDRON_FACES};
use crate::element::tet10::EDGES;
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
        let (node_sets, face_sets) = sides(&tetrahedra, &nodes, &refined, order);
        let mesh = TetrahedralMesh {
            order,
            nodes,
            tetrahedra,
            node_sets,
            face_sets,
            element_sets: BTreeMap::new(),
        };
        Ok(mesh)
    }
}

/// Whether the triad of the first 4 refined points `v` is direct.
fn is_direct(v: &[[usize; 3]], nodes: &[[f64; 3]], id: impl Fn([usize; 3]) -> usize) -> bool {
    let x: Vec<[f64; 3]> = v.iter().map(|&p| nodes[id(p)]).collect();
    let e = |i: usize| -> [f64; 3] { std::array::from_fn(|c| x[i][c] - x[0][c]) };
    let (a, b, c) = (e(1), e(2), e(3));
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
        > 0.0
}

type Sets = (
    BTreeMap<String, Vec<usize>>,
    BTreeMap<String, Vec<BoundaryFace>>,
);

/// Each side's nodes and outward faces: the tetrahedron faces met once whose vertices all
/// lie on that side's plane.
fn sides(
    tetrahedra: &[Vec<usize>],
    nodes: &[[f64; 3]],
    refined: &[Vec<f64>],
    order: ElementOrder,
) -> Sets {
    let mut count: HashMap<[usize; 3], usize> = HashMap::new();
    let key = |t: &[usize], f: &[usize; 3]| {
        let mut k = [t[f[0]], t[f[1]], t[f[2]]];
        k.sort_unstable();
        k
    };
    for t in tetrahedra {
        for f in &TETRAHEDRON_FACES {
            *count.entry(key(t, f)).or_default() += 1;
        }
    }
    let mut node_sets = BTreeMap::new();
    let mut face_sets: BTreeMap<String, Vec<BoundaryFace>> = BTreeMap::new();
    for (name, axis, upper) in SIDES {
        let plane = if upper {
            refined[axis][refined[axis].len() - 1]
        } else {
            refined[axis][0]
        };
        let on = |n: usize| nodes[n][axis] == plane;
        let set: Vec<usize> = (0..nodes.len()).filter(|&n| on(n)).collect();
        node_sets.insert(name.to_string(), set);
        let mut faces = Vec::new();
        for t in tetrahedra {
            for f in &TETRAHEDRON_FACES {
                if count[&key(t, f)] != 1 || !f.iter().all(|&v| on(t[v])) {
                    continue;
                }
                let mut face: Vec<usize> = f.iter().map(|&v| t[v]).collect();
                if order == ElementOrder::P2 {
                    for (a, b) in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
                        let e = EDGES
                            .iter()
                            .position(|&(i, j)| (i, j) == (a, b) || (i, j) == (b, a))
                            .expect("every vertex pair of a tetrahedron is an edge");
                        face.push(t[4 + e]);
                    }
                }
                faces.push(BoundaryFace { nodes: face });
            }
        }
        face_sets.insert(name.to_string(), faces);
    }
    (node_sets, face_sets)
}
