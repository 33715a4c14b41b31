//! Loads and lumped masses of tetrahedral meshes (`Assembly<6>`: `assembly/face_loads.rs`,
//! `assembly/mass.rs`) against identities and closed forms:
//! - (a) a uniform pressure `p` on a surface `S` with boundary curve `∂S` has resultant
//!   `−p ∫_S n dA = −(p/2) ∮ x × dx` and moment about the origin `−p ∫_S x × n dA =
//!   (p/2) ∮ |x|² dx` (Stokes' theorem with `φ = |x|²/2`: `∫_S n × ∇φ dA = ∮ φ dx`), for
//!   any surface shape, so also for the isoparametric P2 faces of a block whose every node
//!   (mid-edge nodes included) is jittered; on the closed surface of all six sides both
//!   vanish (`∮ n dA = 0`, `∮ x × n dA = 0`). The nodal forces satisfy them exactly: their
//!   integrands are polynomials of degree ≤ 4 (P2) in the face's reference coordinates,
//!   integrated exactly by Radon's 7-point rule, and the curve integrals (degree ≤ 5 in the
//!   edge's coordinate) by 3-point Gauss-Legendre;
//! - (b) a traction `t` on a flat side sums to `t A` and acts at the side's centroid; each
//!   flat P2 face sends nothing to its vertices and `t A_f / 3` to each mid-edge node
//!   (Zienkiewicz & Taylor, *The Finite Element Method*, vol. 1, 'Consistent load vectors':
//!   `∫ N_vertex dA = 0` and `∫ N_mid dA = A/3` on the 6-node triangle), a P1 face `t A_f/3`
//!   to each vertex;
//! - (c) hydrostatic water `p = γ (h − y)` on a vertical wall of height `h` and width `w`
//!   pushes it with `γ h² w / 2`, whose line of action lies `h/3` above the base (the
//!   centroid of the triangular load diagram), exactly for the linear `p` on flat faces;
//!   a water level at a grid line (`p = γ max(0, h_w − y)`, linear on every face) gives
//!   `γ h_w² w / 2` at `h_w/3`;
//! - (d) HRZ lumping (Hinton, Rock & Zienkiewicz, *Earthquake Eng. Struct. Dyn.* 4 (1976)
//!   245–249: `m_a = m_e ∫N_a² / Σ_b ∫N_b²`): P1 tetrahedra `m_e/4` per vertex; P2 ones,
//!   with `∫N_v² = V/70` and `∫N_e² = 8V/105` (Σ = 18V/35), `m_e/36` per vertex and
//!   `4m_e/27` per mid-edge node on affine elements; the total is `ρ V`;
//! - (e) refused input, each error naming its field: faces, pressure, traction, dofs, mesh.
//!
//! Tolerances are round-off: 1e-12 relative to each check's scale (`p` times a side's area
//! and arm, `|t| A`, `γ h² w/2`, `ρ V`), sums of at most a few thousand products; the
//! largest deviations measured are 7e-16 of the scale (resultants and moments), 2.5e-16
//! (hydrostatic resultant and line of action) and 6e-16 (masses).
use crate::solid3d;

use solid3d::{
    cross, distorted_block, dot, jitter, nodal, sub, tetrahedron_volume, vertex_flags, BOX_VOLUME,
    XS, YS, ZS,
};
use talus_fem::{
    Assembly, BoundaryFace, Constraint, DofMap, ElementOrder, FemError, Geometry, Mesh, MeshError,
    TetrahedralMesh,
};

const ORDERS: [ElementOrder; 2] = [ElementOrder::P1, ElementOrder::P2];
const SIDES: [&str; 6] = ["left", "right", "bottom", "top", "back", "front"];
const P: f64 = 7.0e4;

/// A block whose every node moves pseudo-randomly, sides included (up to 0.04 m along each
/// axis, a tenth of the smallest cell side), P2 mid-edge nodes by up to 0.02 m off their
/// edges' mid-points: non-planar sides, curved P2 faces.
fn warped_block(order: ElementOrder) -> TetrahedralMesh {
    let mut mesh = TetrahedralMesh::block(&XS, &YS, &ZS, order).unwrap();
    let mut next = jitter(0x2545_F491_4F6C_DD1D);
    let vertices = vertex_flags(&mesh);
    for (x, vertex) in mesh.nodes.iter_mut().zip(&vertices) {
        if *vertex {
            x.iter_mut().for_each(|c| *c += 0.04 * next());
        }
    }
    if order == ElementOrder::P2 {
        solid3d::place_mid_edge_nodes(&mut mesh);
        for (x, vertex) in mesh.nodes.iter_mut().zip(&vertices) {
            if !*vertex {
                x.iter_mut().for_each(|c| *c += 0.02 * next());
            }
        }
    }
    mesh.check_elements().unwrap();
    mesh
}

fn free_dofs(mesh: &TetrahedralMesh) -> DofMap {
    DofMap::with_components(mesh.nodes.len(), 3, &[]).unwrap()
}

/// `(Σ f_a, Σ x_a × f_a)`.
fn resultant_and_moment(mesh: &TetrahedralMesh, forces: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let (mut r, mut m) = ([0.0; 3], [0.0; 3]);
    for (x, f) in mesh.nodes.iter().zip(forces) {
        let xf = cross(*x, *f);
        for c in 0..3 {
            r[c] += f[c];
            m[c] += xf[c];
        }
    }
    (r, m)
}

/// `(½ ∮ x × dx, ½ ∮ |x|² dx)` along the boundary curve of a set of outward faces: the
/// edges met once, each run in its face's (counter-clockwise) direction, as the straight
/// (P1) or quadratic (P2, mid-edge node) curve of the faces' map; 3-point Gauss-Legendre
/// (exact to degree 5).
fn boundary_integrals(mesh: &TetrahedralMesh, faces: &[BoundaryFace]) -> ([f64; 3], [f64; 3]) {
    let mut edges = std::collections::HashMap::new();
    for f in faces {
        for k in 0..3 {
            let (a, b) = (f.nodes[k], f.nodes[(k + 1) % 3]);
            let mid = f.nodes.get(3 + k).copied();
            let key = (a.min(b), a.max(b));
            edges.entry(key).or_insert_with(Vec::new).push((a, b, mid));
        }
    }
    let gauss = [
        (0.5 - 0.5 * (0.6f64).sqrt(), 5.0 / 18.0),
        (0.5, 8.0 / 18.0),
        (0.5 + 0.5 * (0.6f64).sqrt(), 5.0 / 18.0),
    ];
    let (mut area, mut moment) = ([0.0; 3], [0.0; 3]);
    for list in edges.values().filter(|l| l.len() == 1) {
        let (a, b, mid) = list[0];
        let (xa, xb) = (mesh.nodes[a], mesh.nodes[b]);
        for (s, w) in gauss {
            let (x, dx): ([f64; 3], [f64; 3]) = match mid {
                None => (
                    std::array::from_fn(|c| (1.0 - s) * xa[c] + s * xb[c]),
                    sub(xb, xa),
                ),
                Some(m) => {
                    let xm = mesh.nodes[m];
                    let n = [
                        (1.0 - s) * (1.0 - 2.0 * s),
                        s * (2.0 * s - 1.0),
                        4.0 * s * (1.0 - s),
                    ];
                    let dn = [4.0 * s - 3.0, 4.0 * s - 1.0, 4.0 - 8.0 * s];
                    (
                        std::array::from_fn(|c| n[0] * xa[c] + n[1] * xb[c] + n[2] * xm[c]),
                        std::array::from_fn(|c| dn[0] * xa[c] + dn[1] * xb[c] + dn[2] * xm[c]),
                    )
                }
            };
            let xdx = cross(x, dx);
            let r2 = dot(x, x);
            for c in 0..3 {
                area[c] += 0.5 * w * xdx[c];
                moment[c] += 0.5 * w * r2 * dx[c];
            }
        }
    }
    (area, moment)
}

fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    (0..3).all(|c| (a[c] - b[c]).abs() <= tol)
}

#[test]
fn uniform_pressure_on_warped_sides_matches_their_boundary_curves() {
    for order in ORDERS {
        let mesh = warped_block(order);
        let dofs = free_dofs(&mesh);
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        // a side's area is about 6 m², its moment arm at most 4 m
        let (force_scale, moment_scale) = (P * 6.0, P * 6.0 * 4.0);
        let mut total = vec![[0.0; 3]; mesh.nodes.len()];
        for side in SIDES {
            let faces = &mesh.face_sets[side];
            let forces = nodal(&dofs, &asm.pressure(&mesh, faces, P).unwrap());
            let (r, m) = resultant_and_moment(&mesh, &forces);
            let (area, curl) = boundary_integrals(&mesh, faces);
            let want_r = area.map(|a| -P * a);
            let want_m = curl.map(|c| P * c);
            assert!(
                close(r, want_r, 1e-12 * force_scale),
                "{order:?} {side}: {r:?} vs {want_r:?}"
            );
            assert!(
                close(m, want_m, 1e-12 * moment_scale),
                "{order:?} {side}: {m:?} vs {want_m:?}"
            );
            // the side really is warped: its vector area is not axis-aligned
            let big = area.iter().fold(0.0f64, |m, a| m.max(a.abs()));
            assert!(
                area.iter().filter(|a| a.abs() > 1e-4 * big).count() == 3,
                "{side}: {area:?}"
            );
            for (t, f) in total.iter_mut().zip(&forces) {
                (0..3).for_each(|c| t[c] += f[c]);
            }
        }
        let (r, m) = resultant_and_moment(&mesh, &total);
        assert!(
            close(r, [0.0; 3], 1e-12 * force_scale),
            "{order:?}: closed surface {r:?}"
        );
        assert!(
            close(m, [0.0; 3], 1e-12 * moment_scale),
            "{order:?}: closed surface {m:?}"
        );
        // the same through one call on all the faces
        let all: Vec<BoundaryFace> = SIDES
            .iter()
            .flat_map(|s| mesh.face_sets[*s].clone())
            .collect();
        let forces = nodal(&dofs, &asm.pressure(&mesh, &all, P).unwrap());
        let (r, m) = resultant_and_moment(&mesh, &forces);
        assert!(
            close(r, [0.0; 3], 1e-12 * force_scale) && close(m, [0.0; 3], 1e-12 * moment_scale)
        );
    }
}

#[test]
fn uniform_pressure_on_flat_sides_is_p_times_area() {
    let areas = [
        2.0 * 1.5,
        2.0 * 1.5,
        3.0 * 1.5,
        3.0 * 1.5,
        3.0 * 2.0,
        3.0 * 2.0,
    ];
    let normals = [
        [-1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, -1.0],
        [0.0, 0.0, 1.0],
    ];
    for order in ORDERS {
        let mesh = distorted_block(order, 0.05);
        let dofs = free_dofs(&mesh);
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        for ((side, area), n) in SIDES.iter().zip(areas).zip(normals) {
            let forces = nodal(
                &dofs,
                &asm.pressure(&mesh, &mesh.face_sets[*side], P).unwrap(),
            );
            let (r, _) = resultant_and_moment(&mesh, &forces);
            let want = n.map(|c| -P * area * c);
            assert!(
                close(r, want, 1e-12 * P * area),
                "{order:?} {side}: {r:?} vs {want:?}"
            );
        }
    }
}

#[test]
fn traction_on_the_top_sums_to_t_times_area_with_p2_shares_zero_and_a_third() {
    let t = [1.0e3, -5.0e4, 2.0e3];
    let area = 3.0 * 1.5;
    let centroid = [1.5, 2.0, 0.75];
    for order in ORDERS {
        let mesh = distorted_block(order, 0.05);
        let dofs = free_dofs(&mesh);
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        let top = &mesh.face_sets["top"];
        let forces = nodal(&dofs, &asm.traction(&mesh, top, t).unwrap());
        let (r, _) = resultant_and_moment(&mesh, &forces);
        let scale = 5.0e4 * area;
        assert!(
            close(r, t.map(|c| c * area), 1e-12 * scale),
            "{order:?}: {r:?}"
        );
        // Σ x_a ⊗ f_a = A x̄ ⊗ t: the load acts at the side's centroid
        for i in 0..3 {
            for j in 0..3 {
                let m: f64 = mesh
                    .nodes
                    .iter()
                    .zip(&forces)
                    .map(|(x, f)| x[i] * f[j])
                    .sum();
                let want = area * centroid[i] * t[j];
                assert!(
                    (m - want).abs() < 1e-12 * scale * 3.0,
                    "{order:?} ({i}, {j}): {m} vs {want}"
                );
            }
        }
        // face by face
        for face in top {
            let x: Vec<[f64; 3]> = face.nodes.iter().map(|&n| mesh.nodes[n]).collect();
            let normal = cross(sub(x[1], x[0]), sub(x[2], x[0]));
            let a_f = 0.5 * dot(normal, normal).sqrt();
            let share = nodal(
                &dofs,
                &asm.traction(&mesh, std::slice::from_ref(face), t).unwrap(),
            );
            for (k, &node) in face.nodes.iter().enumerate() {
                let fraction = match (order, k) {
                    (ElementOrder::P1, _) => 1.0 / 3.0,
                    (ElementOrder::P2, 0..=2) => 0.0,
                    (ElementOrder::P2, _) => 1.0 / 3.0,
                };
                let want = t.map(|c| fraction * c * a_f);
                assert!(
                    close(share[node], want, 1e-12 * 5.0e4 * a_f),
                    "{order:?}: face {face:?} node {k}: {:?} vs {want:?}",
                    share[node]
                );
            }
            let loaded = share.iter().filter(|f| f.iter().any(|c| *c != 0.0)).count();
            assert!(loaded <= face.nodes.len());
        }
    }
}

#[test]
fn hydrostatic_pressure_on_a_wall_acts_at_a_third_of_its_height() {
    let gamma = 9810.0;
    let (h, w) = (YS[YS.len() - 1], ZS[ZS.len() - 1]);
    for order in ORDERS {
        for (mesh, level) in [
            (distorted_block(order, 0.05), h),
            // a water level at a grid line: p is linear on every face
            (TetrahedralMesh::block(&XS, &YS, &ZS, order).unwrap(), YS[2]),
        ] {
            let dofs = free_dofs(&mesh);
            let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
            let wall = &mesh.face_sets["right"];
            let f = asm
                .pressure_with(&mesh, wall, |x| gamma * (level - x[1]).max(0.0))
                .unwrap();
            let forces = nodal(&dofs, &f);
            let fx: f64 = forces.iter().map(|f| f[0]).sum();
            let want = -gamma * level * level * w / 2.0;
            assert!(
                (fx - want).abs() < 1e-12 * want.abs(),
                "{order:?}: {fx} vs {want}"
            );
            for c in 1..3 {
                let s: f64 = forces.iter().map(|f| f[c]).sum();
                assert!(
                    s.abs() < 1e-12 * want.abs(),
                    "{order:?}: component {c}: {s}"
                );
            }
            let y: f64 = mesh
                .nodes
                .iter()
                .zip(&forces)
                .map(|(x, f)| x[1] * f[0])
                .sum::<f64>()
                / fx;
            let z: f64 = mesh
                .nodes
                .iter()
                .zip(&forces)
                .map(|(x, f)| x[2] * f[0])
                .sum::<f64>()
                / fx;
            assert!(
                (y - level / 3.0).abs() < 1e-12 * h,
                "{order:?}: line of action at y = {y}"
            );
            assert!((z - w / 2.0).abs() < 1e-12 * w, "{order:?}: z = {z}");
        }
        // a constant p through `pressure_with` is `pressure`, to rounding
        let mesh = distorted_block(order, 0.05);
        let dofs = free_dofs(&mesh);
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        let faces = &mesh.face_sets["front"];
        let a = asm.pressure_with(&mesh, faces, |_| P).unwrap().0;
        let b = asm.pressure(&mesh, faces, P).unwrap().0;
        assert!(a.iter().zip(&b).all(|(a, b)| (a - b).abs() < 1e-12 * P));
    }
}

/// One affine, skewed tetrahedron (P2 nodes at the edges' mid-points).
fn one_tetrahedron(order: ElementOrder) -> TetrahedralMesh {
    let vertices = [
        [0.3, -0.2, 0.1],
        [1.4, 0.1, 0.3],
        [0.2, 1.1, -0.1],
        [0.5, 0.4, 1.2],
    ];
    let nodes: Vec<[f64; 3]> = order
        .tetrahedron_reference_nodes()
        .iter()
        .map(|xi| {
            let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
            std::array::from_fn(|k| (0..4).map(|v| l[v] * vertices[v][k]).sum())
        })
        .collect();
    TetrahedralMesh {
        order,
        tetrahedra: vec![(0..nodes.len()).collect()],
        nodes,
        node_sets: Default::default(),
        face_sets: Default::default(),
        element_sets: Default::default(),
    }
}

/// Mass of every node (the x dof's; y and z carry the same), free or prescribed.
fn nodal_masses(asm: &Assembly<6>, dofs: &DofMap) -> Vec<[f64; 3]> {
    dofs.nodal_vectors::<3>(&asm.lumped_mass_free, &asm.lumped_mass_prescribed)
        .unwrap()
}

#[test]
fn hrz_lumped_masses_of_tetrahedra() {
    let rho = 2000.0;
    for order in ORDERS {
        // (vertex, mid-edge) fractions of the element mass
        let (vertex, mid) = match order {
            ElementOrder::P1 => (1.0 / 4.0, 0.0),
            ElementOrder::P2 => (1.0 / 36.0, 4.0 / 27.0),
        };
        let mesh = one_tetrahedron(order);
        let m_e = rho * tetrahedron_volume(&mesh, 0);
        let dofs = free_dofs(&mesh);
        let asm = Assembly::new(&mesh, &dofs, rho).unwrap();
        for (k, m) in nodal_masses(&asm, &dofs).iter().enumerate() {
            let want = if k < 4 { vertex } else { mid } * m_e;
            for c in 0..3 {
                assert!(
                    (m[c] - want).abs() < 1e-13 * m_e,
                    "{order:?} node {k}: {m:?} vs {want}"
                );
            }
        }
        // on a block: each node gathers its elements' shares, free or prescribed, and the
        // total is ρ V of the box (its sides are flat)
        let mesh = distorted_block(order, 0.05);
        let dofs = DofMap::with_components(
            mesh.nodes.len(),
            3,
            &[(mesh.node_sets["bottom"].clone(), Constraint::FixY)],
        )
        .unwrap();
        let asm = Assembly::new(&mesh, &dofs, rho).unwrap();
        let mut want = vec![0.0; mesh.nodes.len()];
        for (e, t) in mesh.tetrahedra.iter().enumerate() {
            let m_e = rho * tetrahedron_volume(&mesh, e);
            for (k, &n) in t.iter().enumerate() {
                want[n] += if k < 4 { vertex } else { mid } * m_e;
            }
        }
        let masses = nodal_masses(&asm, &dofs);
        let total_mass = rho * BOX_VOLUME;
        for (k, (m, w)) in masses.iter().zip(&want).enumerate() {
            assert!(
                m.iter().all(|mc| (mc - w).abs() < 1e-12 * total_mass),
                "{order:?} node {k}: {m:?} vs {w}"
            );
        }
        let total: f64 = masses.iter().map(|m| m[0]).sum();
        assert!(
            (total - total_mass).abs() < 1e-12 * total_mass,
            "{order:?}: {total}"
        );
        assert!(asm.lumped_mass_free.iter().all(|m| *m > 0.0));
    }
}

fn field(err: &FemError) -> &'static str {
    match err {
        FemError::InvalidInput { field, .. } => field,
        FemError::Mesh(MeshError::InvalidInput { field, .. }) => field,
        other => panic!("unexpected error {other}"),
    }
}

#[test]
fn face_loads_and_assemblies_refuse_bad_input_by_name() {
    for order in ORDERS {
        let mesh = TetrahedralMesh::block(&[0.0, 1.0], &[0.0, 1.0], &[0.0, 1.0], order).unwrap();
        let dofs = free_dofs(&mesh);
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        let top = mesh.face_sets["top"].clone();
        // the other order's node count, and a node beyond the mesh
        let wrong = match order {
            ElementOrder::P1 => BoundaryFace {
                nodes: vec![top[0].nodes[0], top[0].nodes[1], top[0].nodes[2], 0, 1, 2],
            },
            ElementOrder::P2 => BoundaryFace {
                nodes: top[0].nodes[..3].to_vec(),
            },
        };
        let mut beyond = top[0].clone();
        beyond.nodes[1] = mesh.nodes.len();
        for face in [wrong, beyond] {
            let faces = std::slice::from_ref(&face);
            for err in [
                asm.pressure(&mesh, faces, 1.0).unwrap_err(),
                asm.pressure_with(&mesh, faces, |_| 1.0).unwrap_err(),
                asm.traction(&mesh, faces, [0.0, 1.0, 0.0]).unwrap_err(),
            ] {
                assert_eq!(field(&err), "faces", "{order:?}: {err}");
                assert!(err.to_string().contains("faces"), "{err}");
            }
        }
        for p in [f64::NAN, f64::INFINITY] {
            let err = asm.pressure(&mesh, &top, p).unwrap_err();
            assert_eq!(field(&err), "pressure", "{err}");
        }
        // p(x) not finite somewhere: the error names the face and its nodes
        let err = asm
            .pressure_with(&mesh, &top, |x| if x[0] > 0.5 { f64::NAN } else { 1.0 })
            .unwrap_err();
        assert_eq!(field(&err), "pressure", "{err}");
        assert!(err.to_string().contains("of face"), "{err}");
        let err = asm.traction(&mesh, &top, [0.0, f64::NAN, 0.0]).unwrap_err();
        assert_eq!(field(&err), "traction", "{err}");
        // a mesh other than the assembly's
        let other =
            TetrahedralMesh::block(&[0.0, 1.0, 2.0], &[0.0, 1.0], &[0.0, 1.0], order).unwrap();
        let err = asm
            .pressure(&other, &other.face_sets["top"], 1.0)
            .unwrap_err();
        assert_eq!(field(&err), "mesh", "{err}");

        // a 2-component dof map on tetrahedra
        let dofs2 = DofMap::new(mesh.nodes.len(), &[]).unwrap();
        let err = Assembly::new(&mesh, &dofs2, 1.0).unwrap_err();
        assert_eq!(field(&err), "dofs", "{err}");
        // tetrahedra outside 3D
        for geometry in [Geometry::PlaneStrain, Geometry::Axisymmetric] {
            let err = Assembly::with_geometry(&mesh, &dofs, 1.0, geometry).unwrap_err();
            assert_eq!(field(&err), "mesh", "{err}");
            assert!(err.to_string().contains("tetrahedral mesh"), "{err}");
        }
        // triangles in 3D, and a 3-component map on triangles
        let triangles = Mesh::rectangle(&[0.0, 1.0], &[0.0, 1.0], order).unwrap();
        let dofs2 = DofMap::new(triangles.nodes.len(), &[]).unwrap();
        let err = Assembly::with_geometry(&triangles, &dofs2, 1.0, Geometry::ThreeDimensional)
            .unwrap_err();
        assert_eq!(field(&err), "mesh", "{err}");
        assert!(err.to_string().contains("triangle mesh"), "{err}");
        let dofs3 = DofMap::with_components(triangles.nodes.len(), 3, &[]).unwrap();
        let err = Assembly::new(&triangles, &dofs3, 1.0).unwrap_err();
        assert_eq!(field(&err), "dofs", "{err}");
    }
}

/// A face given inward (its vertices reversed) is turned outward before the pressure is
/// integrated, as 2D edges are oriented by their triangle: the forces equal those of the
/// outward faces bit for bit. A face between two tetrahedra carries no surface load: it is
/// refused naming `faces`, and so is a triangle that is no face of the mesh.
#[test]
fn faces_are_oriented_outward_and_interior_faces_refused() {
    for order in ORDERS {
        let mesh = distorted_block(order, 0.05);
        let dofs = free_dofs(&mesh);
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        let outward = &mesh.face_sets["top"];
        let inward: Vec<BoundaryFace> = outward
            .iter()
            .map(|f| {
                let mut nodes = f.nodes.clone();
                nodes.swap(1, 2); // vertices 0, 2, 1: the other side
                if nodes.len() == 6 {
                    // mid-edge nodes of edges 02, 21, 10 in that order
                    nodes[3..].copy_from_slice(&[f.nodes[5], f.nodes[4], f.nodes[3]]);
                }
                BoundaryFace { nodes }
            })
            .collect();
        let p = asm.pressure(&mesh, outward, P).unwrap();
        assert_eq!(asm.pressure(&mesh, &inward, P).unwrap(), p, "{order:?}");
        // The top's pressure pushes down.
        let (r, _) = resultant_and_moment(&mesh, &nodal(&dofs, &p));
        assert!(r[1] < 0.0, "{order:?}: {r:?}");
        // Tetrahedron 0's faces that another tetrahedron shares are interior.
        let counts = |f: usize| {
            let mut key: Vec<usize> = talus_fem::mesh3::TETRAHEDRON_FACES[f]
                .iter()
                .map(|&v| mesh.tetrahedra[0][v])
                .collect();
            key.sort_unstable();
            mesh.tetrahedra
                .iter()
                .filter(|t| key.iter().all(|n| t[..4].contains(n)))
                .count()
        };
        let f = (0..4).find(|&f| counts(f) == 2).expect("an interior face");
        let interior = mesh.boundary_face(0, f);
        let err = asm
            .pressure(&mesh, std::slice::from_ref(&interior), P)
            .unwrap_err();
        assert_eq!(field(&err), "faces", "{err}");
        assert!(err.to_string().contains("not on the boundary"), "{err}");
        let err = asm
            .traction(&mesh, &[interior], [0.0, -P, 0.0])
            .unwrap_err();
        assert_eq!(field(&err), "faces", "{err}");
    }
}
