//! Structured tetrahedral meshes of a box (`TetrahedralMesh::block`): counts against
//! closed forms (6 tetrahedra per cell; P2 nodes = vertices + edges of the subdivision,
//! so mid-edge nodes are shared), conformity (every interior face met twice), the volume,
//! outward side faces whose areas sum to each side's, and refused input.
use std::collections::HashMap;

use talus_fem::element::ElementOrder;
use talus_fem::mesh3::TETRAHEDRON_FACES;
use talus_fem::{graded_coordinates, MeshError, TetrahedralMesh};

const ORDERS: [ElementOrder; 2] = [ElementOrder::P1, ElementOrder::P2];

fn grid() -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    (
        graded_coordinates(-1.0, 2.0, 3, 0.0, 1.3).unwrap(),
        graded_coordinates(-1.0, 0.0, 2, 0.0, 1.5).unwrap(),
        vec![0.0, 0.4, 0.5, 1.5],
    )
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[test]
fn counts_match_the_subdivision() {
    let (xs, ys, zs) = grid();
    let (nx, ny, nz) = (3usize, 2usize, 3usize);
    let vertices = (nx + 1) * (ny + 1) * (nz + 1);
    // Edges of Kuhn's subdivision: the grid's, one diagonal per grid face, one per cell.
    let edges = nx * (ny + 1) * (nz + 1)
        + (nx + 1) * ny * (nz + 1)
        + (nx + 1) * (ny + 1) * nz
        + nx * ny * (nz + 1)
        + nx * (ny + 1) * nz
        + (nx + 1) * ny * nz
        + nx * ny * nz;
    for order in ORDERS {
        let mesh = TetrahedralMesh::block(&xs, &ys, &zs, order).unwrap();
        assert_eq!(mesh.tetrahedra.len(), 6 * nx * ny * nz);
        let expected = match order {
            ElementOrder::P1 => vertices,
            ElementOrder::P2 => vertices + edges,
        };
        assert_eq!(mesh.nodes.len(), expected, "{order:?}");
        // every node is used
        let mut used = vec![false; mesh.nodes.len()];
        mesh.tetrahedra
            .iter()
            .flatten()
            .for_each(|&n| used[n] = true);
        assert!(used.iter().all(|u| *u), "{order:?}: unused nodes");
        mesh.check_elements().unwrap();
    }
}

#[test]
fn the_mesh_is_conforming_and_fills_the_box() {
    let (xs, ys, zs) = grid();
    let box_volume = 3.0 * 1.0 * 1.5;
    for order in ORDERS {
        let mesh = TetrahedralMesh::block(&xs, &ys, &zs, order).unwrap();
        let mut count: HashMap<[usize; 3], usize> = HashMap::new();
        let mut volume = 0.0;
        for t in &mesh.tetrahedra {
            for f in TETRAHEDRON_FACES {
                let mut k = [t[f[0]], t[f[1]], t[f[2]]];
                k.sort_unstable();
                *count.entry(k).or_default() += 1;
            }
            let x: Vec<[f64; 3]> = t[..4].iter().map(|&n| mesh.nodes[n]).collect();
            let c = cross(sub(x[2], x[0]), sub(x[3], x[0]));
            let e = sub(x[1], x[0]);
            volume += (e[0] * c[0] + e[1] * c[1] + e[2] * c[2]) / 6.0;
        }
        assert!((volume - box_volume).abs() < 1e-13, "{order:?}: {volume}");
        assert!(count.values().all(|&c| c == 1 || c == 2));
        let boundary = count.values().filter(|&&c| c == 1).count();
        let (nx, ny, nz) = (3, 2, 3);
        assert_eq!(boundary, 4 * (nx * ny + ny * nz + nz * nx));
        let in_sets: usize = mesh.face_sets.values().map(Vec::len).sum();
        assert_eq!(in_sets, boundary, "each boundary face in exactly one side");
    }
}

#[test]
fn side_faces_point_outward_and_cover_their_side() {
    let (xs, ys, zs) = grid();
    let sides = [
        ("left", 0, -1.0, 1.0 * 1.5),
        ("right", 0, 1.0, 1.0 * 1.5),
        ("bottom", 1, -1.0, 3.0 * 1.5),
        ("top", 1, 1.0, 3.0 * 1.5),
        ("back", 2, -1.0, 3.0 * 1.0),
        ("front", 2, 1.0, 3.0 * 1.0),
    ];
    for order in ORDERS {
        let mesh = TetrahedralMesh::block(&xs, &ys, &zs, order).unwrap();
        for (name, axis, sign, area) in sides {
            let mut total = 0.0;
            for face in &mesh.face_sets[name] {
                let x: Vec<[f64; 3]> = face.nodes.iter().map(|&n| mesh.nodes[n]).collect();
                let n = cross(sub(x[1], x[0]), sub(x[2], x[0]));
                assert!(
                    n[axis] * sign > 0.0,
                    "{order:?} {name}: inward face {face:?}"
                );
                for (c, v) in n.iter().enumerate() {
                    assert!(c == axis || v.abs() < 1e-14, "{name}: face off its plane");
                }
                total += 0.5 * n[axis].abs();
                if order == ElementOrder::P2 {
                    assert_eq!(face.nodes.len(), 6);
                    for (m, (a, b)) in [(0, 1), (1, 2), (2, 0)].iter().enumerate() {
                        let mid = x[3 + m];
                        for c in 0..3 {
                            assert!((mid[c] - 0.5 * (x[*a][c] + x[*b][c])).abs() < 1e-15);
                        }
                    }
                }
            }
            assert!((total - area).abs() < 1e-13, "{order:?} {name}: {total} m²");
            let nodes = &mesh.node_sets[name];
            let plane = mesh.nodes[nodes[0]][axis];
            assert!(nodes.iter().all(|&n| mesh.nodes[n][axis] == plane));
        }
    }
}

#[test]
fn inverted_tetrahedra_and_bad_grids_are_refused_by_name() {
    let (xs, ys, zs) = grid();
    let mut mesh = TetrahedralMesh::block(&xs, &ys, &zs, ElementOrder::P1).unwrap();
    mesh.tetrahedra[7].swap(1, 2);
    let err = mesh.check_elements().unwrap_err();
    assert!(
        matches!(&err, MeshError::BadElement { element, .. } if element == "tetrahedron 7"),
        "{err}"
    );
    assert!(err.to_string().contains("inverted or flat"), "{err}");
    let err = TetrahedralMesh::block(&xs, &ys, &[0.0], ElementOrder::P2).unwrap_err();
    assert!(
        matches!(err, MeshError::InvalidInput { field: "zs", .. }),
        "{err}"
    );
    let err = TetrahedralMesh::block(&xs, &ys, &[0.0, 0.0], ElementOrder::P1).unwrap_err();
    assert!(err.to_string().contains("zs"), "{err}");
}
