//! `Mesh::to_p2`: a P1 mesh becomes the P2 mesh of the same straight triangles.
//!
//! - (a) on a graded rectangle it gives `Mesh::rectangle(.., P2)` up to node numbering:
//!   the same node coordinates (bit for bit: both take `0.5 (a + b)`), triangles, node and
//!   edge sets;
//! - (b) areas (det J / 2 from the vertices, det J of the P2 map, the assembly's volumes)
//!   are unchanged;
//! - (c) a quadratic field sampled at the new mesh's nodes is reproduced exactly inside
//!   each triangle by the P2 shape functions, and not by P1 on the original mesh;
//! - (d) a P2 mesh is refused, naming its order;
//!
//! and on Gmsh meshes: shared sides share one mid node, element sets are kept, edge sets
//! become `[a, b, mid]`, node sets gain mid nodes by the rule of the documentation.
use std::collections::{BTreeMap, BTreeSet, HashMap};

use talus_fem::element::jacobian_determinant;
use talus_fem::{Assembly, BoundaryEdge, DofMap, ElementOrder, Mesh, MeshError};

use crate::common;
use crate::gmsh_layers;
use common::gmsh_square::{p1_file, P1_TRIANGLES};

const XS: [f64; 5] = [0.0, 0.3, 1.1, 2.0, 2.4];
const YS: [f64; 4] = [-1.0, -0.25, 0.5, 0.9];

fn bits(p: [f64; 2]) -> [u64; 2] {
    [p[0].to_bits(), p[1].to_bits()]
}

/// Twice the signed area of the corners of triangle `t`.
fn twice_area(mesh: &Mesh, t: &[usize]) -> f64 {
    let [a, b, c] = [mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]]];
    (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
}

/// The P1 meshes the general checks run on.
fn p1_meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        (
            "rectangle",
            Mesh::rectangle(&XS, &YS, ElementOrder::P1).unwrap(),
        ),
        ("distorted", common::distorted_rectangle(ElementOrder::P1)),
        (
            "gmsh square",
            Mesh::from_msh_bytes(p1_file(P1_TRIANGLES).as_bytes()).unwrap(),
        ),
        (
            "gmsh layers",
            Mesh::from_msh_bytes(gmsh_layers::layers().ascii().as_bytes()).unwrap(),
        ),
    ]
}

/// (a) The converted P1 rectangle is the P2 rectangle, renumbered: a bijection of nodes
/// with bit-identical coordinates carries triangles, node sets and edge sets onto it.
#[test]
fn to_p2_of_p1_rectangle_is_the_p2_rectangle() {
    let p2 = Mesh::rectangle(&XS, &YS, ElementOrder::P1)
        .unwrap()
        .to_p2()
        .unwrap();
    let reference = Mesh::rectangle(&XS, &YS, ElementOrder::P2).unwrap();
    assert_eq!(p2.order, ElementOrder::P2);
    assert_eq!(p2.nodes.len(), reference.nodes.len());
    let index: HashMap<[u64; 2], usize> = reference
        .nodes
        .iter()
        .enumerate()
        .map(|(i, &p)| (bits(p), i))
        .collect();
    assert_eq!(
        index.len(),
        reference.nodes.len(),
        "reference nodes distinct"
    );
    let map: Vec<usize> = p2
        .nodes
        .iter()
        .map(|&p| {
            *index
                .get(&bits(p))
                .unwrap_or_else(|| panic!("node {p:?} is no node of the P2 rectangle"))
        })
        .collect();
    let image: BTreeSet<usize> = map.iter().copied().collect();
    assert_eq!(image.len(), map.len(), "two nodes at one point");
    // Triangle e stays triangle e (element sets depend on it), node order included.
    let triangles: Vec<Vec<usize>> = p2
        .triangles
        .iter()
        .map(|t| t.iter().map(|&n| map[n]).collect())
        .collect();
    assert_eq!(triangles, reference.triangles);
    let node_sets: BTreeMap<String, Vec<usize>> = p2
        .node_sets
        .iter()
        .map(|(k, s)| {
            let mut s: Vec<usize> = s.iter().map(|&n| map[n]).collect();
            s.sort_unstable();
            (k.clone(), s)
        })
        .collect();
    assert_eq!(node_sets, reference.node_sets);
    let edge_sets: BTreeMap<String, Vec<BoundaryEdge>> = p2
        .edge_sets
        .iter()
        .map(|(k, edges)| {
            let edges = edges
                .iter()
                .map(|e| BoundaryEdge {
                    nodes: e.nodes.iter().map(|&n| map[n]).collect(),
                })
                .collect();
            (k.clone(), edges)
        })
        .collect();
    assert_eq!(edge_sets, reference.edge_sets);
    assert_eq!(p2.element_sets, reference.element_sets);
    p2.validate().unwrap();
}

/// What holds on every mesh: old nodes and corners unchanged, mid nodes at the exact mid
/// points, one mid node per side (shared sides share it), boundary edges gain their mid
/// node, the result validates and element sets are unchanged.
#[test]
fn to_p2_keeps_nodes_and_adds_one_mid_node_per_side() {
    for (name, p1) in p1_meshes() {
        let p2 = p1.to_p2().unwrap();
        p2.validate().unwrap();
        assert_eq!(p2.order, ElementOrder::P2, "{name}");
        assert_eq!(&p2.nodes[..p1.nodes.len()], &p1.nodes[..], "{name}");
        assert_eq!(p2.triangles.len(), p1.triangles.len(), "{name}");
        let mut sides: BTreeMap<(usize, usize), usize> = BTreeMap::new();
        for (t1, t2) in p1.triangles.iter().zip(&p2.triangles) {
            assert_eq!(&t2[..3], &t1[..], "{name}");
            for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                let (a, b, m) = (t1[i], t1[j], t2[3 + k]);
                assert!(m >= p1.nodes.len(), "{name}: mid node {m} is an old node");
                let (pa, pb) = (p1.nodes[a], p1.nodes[b]);
                assert_eq!(
                    p2.nodes[m],
                    [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])],
                    "{name}: mid node of side {a}–{b}"
                );
                let first = *sides.entry((a.min(b), a.max(b))).or_insert(m);
                assert_eq!(first, m, "{name}: side {a}–{b} has two mid nodes");
            }
        }
        assert_eq!(p2.nodes.len(), p1.nodes.len() + sides.len(), "{name}");
        let expected: Vec<BoundaryEdge> = p1
            .boundary_edges()
            .into_iter()
            .map(|e| {
                let (a, b) = (e.nodes[0], e.nodes[1]);
                BoundaryEdge {
                    nodes: vec![a, b, sides[&(a.min(b), a.max(b))]],
                }
            })
            .collect();
        assert_eq!(p2.boundary_edges(), expected, "{name}");
        assert_eq!(p2.element_sets, p1.element_sets, "{name}");
    }
}

/// (b) The area is unchanged: Σ det J / 2 from the corners, det J of the P2 map at
/// points inside each triangle (constant: the sides are straight), and the volumes of
/// the assembly's Gauss points.
#[test]
fn to_p2_keeps_the_area() {
    for (name, p1) in p1_meshes() {
        let p2 = p1.to_p2().unwrap();
        let area = |m: &Mesh| m.triangles.iter().map(|t| twice_area(m, t)).sum::<f64>() / 2.0;
        let (a1, a2) = (area(&p1), area(&p2));
        assert!((a1 - a2).abs() <= 1e-14 * a1, "{name}: {a1} vs {a2}");
        if name == "distorted" {
            assert!((a2 - common::AREA).abs() < 1e-12, "{name}: {a2}");
        }
        for (e, t) in p2.triangles.iter().enumerate() {
            let coords: Vec<[f64; 2]> = t.iter().map(|&n| p2.nodes[n]).collect();
            let det1 = twice_area(&p1, &p1.triangles[e]);
            for xi in [[0.0, 0.0], [0.2, 0.3], [0.6, 0.1], [0.1, 0.8]] {
                let det2 = jacobian_determinant(ElementOrder::P2, &coords, xi);
                assert!(
                    (det2 - det1).abs() <= 1e-12 * det1,
                    "{name}: triangle {e} at {xi:?}: det J {det2} vs {det1}"
                );
            }
        }
        let volume = |m: &Mesh| {
            let dofs = DofMap::new(m.nodes.len(), &[]).unwrap();
            let asm = Assembly::new(m, &dofs, 1.0).unwrap();
            asm.gauss_volumes.iter().sum::<f64>()
        };
        let (v1, v2) = (volume(&p1), volume(&p2));
        assert!((v1 - v2).abs() <= 1e-13 * v1, "{name}: {v1} vs {v2}");
        assert!((v1 - a1).abs() <= 1e-13 * a1, "{name}: {v1} vs {a1}");
    }
}

/// (c) `f` is quadratic with a positive definite Hessian, so P1 interpolation misses it
/// at every interior point (by ½ Σ N_a (x_a − x)ᵀ H (x_a − x) > 0) while P2 on the
/// converted mesh reproduces it.
#[test]
fn to_p2_reproduces_a_quadratic_field() {
    let f = |p: [f64; 2]| {
        let (x, y) = (p[0], p[1]);
        1.0 + 2.0 * x - 3.0 * y + 0.7 * x * x + 0.3 * x * y + 0.5 * y * y
    };
    let p1 = common::distorted_rectangle(ElementOrder::P1);
    let p2 = p1.to_p2().unwrap();
    let values: Vec<f64> = p2.nodes.iter().map(|&p| f(p)).collect();
    let mut smallest_p1_error = f64::INFINITY;
    for e in 0..p2.triangles.len() {
        for xi in [[0.2, 0.3], [0.1, 0.7], [0.45, 0.15], [1.0 / 3.0, 1.0 / 3.0]] {
            let x = p2.map_reference_point(e, xi).unwrap();
            let x1 = p1.map_reference_point(e, xi).unwrap();
            assert!(
                (x[0] - x1[0]).abs() < 1e-14 && (x[1] - x1[1]).abs() < 1e-14,
                "triangle {e}: the P2 map moved the point: {x:?} vs {x1:?}"
            );
            let interpolate = |order: ElementOrder, tri: &[usize]| -> f64 {
                order
                    .shape_functions(xi)
                    .iter()
                    .zip(tri)
                    .map(|(n, &a)| n * values[a])
                    .sum()
            };
            let exact = f(x);
            let quadratic = interpolate(ElementOrder::P2, &p2.triangles[e]);
            assert!(
                (quadratic - exact).abs() < 1e-13,
                "triangle {e} at {xi:?}: P2 {quadratic} vs f = {exact}"
            );
            // P1 on the original mesh: the old node indices are unchanged, so `values`
            // serves it too.
            let linear = interpolate(ElementOrder::P1, &p1.triangles[e]);
            smallest_p1_error = smallest_p1_error.min((linear - exact).abs());
        }
    }
    assert!(
        smallest_p1_error > 1e-4,
        "P1 reproduced the quadratic somewhere (error {smallest_p1_error:e})"
    );
}

/// (d) A P2 mesh is refused, the error naming its order.
#[test]
fn to_p2_of_a_p2_mesh_is_an_error_naming_the_order() {
    let p2 = Mesh::rectangle(&XS, &YS, ElementOrder::P2).unwrap();
    let converted = Mesh::rectangle(&XS, &YS, ElementOrder::P1)
        .unwrap()
        .to_p2()
        .unwrap();
    for mesh in [p2, converted] {
        let err = mesh.to_p2().unwrap_err();
        assert!(
            matches!(
                err,
                MeshError::InvalidInput {
                    field: "mesh order",
                    ..
                }
            ),
            "{err}"
        );
        assert!(err.to_string().contains("P2"), "{err}");
    }
}

/// Gmsh square (`common/gmsh_square.rs`): "bottom" (nodes 0, 1 and the edge 0–1) gains the
/// edge's mid node; "corner" (node 1 alone, no edge set) gains nothing; a node set with no
/// edge set gains the mid nodes of the sides with both ends in it, interior sides included.
#[test]
fn to_p2_node_and_edge_sets_of_a_gmsh_mesh() {
    let mut p1 = Mesh::from_msh_bytes(p1_file(P1_TRIANGLES).as_bytes()).unwrap();
    // the first triangle's corners (0, 0), (1, 0), (0.5, 0.5), and node 3 = (0, 1)
    p1.node_sets.insert("wedge".to_string(), vec![0, 1, 3, 4]);
    let p2 = p1.to_p2().unwrap();
    let node = |p: [f64; 2]| {
        p2.nodes
            .iter()
            .position(|&q| q == p)
            .unwrap_or_else(|| panic!("no node at {p:?}"))
    };
    let m01 = node([0.5, 0.0]);
    assert_eq!(
        p2.edge_sets["bottom"],
        vec![BoundaryEdge {
            nodes: vec![0, 1, m01]
        }]
    );
    assert_eq!(p2.node_sets["bottom"], vec![0, 1, m01]);
    assert_eq!(p2.node_sets["corner"], vec![1]);
    // sides 0–1, 1–4, 4–0, 3–0 (left side), 3–4; not 1–2, 2–3, 2–4
    let mut wedge = vec![
        0,
        1,
        3,
        4,
        m01,
        node([0.75, 0.25]),
        node([0.25, 0.25]),
        node([0.0, 0.5]),
        node([0.25, 0.75]),
    ];
    wedge.sort_unstable();
    assert_eq!(p2.node_sets["wedge"], wedge);
    assert_eq!(p2.element_sets, p1.element_sets);
    // The converted edge set is a boundary edge of the P2 mesh as it stands.
    assert_eq!(
        p2.orient_boundary_edges(&p2.edge_sets["bottom"]).unwrap(),
        p2.edge_sets["bottom"]
    );
}

/// The two-layer Gmsh mesh: element sets kept, both bottom lines gain their mid nodes,
/// and the P2 mesh assembles with the layers' areas.
#[test]
fn to_p2_of_the_gmsh_layers_keeps_element_sets() {
    let p1 = Mesh::from_msh_bytes(&gmsh_layers::layers().binary()).unwrap();
    let p2 = p1.to_p2().unwrap();
    assert_eq!(p2.element_sets, p1.element_sets);
    assert_eq!(p2.nodes.len(), 25); // the 5 × 5 grid of spacing 0.25
    for (k, edge) in p2.edge_sets["bottom"].iter().enumerate() {
        let (a, b) = (
            p1.edge_sets["bottom"][k].nodes[0],
            p1.edge_sets["bottom"][k].nodes[1],
        );
        assert_eq!(edge.nodes[..2], [a, b]);
        let x = 0.5 * (p2.nodes[a][0] + p2.nodes[b][0]);
        assert_eq!(p2.nodes[edge.nodes[2]], [x, 0.0]);
    }
    let bottom: Vec<usize> = (0..p2.nodes.len())
        .filter(|&n| p2.nodes[n][1] == 0.0)
        .collect();
    assert_eq!(p2.node_sets["bottom"], bottom);
    for layer in ["sand", "clay"] {
        let area: f64 = p2.element_sets[layer]
            .iter()
            .map(|&e| twice_area(&p2, &p2.triangles[e]) / 2.0)
            .sum();
        assert!((area - 0.5).abs() < 1e-15, "{layer}: {area}");
    }
}

/// An edge of an edge set that is the side of no triangle has no mid node: an error
/// naming the set and the edge.
#[test]
fn to_p2_refuses_an_edge_that_is_no_side() {
    let mut p1 = Mesh::from_msh_bytes(p1_file(P1_TRIANGLES).as_bytes()).unwrap();
    // the square's diagonal (0, 0)–(1, 1) passes through the centre node: no side
    p1.edge_sets.insert(
        "diagonal".to_string(),
        vec![BoundaryEdge { nodes: vec![0, 2] }],
    );
    let err = p1.to_p2().unwrap_err().to_string();
    assert!(
        err.contains("\"diagonal\"") && err.contains("[0, 2]") && err.contains("no triangle"),
        "{err}"
    );
}

/// A node set with an edge set of the same name gains the mid nodes of those edges only;
/// without one, of every side with both ends in it. The two rules differ on the lower right
/// corner triangle of the layers mesh, (0.5, 0), (1, 0), (1, 0.5): the boundary edges
/// along the corner versus also the diagonal (0.5, 0)–(1, 0.5).
#[test]
fn to_p2_node_set_follows_its_edge_set_when_there_is_one() {
    let mut p1 = Mesh::from_msh_bytes(gmsh_layers::layers().ascii().as_bytes()).unwrap();
    let at = |m: &Mesh, p: [f64; 2]| m.nodes.iter().position(|&q| q == p).unwrap();
    let (a, b, c) = (
        at(&p1, [0.5, 0.0]),
        at(&p1, [1.0, 0.0]),
        at(&p1, [1.0, 0.5]),
    );
    let corner = vec![
        BoundaryEdge { nodes: vec![a, b] },
        BoundaryEdge { nodes: vec![b, c] },
    ];
    let mut nodes = vec![a, b, c];
    nodes.sort_unstable();
    p1.edge_sets.insert("corner".to_string(), corner);
    p1.node_sets.insert("corner".to_string(), nodes.clone());
    p1.node_sets
        .insert("corner_nodes".to_string(), nodes.clone());
    let p2 = p1.to_p2().unwrap();
    let (m_ab, m_bc, m_ca) = (
        at(&p2, [0.75, 0.0]),
        at(&p2, [1.0, 0.25]),
        at(&p2, [0.75, 0.25]),
    );
    let sorted = |mut v: Vec<usize>| {
        v.sort_unstable();
        v
    };
    assert_eq!(
        p2.node_sets["corner"],
        sorted([nodes.clone(), vec![m_ab, m_bc]].concat())
    );
    assert_eq!(
        p2.node_sets["corner_nodes"],
        sorted([nodes, vec![m_ab, m_bc, m_ca]].concat())
    );
    assert_eq!(
        p2.edge_sets["corner"],
        vec![
            BoundaryEdge {
                nodes: vec![a, b, m_ab]
            },
            BoundaryEdge {
                nodes: vec![b, c, m_bc]
            },
        ]
    );
}
