//! `TetrahedralMesh::extrude`: a triangle mesh extruded along z into prisms, each cut into
//! 3 tetrahedra by the global numbering. On the unstructured slope mesh of
//! `scenes/slope.msh` (Gmsh's numbering, 2:1 slope of area 300 m²) and on a structured
//! rectangle, P1 and P2, over uneven layers:
//! - the volume is the area times the depth, every tetrahedron direct;
//! - conformity: every face is met by one or two tetrahedra, and the faces met once are
//!   exactly the two ends' triangles and two per boundary edge and layer (a side cut
//!   along different diagonals by its two prisms would leave 4 more per side);
//! - the boundary faces point outward: `∮ n dA = 0` and `⅓ ∮ x·n dA = V` (divergence
//!   theorem), and the extruded face sets `base`, `back`, `front` point along −y, −z, +z;
//! - the P2 patch test: a linear displacement gives its constant strain at every Gauss
//!   point, and prescribed on the boundary, the static elastic solve gives it back inside.
use crate::solid3d;

use std::collections::HashMap;
use std::path::Path;

use nalgebra::SVector;
use solid3d::{cross, dot, mul, solve_spd, split, stiffness, sub, tetrahedron_volume};
use talus_bipotential::mandel::isotropic_compliance;
use talus_fem::{Assembly, Constraint, DofMap, ElementOrder, Mesh, TetrahedralMesh};

const ZS: [f64; 4] = [-1.0, 0.5, 1.0, 3.0];
/// The largest side of the meshes (the slope's 40 m): the scale of coordinates' round-off.
const SIDE: f64 = 40.0;

fn slope(order: ElementOrder) -> Mesh {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/slope.msh");
    let mesh = Mesh::from_msh(&path).unwrap();
    match (order, mesh.order) {
        (ElementOrder::P1, ElementOrder::P1) | (ElementOrder::P2, ElementOrder::P2) => mesh,
        (ElementOrder::P2, ElementOrder::P1) => mesh.to_p2().unwrap(),
        // The P2 file's vertices and triangles, its mid-edge nodes left unused.
        (ElementOrder::P1, ElementOrder::P2) => {
            let mut used = vec![usize::MAX; mesh.nodes.len()];
            let mut nodes = Vec::new();
            let triangles = (mesh.triangles.iter())
                .map(|t| {
                    t[..3]
                        .iter()
                        .map(|&n| {
                            if used[n] == usize::MAX {
                                used[n] = nodes.len();
                                nodes.push(mesh.nodes[n]);
                            }
                            used[n]
                        })
                        .collect()
                })
                .collect();
            let mut p1 = Mesh {
                order: ElementOrder::P1,
                nodes,
                triangles,
                node_sets: Default::default(),
                edge_sets: Default::default(),
                element_sets: mesh.element_sets.clone(),
            };
            for (name, set) in &mesh.node_sets {
                let mut kept: Vec<usize> = (set.iter())
                    .filter(|&&n| used[n] != usize::MAX)
                    .map(|&n| used[n])
                    .collect();
                kept.sort_unstable();
                p1.node_sets.insert(name.clone(), kept);
            }
            for (name, set) in &mesh.edge_sets {
                let edges = set
                    .iter()
                    .map(|e| talus_fem::BoundaryEdge {
                        nodes: vec![used[e.nodes[0]], used[e.nodes[1]]],
                    })
                    .collect();
                p1.edge_sets.insert(name.clone(), edges);
            }
            p1
        }
    }
}

fn rectangle(order: ElementOrder) -> Mesh {
    Mesh::rectangle(&[0.0, 0.3, 1.0, 1.6], &[-0.5, 0.0, 0.7], order).unwrap()
}

fn meshes() -> Vec<(String, Mesh, f64)> {
    let mut all = Vec::new();
    for order in [ElementOrder::P1, ElementOrder::P2] {
        all.push((format!("slope {order:?}"), slope(order), 300.0));
        all.push((format!("rectangle {order:?}"), rectangle(order), 1.6 * 1.2));
    }
    all
}

fn area_normal(mesh: &TetrahedralMesh, nodes: &[usize]) -> [f64; 3] {
    let [a, b, c] = [0, 1, 2].map(|k| mesh.nodes[nodes[k]]);
    cross(sub(b, a), sub(c, a)).map(|v| 0.5 * v)
}

#[test]
fn extruded_volume_is_area_times_depth() {
    let depth = ZS[3] - ZS[0];
    for (name, mesh, area) in meshes() {
        let m = TetrahedralMesh::extrude(&mesh, &ZS).unwrap();
        m.check_elements().unwrap();
        assert_eq!(m.tetrahedra.len(), 3 * 3 * mesh.triangles.len(), "{name}");
        let volumes: Vec<f64> = (0..m.tetrahedra.len())
            .map(|e| tetrahedron_volume(&m, e))
            .collect();
        assert!(volumes.iter().all(|v| *v > 0.0), "{name}");
        let v: f64 = volumes.iter().sum();
        assert!(
            (v - area * depth).abs() < 1e-12 * area * depth,
            "{name}: {v}"
        );
        // Every node is used by some tetrahedron (none left without stiffness).
        let mut used = vec![false; m.nodes.len()];
        m.tetrahedra.iter().flatten().for_each(|&n| used[n] = true);
        assert!(used.iter().all(|u| *u), "{name}: unused nodes");
    }
}

#[test]
fn extruded_mesh_is_conforming() {
    for (name, mesh, _) in meshes() {
        let m = TetrahedralMesh::extrude(&mesh, &ZS).unwrap();
        let mut count: HashMap<[usize; 3], usize> = HashMap::new();
        for t in &m.tetrahedra {
            for f in talus_fem::mesh3::TETRAHEDRON_FACES {
                let mut k = f.map(|v| t[v]);
                k.sort_unstable();
                *count.entry(k).or_default() += 1;
            }
        }
        assert!(count.values().all(|c| *c == 1 || *c == 2), "{name}");
        let once = count.values().filter(|c| **c == 1).count();
        let layers = ZS.len() - 1;
        let edges = mesh.boundary_edges().len();
        assert_eq!(
            once,
            2 * mesh.triangles.len() + 2 * edges * layers,
            "{name}: boundary faces"
        );
        assert_eq!(m.boundary_faces().len(), once, "{name}");
        // P2: every edge's mid-node is one node for all its tetrahedra.
        if m.order == ElementOrder::P2 {
            let mut mids: HashMap<(usize, usize), usize> = HashMap::new();
            for t in &m.tetrahedra {
                for (k, (i, j)) in talus_fem::element::tet10::EDGES.iter().enumerate() {
                    let key = (t[*i].min(t[*j]), t[*i].max(t[*j]));
                    let mid = *mids.entry(key).or_insert(t[4 + k]);
                    assert_eq!(mid, t[4 + k], "{name}: edge {key:?}");
                    // At the edge's mid-point (straight edges), to the round-off of the
                    // file's coordinates: Gmsh writes the slope's 2.3e-12 m off (at 40 m).
                    let (a, b) = (m.nodes[t[*i]], m.nodes[t[*j]]);
                    let x = m.nodes[t[4 + k]];
                    for c in 0..3 {
                        let off = (x[c] - 0.5 * (a[c] + b[c])).abs();
                        assert!(off < 1e-12 * SIDE, "{name}: {x:?} {a:?} {b:?}");
                    }
                }
            }
        }
    }
}

#[test]
fn extruded_boundary_faces_point_outward() {
    for (name, mesh, area) in meshes() {
        let m = TetrahedralMesh::extrude(&mesh, &ZS).unwrap();
        let volume = area * (ZS[3] - ZS[0]);
        let (mut sum_n, mut flux) = ([0.0; 3], 0.0);
        for f in m.boundary_faces() {
            let n = area_normal(&m, &f.nodes);
            let centre: [f64; 3] =
                std::array::from_fn(|c| (0..3).map(|k| m.nodes[f.nodes[k]][c]).sum::<f64>() / 3.0);
            (0..3).for_each(|c| sum_n[c] += n[c]);
            flux += dot(centre, n) / 3.0;
        }
        assert!(
            sum_n.iter().all(|s| s.abs() < 1e-9 * area),
            "{name}: {sum_n:?}"
        );
        assert!(
            (flux - volume).abs() < 1e-9 * volume,
            "{name}: {flux} vs {volume}"
        );
        // The extruded sets: `base` (y at its lowest), the ends.
        let base_edges = if name.starts_with("slope") {
            mesh.edge_sets["base"].len()
        } else {
            mesh.edge_sets["bottom"].len()
        };
        let base = if name.starts_with("slope") {
            "base"
        } else {
            "bottom"
        };
        let sets = [
            (base, [0.0, -1.0, 0.0], 2 * base_edges * (ZS.len() - 1)),
            ("back", [0.0, 0.0, -1.0], mesh.triangles.len()),
            ("front", [0.0, 0.0, 1.0], mesh.triangles.len()),
        ];
        for (set, direction, n_faces) in sets {
            let faces = &m.face_sets[set];
            assert_eq!(faces.len(), n_faces, "{name}: {set}");
            for f in faces {
                let n = area_normal(&m, &f.nodes);
                let len = dot(n, n).sqrt();
                assert!(
                    dot(n, direction) > (1.0 - 1e-12) * len,
                    "{name}: {set} {n:?}"
                );
                assert_eq!(
                    f.nodes.len(),
                    if m.order == ElementOrder::P2 { 6 } else { 3 }
                );
            }
        }
        // A node set holds its 2D nodes at every level; `back` those at the first z.
        let levels = if m.order == ElementOrder::P2 { 7 } else { 4 };
        let nodes = &m.node_sets[base];
        assert_eq!(nodes.len(), levels * mesh.node_sets[base].len(), "{name}");
        assert!(nodes.windows(2).all(|w| w[0] < w[1]));
        assert!(nodes
            .iter()
            .all(|&n| m.nodes[n][1] == mesh.nodes[n % mesh.nodes.len()][1]));
        assert!(m.node_sets["back"].iter().all(|&n| m.nodes[n][2] == ZS[0]));
        assert_eq!(m.node_sets["front"].len(), mesh.nodes.len());
        // Element sets: every tetrahedron of the slope's `soil`.
        if name.starts_with("slope") {
            assert_eq!(m.element_sets["soil"].len(), m.tetrahedra.len());
        }
    }
}

const G: [[f64; 3]; 3] = [
    [0.013, -0.021, 0.007],
    [0.034, -0.008, -0.015],
    [-0.011, 0.026, 0.019],
];

fn linear(x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| 0.1 * i as f64 + (0..3).map(|j| G[i][j] * x[j]).sum::<f64>())
}

fn mandel_sym() -> SVector<f64, 6> {
    let s = std::f64::consts::SQRT_2;
    let e = |i: usize, j: usize| 0.5 * (G[i][j] + G[j][i]);
    SVector::from([
        e(0, 0),
        e(1, 1),
        e(2, 2),
        s * e(1, 2),
        s * e(0, 2),
        s * e(0, 1),
    ])
}

#[test]
fn extruded_p2_patch_test() {
    let s0 = isotropic_compliance::<6>(1.0e8, 0.3);
    let mesh = slope(ElementOrder::P2);
    let m = TetrahedralMesh::extrude(&mesh, &[0.0, 0.7, 2.0]).unwrap();
    // (a) a linear field strains every Gauss point by sym G.
    let dofs = DofMap::with_components(m.nodes.len(), 3, &[]).unwrap();
    let asm = Assembly::new(&m, &dofs, 1.0).unwrap();
    let (free, prescribed) = split(&dofs, |n, c| linear(m.nodes[n])[c]);
    let want = mandel_sym();
    for (p, e) in asm.strain(&free, &prescribed).unwrap().iter().enumerate() {
        assert!((e - want).amax() < 1e-12 * want.amax(), "point {p}: {e}");
    }
    // (b) prescribed on the boundary, the static solve gives it back inside.
    let mut boundary: Vec<usize> = (m.boundary_faces().iter())
        .flat_map(|f| f.nodes.clone())
        .collect();
    boundary.sort_unstable();
    boundary.dedup();
    let dofs = DofMap::with_components(m.nodes.len(), 3, &[(boundary, Constraint::Fixed)]).unwrap();
    assert!(dofs.n_free() > 1000, "{} free dofs", dofs.n_free());
    let asm = Assembly::new(&m, &dofs, 1.0).unwrap();
    let (k_ff, k_fp) = stiffness(&asm, &s0);
    let (exact, u_p) = split(&dofs, |n, c| linear(m.nodes[n])[c]);
    let rhs: Vec<f64> = mul(&k_fp, &u_p).iter().map(|f| -f).collect();
    let u_f = solve_spd(&k_ff, &rhs);
    let scale = exact.iter().fold(0.0f64, |s, u| s.max(u.abs()));
    for (i, (a, b)) in u_f.iter().zip(&exact).enumerate() {
        assert!((a - b).abs() < 1e-10 * scale, "free dof {i}: {a} vs {b}");
    }
    // A quadratic field is P2's too: u_x = x² gives ε_xx = 2x at each point, exactly.
    let dofs = DofMap::with_components(m.nodes.len(), 3, &[]).unwrap();
    let asm = Assembly::new(&m, &dofs, 1.0).unwrap();
    let (free, prescribed) = split(
        &dofs,
        |n, c| if c == 0 { m.nodes[n][0].powi(2) } else { 0.0 },
    );
    for (e, x) in asm
        .strain(&free, &prescribed)
        .unwrap()
        .iter()
        .zip(&asm.gauss_points)
    {
        assert!(
            (e[0] - 2.0 * x[0]).abs() < 1e-10 * 80.0,
            "{} vs {}",
            e[0],
            2.0 * x[0]
        );
    }
}

#[test]
fn extrusion_refuses_bad_input() {
    let mesh = rectangle(ElementOrder::P1);
    assert!(TetrahedralMesh::extrude(&mesh, &[0.0]).is_err());
    assert!(TetrahedralMesh::extrude(&mesh, &[0.0, 0.0]).is_err());
    assert!(TetrahedralMesh::extrude(&mesh, &[1.0, f64::NAN]).is_err());
    let mut named = mesh.clone();
    named.node_sets.insert("front".into(), vec![0]);
    let e = TetrahedralMesh::extrude(&named, &[0.0, 1.0]).unwrap_err();
    assert!(e.to_string().contains("front"), "{e}");
    let mut bad = mesh;
    bad.triangles[0].push(0);
    assert!(TetrahedralMesh::extrude(&bad, &[0.0, 1.0]).is_err());
}
