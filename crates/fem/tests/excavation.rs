//! Construction in stages: `Mesh::submesh` and the excavation primitives of
//! `talus_fem::excavation` (`element_forces`, `restrict_state`, `restrict_forces`,
//! `kept_points`).
//!
//! - The submesh of a rectangle's lower half: counts, area and sets against the grid.
//! - The force of a removed block under a uniform stress: `F_a = −∮ N_a σ·n ds` over the
//!   block's boundary, Simpson's weights on straight P2 edges (closed form), and `Σ F` the
//!   block's weight for any stress.
//! - An elastic block under gravity, at rest from a direct solve `K u = f`: its top half
//!   (or its top right quarter, for a 2D release) removed, the kept part balances under
//!   its weight and `F` alone; and releasing `F` through the engine (a load ramped from 1
//!   to 0, negligible masses) gives the kept body's direct elastic solve `K_K Δu = −F`.
//! - `restrict_state` against fields that are functions of position.
use crate::common;

use common::dense;
use nalgebra::{DMatrix, DVector, SMatrix};
use talus_bipotential::{Elastic, Material};
use talus_engine::{Ramp, StepSettings, Stepper};
use talus_fem::{
    element_forces, kept_points, restrict_forces, restrict_state, Assembly, BoundaryEdge,
    Constraint, Dof, DofMap, ElementOrder, FemError, Mesh, MeshError, Model, State,
};

const GRAVITY: [f64; 2] = [0.0, -9.81];

fn centroid(mesh: &Mesh, e: usize) -> [f64; 2] {
    let t = &mesh.triangles[e];
    let c = |k: usize| (0..3).map(|i| mesh.nodes[t[i]][k]).sum::<f64>() / 3.0;
    [c(0), c(1)]
}

/// The triangles whose centroid is above (`true`) or below `y`.
fn split_at(mesh: &Mesh, y: f64) -> (Vec<usize>, Vec<usize>) {
    (0..mesh.triangles.len()).partition(|&e| centroid(mesh, e)[1] > y)
}

fn corner_area(mesh: &Mesh) -> f64 {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = [mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]]];
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
        })
        .sum()
}

#[test]
fn submesh_of_the_lower_half_of_a_p2_rectangle() {
    // 2 × 4 cells on [0, 2] × [0, 2]; P2: a 5 × 9 grid of nodes, row by row from the bottom.
    let ys = [0.0, 0.5, 1.0, 1.5, 2.0];
    let mesh = Mesh::rectangle(&[0.0, 1.0, 2.0], &ys, ElementOrder::P2).unwrap();
    assert_eq!((mesh.nodes.len(), mesh.triangles.len()), (45, 16));
    let (upper, lower) = split_at(&mesh, 1.0);
    assert_eq!((upper.len(), lower.len()), (8, 8));
    // Any order: reversed.
    let reversed: Vec<usize> = lower.iter().rev().copied().collect();
    let (sub, map) = mesh.submesh(&reversed).unwrap();
    sub.validate().unwrap();

    // Nodes: the 5 × 5 rows with y ≤ 1, the first 25 of the grid, in the same order.
    assert_eq!(sub.nodes.len(), 25);
    for (old, new) in map.iter().enumerate() {
        let kept = mesh.nodes[old][1] <= 1.0;
        assert_eq!(
            *new,
            kept.then_some(old),
            "node {old} at {:?}",
            mesh.nodes[old]
        );
    }
    assert_eq!(sub.nodes[..], mesh.nodes[..25]);
    // Triangles: the kept ones in increasing old index, their nodes renumbered.
    assert_eq!(sub.triangles.len(), 8);
    for (k, &e) in lower.iter().enumerate() {
        let renumbered: Vec<usize> = mesh.triangles[e].iter().map(|&n| map[n].unwrap()).collect();
        assert_eq!(sub.triangles[k], renumbered);
    }
    // Area 2 × 1 by the corners and by the Gauss volumes of an assembly.
    assert!((corner_area(&sub) - 2.0).abs() < 1e-14);
    let dofs = DofMap::new(
        sub.nodes.len(),
        &[(sub.node_sets["bottom"].clone(), Constraint::Fixed)],
    )
    .unwrap();
    let asm = Assembly::new(&sub, &dofs, 1.0).unwrap();
    assert!((asm.gauss_volumes.iter().sum::<f64>() - 2.0).abs() < 1e-14);

    // Node sets: their kept nodes; "top" (y = 2) is left empty, under its name.
    let column = |i: usize| (0..5).map(|j| 5 * j + i).collect::<Vec<_>>();
    assert_eq!(sub.node_sets["bottom"], vec![0, 1, 2, 3, 4]);
    assert_eq!(sub.node_sets["left"], column(0));
    assert_eq!(sub.node_sets["right"], column(4));
    assert_eq!(sub.node_sets["top"], Vec::<usize>::new());
    // Edge sets: the sides' edges still there, in their direction; "top" empty.
    assert_eq!(sub.edge_sets["bottom"], mesh.edge_sets["bottom"]);
    assert_eq!(
        sub.edge_sets["left"],
        vec![
            BoundaryEdge {
                nodes: vec![20, 10, 15]
            },
            BoundaryEdge {
                nodes: vec![10, 0, 5]
            },
        ]
    );
    assert_eq!(
        sub.edge_sets["right"],
        vec![
            BoundaryEdge {
                nodes: vec![4, 14, 9]
            },
            BoundaryEdge {
                nodes: vec![14, 24, 19]
            },
        ]
    );
    assert!(sub.edge_sets["top"].is_empty());
    // The new surface y = 1 is on the boundary, in no set.
    let new_top: Vec<BoundaryEdge> = sub
        .boundary_edges()
        .into_iter()
        .filter(|e| e.nodes.iter().all(|&n| sub.nodes[n][1] == 1.0))
        .collect();
    assert_eq!(new_top.len(), 2);
    assert!(sub
        .edge_sets
        .values()
        .all(|set| new_top.iter().all(|e| !set.contains(e))));
    assert!(sub.element_sets.is_empty());
}

#[test]
fn submesh_edge_and_element_sets() {
    // P1, 3 × 1 cells on [0, 3] × [0, 1]. Cell 1 (triangles 2, 3) has the diagonal
    // (2, 0)–(1, 1); triangle 3 = (2, 0), (2, 1), (1, 1) holds the top edge (2, 1)–(1, 1),
    // whose ends stay with triangles 2 and 4, 5.
    let mut mesh = Mesh::rectangle(&[0.0, 1.0, 2.0, 3.0], &[0.0, 1.0], ElementOrder::P1).unwrap();
    let node = |x: f64, y: f64| mesh.nodes.iter().position(|p| *p == [x, y]).unwrap();
    let (n20, n11, n10, n21) = (
        node(2.0, 0.0),
        node(1.0, 1.0),
        node(1.0, 0.0),
        node(2.0, 1.0),
    );
    assert_eq!(mesh.triangles[3], vec![n20, n21, n11]);
    // An interior side that the excavation lays bare, and one that stays inside.
    mesh.edge_sets.insert(
        "floor".into(),
        vec![BoundaryEdge {
            nodes: vec![n11, n20],
        }],
    );
    mesh.edge_sets.insert(
        "inner".into(),
        vec![BoundaryEdge {
            nodes: vec![n10, n11],
        }],
    );
    mesh.element_sets.insert("a".into(), vec![1, 3, 5]);
    mesh.element_sets.insert("b".into(), vec![3]);
    mesh.validate().unwrap();

    let (sub, map) = mesh.submesh(&[5, 0, 4, 2, 1]).unwrap();
    sub.validate().unwrap();
    assert_eq!(sub.nodes.len(), mesh.nodes.len(), "every node stays");
    assert!(map.iter().enumerate().all(|(i, m)| *m == Some(i)));
    assert_eq!(sub.triangles.len(), 5);
    // The top edge over the pit goes though its nodes stay; the others stay.
    let top: Vec<[[f64; 2]; 2]> = sub.edge_sets["top"]
        .iter()
        .map(|e| [sub.nodes[e.nodes[0]], sub.nodes[e.nodes[1]]])
        .collect();
    assert_eq!(
        top,
        vec![[[3.0, 1.0], [2.0, 1.0]], [[1.0, 1.0], [0.0, 1.0]]]
    );
    assert_eq!(sub.edge_sets["bottom"], mesh.edge_sets["bottom"]);
    // "floor" now bounds the pit, and loads it outward once oriented; "inner" stays.
    assert_eq!(sub.edge_sets["floor"], mesh.edge_sets["floor"]);
    let oriented = sub.orient_boundary_edges(&sub.edge_sets["floor"]).unwrap();
    assert_eq!(
        oriented,
        vec![BoundaryEdge {
            nodes: vec![n20, n11]
        }]
    );
    assert_eq!(sub.edge_sets["inner"], mesh.edge_sets["inner"]);
    assert!(!sub.boundary_edges().iter().any(|e| {
        let mut n = e.nodes.clone();
        n.sort_unstable();
        n == vec![n10, n11]
    }));
    // Element sets renumbered: old 0, 1, 2, 4, 5 -> 0, 1, 2, 3, 4.
    assert_eq!(sub.element_sets["a"], vec![1, 4]);
    assert_eq!(sub.element_sets["b"], Vec::<usize>::new());
}

#[test]
fn submesh_errors_name_elements_and_the_index() {
    let mesh = Mesh::rectangle(&[0.0, 1.0, 2.0], &[0.0, 1.0], ElementOrder::P2).unwrap();
    let field = |e: MeshError| match e {
        MeshError::InvalidInput { field, reason } => (field, reason),
        other => panic!("{other}"),
    };
    let (f, r) = field(mesh.submesh(&[]).unwrap_err());
    assert_eq!(f, "elements");
    assert!(r.contains("no triangle"), "{r}");
    let (f, r) = field(mesh.submesh(&[0, 4]).unwrap_err());
    assert_eq!(f, "elements");
    assert!(
        r.contains("entry 1 is triangle 4") && r.contains("4 triangles"),
        "{r}"
    );
    let (f, r) = field(mesh.submesh(&[2, 0, 2]).unwrap_err());
    assert_eq!(f, "elements");
    assert!(r.contains("entry 2 names triangle 2 a second time"), "{r}");
}

/// A P2 block [0, 2] × [0, 2] of 4 × 4 cells, bottom fixed, sides on rollers, elastic
/// (E = 10 MPa, ν = 0.3), weighing `RHO_W` kg/m³, with inertial density `rho_mass`.
const RHO_W: f64 = 2000.0;
const E: f64 = 1e7;
const NU: f64 = 0.3;

fn constraints(mesh: &Mesh) -> Vec<(Vec<usize>, Constraint)> {
    vec![
        (mesh.node_sets["bottom"].clone(), Constraint::Fixed),
        (mesh.node_sets["left"].clone(), Constraint::FixX),
        (mesh.node_sets["right"].clone(), Constraint::FixX),
    ]
}

/// The elastic model on `mesh` with its weight (no ramp).
fn elastic_model(mesh: Mesh, rho_mass: f64) -> Model {
    let dofs = DofMap::new(mesh.nodes.len(), &constraints(&mesh)).unwrap();
    let asm = Assembly::new(&mesh, &dofs, rho_mass).unwrap();
    let weight = asm.body_force(RHO_W, GRAVITY).unwrap();
    let mut model = Model::new(
        mesh,
        asm,
        Material::Elastic(Elastic::try_new(E, NU).unwrap()),
    );
    model.add_load(weight, None);
    model
}

fn block(rho_mass: f64) -> Model {
    let c = [0.0, 0.5, 1.0, 1.5, 2.0];
    elastic_model(Mesh::rectangle(&c, &c, ElementOrder::P2).unwrap(), rho_mass)
}

/// The dense stiffness on the free dofs, `K = Σ_p b_pᵀ (V_p S₀)⁻¹ b_p` (`b_p` the row block
/// of point p in `B_free`), as `tests/elastic_step.rs` assembles `Bᵀ S⁻¹ B`.
fn stiffness(model: &Model) -> DMatrix<f64> {
    let asm = &model.assembly;
    let b = dense(&asm.b_free);
    let mut k = DMatrix::zeros(b.ncols(), b.ncols());
    for p in 0..asm.n_points() {
        let s_inv = (model.compliance_at(p) * asm.gauss_volumes[p])
            .try_inverse()
            .unwrap();
        let bp = b.rows(4 * p, 4);
        k += bp.transpose() * s_inv * bp;
    }
    k
}

/// σ_p = S₀⁻¹ ε_p of the free displacements `u` (prescribed ones 0).
fn elastic_stress(model: &Model, u: &[f64]) -> Vec<f64> {
    let asm = &model.assembly;
    let strain = asm
        .strain(u, &vec![0.0; asm.dofs().n_prescribed()])
        .unwrap();
    let mut sigma = Vec::with_capacity(4 * strain.len());
    for (p, e) in strain.iter().enumerate() {
        let s0: &SMatrix<f64, 4, 4> = model.compliance_at(p);
        sigma.extend_from_slice((s0.try_inverse().unwrap() * e).as_slice());
    }
    sigma
}

/// The model's state at rest under its weight: `K u = f` solved directly (LU).
fn at_rest(model: &Model) -> State {
    let asm = &model.assembly;
    let dofs = asm.dofs();
    let f = DVector::from_vec(model.force_free.clone());
    let u = stiffness(model).lu().solve(&f).unwrap();
    let mut state = State::at_rest(
        asm.n_points(),
        dofs.n_free(),
        dofs.n_prescribed(),
        model.mesh.nodes.len(),
    );
    state.sigma = elastic_stress(model, u.as_slice());
    state.displacement = dofs
        .scatter(u.as_slice(), &vec![0.0; dofs.n_prescribed()])
        .unwrap();
    state
}

fn amax(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// `Bᵀσ − f − extra` on the free dofs.
fn free_residual(model: &Model, sigma: &[f64], extra: &[f64]) -> Vec<f64> {
    let (internal, _) = model.assembly.internal_force(sigma).unwrap();
    (0..internal.len())
        .map(|i| internal[i] - model.force_free[i] - extra[i])
        .collect()
}

#[test]
fn removed_block_pushes_with_its_boundary_stress_and_weighs_its_weight() {
    let model = block(RHO_W);
    let n = model.n_points();
    let (removed, _) = split_at(&model.mesh, 1.0);
    let mesh = &model.mesh;

    // Uniform σ = (−q, −p, −q, 0), weightless: F_a = −∮_{∂R} N_a σ·n ds over R = [0, 2] × [1, 2],
    // on straight P2 edges of length L = 0.5 the weights L/6 (each end) and 2L/3 (mid).
    let (p, q) = (3e4, 1e4);
    let mut state = State::at_rest(n, 0, 0, mesh.nodes.len());
    state.sigma = (0..n).flat_map(|_| [-q, -p, -q, 0.0]).collect();
    let f = element_forces(&model, &state, &removed, GRAVITY, &vec![0.0; n]).unwrap();
    let weight = |s: f64, length: f64| {
        // s: position along a side of R from 0 to `length` (node spacing 0.25)
        let (k, last) = (
            (s / 0.25).round() as usize,
            (length / 0.25).round() as usize,
        );
        let l = 0.5;
        if k % 2 == 1 {
            2.0 * l / 3.0
        } else if k == 0 || k == last {
            l / 6.0
        } else {
            l / 3.0
        }
    };
    let tol = 1e-12 * p;
    for (a, x) in mesh.nodes.iter().enumerate() {
        let mut expected = [0.0; 2];
        // σ·n on each side: bottom (y = 1, n = −y) p ŷ; top (n = +y) −p ŷ; left (x = 0,
        // n = −x) q x̂; right (n = +x) −q x̂.
        if x[1] >= 1.0 {
            if x[1] == 1.0 {
                expected[1] -= p * weight(x[0], 2.0);
            }
            if x[1] == 2.0 {
                expected[1] += p * weight(x[0], 2.0);
            }
            if x[0] == 0.0 {
                expected[0] -= q * weight(x[1] - 1.0, 1.0);
            }
            if x[0] == 2.0 {
                expected[0] += q * weight(x[1] - 1.0, 1.0);
            }
        }
        for c in 0..2 {
            assert!(
                (f[a][c] - expected[c]).abs() < tol,
                "node {a} at {x:?}, component {c}: {} N/m against {} N/m",
                f[a][c],
                expected[c]
            );
        }
    }

    // Any stress, with weight: Σ F is the weight of R, 2 m² × ρ g (a translation strains
    // nothing).
    state.sigma = (0..4 * n)
        .map(|k| 1e4 * ((k as f64) * 0.731).sin())
        .collect();
    let f = element_forces(&model, &state, &removed, GRAVITY, &vec![RHO_W; n]).unwrap();
    let sum = f.iter().fold([0.0; 2], |s, v| [s[0] + v[0], s[1] + v[1]]);
    let w = RHO_W * 9.81 * 2.0;
    assert!(sum[0].abs() < 1e-11 * w, "{sum:?}");
    assert!((sum[1] + w).abs() < 1e-11 * w, "{sum:?} against {w}");

    // Errors name their input.
    let bad = |e: FemError| match e {
        FemError::InvalidInput { field, .. } => field,
        other => panic!("{other}"),
    };
    let rho = vec![RHO_W; n];
    assert_eq!(
        bad(element_forces(&model, &state, &[], GRAVITY, &rho).unwrap_err()),
        "elements"
    );
    assert_eq!(
        bad(element_forces(&model, &state, &[0, 0], GRAVITY, &rho).unwrap_err()),
        "elements"
    );
    assert_eq!(
        bad(element_forces(&model, &state, &[32], GRAVITY, &rho).unwrap_err()),
        "elements"
    );
    assert_eq!(
        bad(element_forces(&model, &state, &[0], GRAVITY, &rho[1..]).unwrap_err()),
        "densities"
    );
}

#[test]
fn restrict_state_follows_points_and_nodes() {
    let model = block(RHO_W);
    let asm = &model.assembly;
    let dofs = asm.dofs();
    let (_, kept) = split_at(&model.mesh, 1.0);
    let (sub, map) = model.mesh.submesh(&kept).unwrap();
    let kept_model = elastic_model(sub, RHO_W);
    // A state whose every field is a function of position.
    let field = |x: [f64; 2], k: usize| (k as f64 + 1.0) * (x[0] + 0.37 * x[1] * x[1]);
    let mut state = State::at_rest(
        asm.n_points(),
        dofs.n_free(),
        dofs.n_prescribed(),
        model.mesh.nodes.len(),
    );
    state.time = 3.5;
    for (p, x) in asm.gauss_points.iter().enumerate() {
        for k in 0..4 {
            state.sigma[4 * p + k] = field(*x, k);
        }
        state.plastic_strain[p] = field(*x, 7);
    }
    for (n, x) in model.mesh.nodes.iter().enumerate() {
        state.displacement[n] = [field(*x, 4), field(*x, 5)];
        for c in 0..2 {
            match dofs.dof(n, c).unwrap() {
                Dof::Free(i) => state.velocity_free[i] = field(*x, 8 + c),
                Dof::Prescribed(j) => state.velocity_prescribed[j] = field(*x, 8 + c),
            }
        }
    }
    let points = kept_points(&model, &kept).unwrap();
    let out = restrict_state(&model, &state, &kept_model, &kept, &map).unwrap();
    let kasm = &kept_model.assembly;
    assert_eq!(points.len(), kasm.n_points());
    assert_eq!(out.time, 3.5);
    for (p, x) in kasm.gauss_points.iter().enumerate() {
        assert_eq!(*x, asm.gauss_points[points[p]]);
        for k in 0..4 {
            assert_eq!(out.sigma[4 * p + k], field(*x, k));
        }
        assert_eq!(out.plastic_strain[p], field(*x, 7));
    }
    let v = kasm
        .dofs()
        .scatter(&out.velocity_free, &out.velocity_prescribed)
        .unwrap();
    for (n, x) in kept_model.mesh.nodes.iter().enumerate() {
        assert_eq!(out.displacement[n], [field(*x, 4), field(*x, 5)]);
        assert_eq!(v[n], [field(*x, 8), field(*x, 9)]);
    }
    // A kept model of other triangles is refused.
    let (upper, _) = split_at(&model.mesh, 1.0);
    let e = restrict_state(&model, &state, &kept_model, &upper, &map).unwrap_err();
    assert!(
        matches!(e, FemError::InvalidInput { field: "kept", .. }),
        "{e}"
    );
}

#[test]
fn excavated_block_balances_and_releases_like_a_direct_solve() {
    // The top half (the body's state and its release are 1D: oedometric), and the top
    // right quarter (a pit with a wall at x = 1: a 2D release, F_x at the wall).
    let [fx, f] = excavate("top half", |c| c[1] > 1.0);
    assert!(fx < 1e-12 * f, "{fx:e} of {f:e}");
    let [fx, f] = excavate("top right quarter", |c| c[1] > 1.0 && c[0] > 1.0);
    assert!(fx > 0.1 * f, "{fx:e} of {f:e}");
}

/// The block at rest under its weight, the triangles whose centroid `dug` selects removed:
/// checks the balance of the kept part and its release; returns the largest horizontal
/// and the largest component of `F` on the kept free dofs (N/m).
fn excavate(label: &str, dug: fn([f64; 2]) -> bool) -> [f64; 2] {
    // Inertia negligible: with h = 0.25 s, M/h² ≈ 2.4e-6 of the stiffness (checked below).
    // The velocity update's round-off, ε_machine over that ratio (1e-9 at 2.4e-7), bounds
    // it from below.
    let (t_end, steps, held) = (1.0, 4, 4);
    let h = t_end / steps as f64;
    let rho_mass = 100.0;
    let model = block(rho_mass);
    let state = at_rest(&model);
    let n = model.n_points();
    let scale = amax(&model.force_free);
    // The full block is at rest (the direct solve's round-off).
    let r = free_residual(&model, &state.sigma, &vec![0.0; model.force_free.len()]);
    assert!(amax(&r) < 1e-11 * scale, "{:e}", amax(&r) / scale);

    let (removed, kept): (Vec<usize>, Vec<usize>) =
        (0..model.mesh.triangles.len()).partition(|&e| dug(centroid(&model.mesh, e)));
    let forces = element_forces(&model, &state, &removed, GRAVITY, &vec![RHO_W; n]).unwrap();
    let (sub, map) = model.mesh.submesh(&kept).unwrap();
    // The nodes that go with the removed part carry no force (at rest, free dofs).
    for (a, f) in forces.iter().enumerate() {
        if map[a].is_none() {
            let free = (0..2).filter(|&c| model.assembly.dofs().free(a, c).is_some());
            for c in free {
                assert!(f[c].abs() < 1e-11 * scale, "{label}: node {a}: {f:?}");
            }
        }
    }
    let mut kept_model = elastic_model(sub, rho_mass);
    let kept_state = restrict_state(&model, &state, &kept_model, &kept, &map).unwrap();
    let (f_free, f_prescribed) =
        restrict_forces(&forces, &map, kept_model.assembly.dofs()).unwrap();

    let kept_dofs = kept_model.assembly.dofs();
    let fx = (0..kept_model.mesh.nodes.len())
        .filter_map(|a| kept_dofs.free(a, 0))
        .fold(0.0f64, |m, i| m.max(f_free[i].abs()));
    println!(
        "{label}: max |F| on kept free dofs {:.3e} N/m, of which horizontal {fx:.3e} N/m",
        amax(&f_free)
    );

    // 1. The kept part balances its weight and F: Σ_K (Bᵀσ)_i − f_i^K − F_i = 0.
    let scale_k = amax(&kept_model.force_free);
    let with_f = amax(&free_residual(&kept_model, &kept_state.sigma, &f_free)) / scale_k;
    let without_f = amax(&free_residual(
        &kept_model,
        &kept_state.sigma,
        &vec![0.0; f_free.len()],
    )) / scale_k;
    println!(
        "{label}: kept balance with F {with_f:.3e}, without F {without_f:.3e} (relative to max |f|)"
    );
    assert!(with_f < 1e-10, "{label}: {with_f:e}");
    assert!(without_f > 0.1, "{label}: the witness: {without_f:e}");

    // 2. Releasing F: the direct elastic answer K_K Δu = −F on the kept free dofs.
    let k = stiffness(&kept_model);
    let du = k
        .clone()
        .lu()
        .solve(&(-DVector::from_vec(f_free.clone())))
        .unwrap();
    let dsigma = elastic_stress(&kept_model, du.as_slice());

    // ... against the engine, F a load ramped from 1 to 0 over t_end.
    let masses = &kept_model.assembly.lumped_mass_free;
    let inertia = (0..masses.len())
        .map(|i| masses[i] / (h * h) / k[(i, i)])
        .fold(0.0, f64::max);
    println!("{label}: max M_ii / (h² K_ii) = {inertia:.3e}");
    assert!(inertia < 1e-5, "{label}: {inertia:e}");
    let ramp = Ramp::try_new(&[[0.0, 1.0], [t_end, 0.0]]).unwrap();
    kept_model.add_load((f_free.clone(), f_prescribed), Some(ramp));
    let mut stepped = kept_state.clone();
    let mut stepper = Stepper::new(&kept_model, StepSettings::fem());
    for _ in 0..steps + held {
        stepper.advance(&mut stepped, h).unwrap();
    }
    assert!((stepped.time - (t_end + held as f64 * h)).abs() < 1e-12);
    let dofs = kept_model.assembly.dofs();
    let mut moved = vec![0.0; dofs.n_free()];
    for (node, (u1, u0)) in stepped
        .displacement
        .iter()
        .zip(&kept_state.displacement)
        .enumerate()
    {
        for c in 0..2 {
            if let Some(i) = dofs.free(node, c) {
                moved[i] = u1[c] - u0[c];
            }
        }
    }
    let u_err = (DVector::from_vec(moved) - &du).amax() / du.amax();
    let s_change: Vec<f64> = (0..4 * kept_model.n_points())
        .map(|k| stepped.sigma[k] - kept_state.sigma[k] - dsigma[k])
        .collect();
    let s_err = amax(&s_change) / amax(&dsigma);
    println!(
        "{label}: release: max |Δu| = {:.3e} m, displacement error {u_err:.3e}, stress error \
         {s_err:.3e} (relative)",
        du.amax()
    );
    assert!(u_err < 1e-8, "{label}: {u_err:e}");
    assert!(s_err < 1e-8, "{label}: {s_err:e}");
    // And the kept body ends at rest under its weight alone.
    let end = amax(&free_residual(
        &kept_model,
        &stepped.sigma,
        &vec![0.0; f_free.len()],
    ));
    assert!(end < 1e-8 * scale_k, "{label}: {:e}", end / scale_k);
    [fx, amax(&f_free)]
}
