//! Normal pressure on straight and curved edges: resultants and moments against identities
//! that hold for any edge shape, nodal forces against closed forms, orientation taken from
//! the triangles whatever the direction an edge set was drawn in.
//!
//! For an edge `x(s)`, `s ∈ [0, 1]`, from `a` to `b`, oriented counter-clockwise around
//! the body, the pressure `p` pushes with `−p n ds = p (−y′, x′) ds`, so
//! - the resultant is `p ∫ (−y′, x′) ds = p (−(b_y − a_y), b_x − a_x)`;
//! - its moment about the origin is `p ∫ (x x′ + y y′) ds = p (|b|² − |a|²) / 2`.
//!
//! With isoparametric edges (`x(s) = Σ N_a x_a`) both hold for the nodal forces exactly.
use talus_fem::{Assembly, BoundaryEdge, Dof, DofMap, ElementOrder, Mesh};

/// Force on every node `[fx, fy]`, free and prescribed dofs together.
fn nodal(dofs: &DofMap, f: &(Vec<f64>, Vec<f64>)) -> Vec<[f64; 2]> {
    (0..dofs.n_nodes())
        .map(|n| {
            let c = |comp| match dofs.dof(n, comp).unwrap() {
                Dof::Free(i) => f.0[i],
                Dof::Prescribed(j) => f.1[j],
            };
            [c(0), c(1)]
        })
        .collect()
}

fn resultant_and_moment(mesh: &Mesh, forces: &[[f64; 2]]) -> ([f64; 2], f64) {
    let mut r = [0.0; 2];
    let mut m = 0.0;
    for (x, f) in mesh.nodes.iter().zip(forces) {
        r[0] += f[0];
        r[1] += f[1];
        m += x[0] * f[1] - x[1] * f[0];
    }
    (r, m)
}

/// A P2 quarter annulus `r ∈ [r_in, r_out]`, `θ ∈ [0, π/2]`: nodes on the refined polar
/// grid (mid nodes at mid radius and mid angle, so the arc edges are curved and their three
/// nodes lie on the circle). Edge sets `inner` (drawn from θ = 0 to π/2, against the
/// domain's counter-clockwise direction) and `outer` (drawn from θ = π/2 to 0, also
/// against it), so that only the triangles can tell the outside.
fn quarter_annulus_p2(r_in: f64, r_out: f64, nr: usize, nt: usize) -> Mesh {
    let (cr, ct) = (2 * nr + 1, 2 * nt + 1);
    let id = |i: usize, j: usize| j * cr + i; // i radial, j angular (refined indices)
    let mut nodes = Vec::with_capacity(cr * ct);
    for j in 0..ct {
        let theta = std::f64::consts::FRAC_PI_2 * j as f64 / (ct - 1) as f64;
        for i in 0..cr {
            let r = r_in + (r_out - r_in) * i as f64 / (cr - 1) as f64;
            nodes.push([r * theta.cos(), r * theta.sin()]);
        }
    }
    let mut triangles = Vec::new();
    for cj in 0..nt {
        for ci in 0..nr {
            let (i, j) = (2 * ci, 2 * cj);
            // (r, θ) → (x, y) keeps orientation (det = r > 0): counter-clockwise in (i, j).
            let (p00, p20, p02, p22) = (id(i, j), id(i + 2, j), id(i, j + 2), id(i + 2, j + 2));
            triangles.push(vec![
                p00,
                p20,
                p22,
                id(i + 1, j),
                id(i + 2, j + 1),
                id(i + 1, j + 1),
            ]);
            triangles.push(vec![
                p00,
                p22,
                p02,
                id(i + 1, j + 1),
                id(i + 1, j + 2),
                id(i, j + 1),
            ]);
        }
    }
    let inner = (0..nt)
        .map(|cj| BoundaryEdge {
            nodes: vec![id(0, 2 * cj), id(0, 2 * cj + 2), id(0, 2 * cj + 1)],
        })
        .collect();
    let outer = (0..nt)
        .rev()
        .map(|cj| BoundaryEdge {
            nodes: vec![
                id(cr - 1, 2 * cj + 2),
                id(cr - 1, 2 * cj),
                id(cr - 1, 2 * cj + 1),
            ],
        })
        .collect();
    let mesh = Mesh {
        order: ElementOrder::P2,
        nodes,
        triangles,
        node_sets: Default::default(),
        edge_sets: [("inner".to_string(), inner), ("outer".to_string(), outer)].into(),
        element_sets: Default::default(),
    };
    mesh.validate().unwrap();
    mesh
}

/// An inner pressure on a quarter circle of radius R pushes the body out with `p R` in x
/// and in y (the resultant over any curve from (R, 0) to (0, R)), with no moment about the
/// centre; an outer one pushes it in with `−p R_out`. Both arcs are drawn against the
/// domain's direction, so a normal taken from the edge as drawn would flip the sign.
#[test]
fn quarter_circle_pressure_resultant_is_p_times_radius() {
    let (r_in, r_out, p) = (1.5, 4.0, 2.0e5);
    for nt in [1, 3, 8] {
        let mesh = quarter_annulus_p2(r_in, r_out, 2, nt);
        let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        for (set, radius, sign) in [("inner", r_in, 1.0), ("outer", r_out, -1.0)] {
            let f = asm.pressure(&mesh, &mesh.edge_sets[set], p).unwrap();
            let forces = nodal(&dofs, &f);
            let (r, m) = resultant_and_moment(&mesh, &forces);
            let want = sign * p * radius;
            for (c, rc) in r.iter().enumerate() {
                assert!(
                    (rc - want).abs() <= 1e-12 * want.abs(),
                    "{set}, {nt} edges: resultant[{c}] = {rc}, want {want}"
                );
            }
            assert!(
                m.abs() <= 1e-12 * p * radius * radius,
                "{set}, {nt} edges: moment {m}"
            );
            // every loaded node is pushed along its radius, outward for the cavity
            for (x, fa) in mesh.nodes.iter().zip(&forces) {
                let radial = (x[0] * fa[0] + x[1] * fa[1]) / x[0].hypot(x[1]);
                let tangential = (x[0] * fa[1] - x[1] * fa[0]) / x[0].hypot(x[1]);
                if fa[0] != 0.0 || fa[1] != 0.0 {
                    assert!(sign * radial > 0.0, "{set}: node at {x:?} gets {fa:?}");
                    // an end node of the arc also gets a tangential share (consistent
                    // forces are not lumped), but never more than its radial one
                    assert!(tangential.abs() < radial.abs(), "{set}: {x:?}: {fa:?}");
                }
            }
        }
        // the same arc drawn in the domain's direction gives the same forces
        let reversed: Vec<BoundaryEdge> = mesh.edge_sets["inner"]
            .iter()
            .map(|e| BoundaryEdge {
                nodes: vec![e.nodes[1], e.nodes[0], e.nodes[2]],
            })
            .collect();
        assert_eq!(
            asm.pressure(&mesh, &reversed, p).unwrap(),
            asm.pressure(&mesh, &mesh.edge_sets["inner"], p).unwrap()
        );
    }
}

/// One curved P2 edge with its mid node off the chord's bisector: the nodal forces equal
/// `f_a = p Σ_b C_ab (−y_b, x_b)`, `C_ab = ∫₀¹ N_a N_b′ ds` (closed form below, Lin3 order:
/// ends, then mid), and satisfy the resultant and moment identities.
#[test]
fn curved_p2_edge_forces_match_closed_form() {
    // ∫ N_a N_b' ds for N = ((1−s)(1−2s), s(2s−1), 4s(1−s)).
    const C: [[f64; 3]; 3] = [
        [-0.5, -1.0 / 6.0, 2.0 / 3.0],
        [1.0 / 6.0, 0.5, -2.0 / 3.0],
        [-2.0 / 3.0, 2.0 / 3.0, 0.0],
    ];
    // bottom side 0 → 1 bulges downward (outward) and leans towards node 1
    let nodes = vec![
        [0.0, 0.0],
        [3.0, 0.5],
        [0.5, 2.5],
        [1.9, -0.4],
        [1.8, 1.5],
        [0.2, 1.3],
    ];
    let mesh = Mesh {
        order: ElementOrder::P2,
        nodes: nodes.clone(),
        triangles: vec![vec![0, 1, 2, 3, 4, 5]],
        node_sets: Default::default(),
        edge_sets: Default::default(),
        element_sets: Default::default(),
    };
    mesh.validate().unwrap();
    let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
    let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
    let p = 3.0e4;
    // drawn backwards on purpose
    let edge = BoundaryEdge {
        nodes: vec![1, 0, 3],
    };
    let forces = nodal(&dofs, &asm.pressure(&mesh, &[edge], p).unwrap());
    let oriented = [0, 1, 3];
    for (a, &na) in oriented.iter().enumerate() {
        let mut want = [0.0; 2];
        for (b, &nb) in oriented.iter().enumerate() {
            want[0] += p * C[a][b] * -nodes[nb][1];
            want[1] += p * C[a][b] * nodes[nb][0];
        }
        for c in 0..2 {
            assert!(
                (forces[na][c] - want[c]).abs() <= 1e-12 * p,
                "node {na}: {:?} vs {want:?}",
                forces[na]
            );
        }
    }
    let (r, m) = resultant_and_moment(&mesh, &forces);
    let (a, b) = (nodes[0], nodes[1]);
    assert!((r[0] - p * -(b[1] - a[1])).abs() <= 1e-12 * p);
    assert!((r[1] - p * (b[0] - a[0])).abs() <= 1e-12 * p);
    let want_m = p * ((b[0] * b[0] + b[1] * b[1]) - (a[0] * a[0] + a[1] * a[1])) / 2.0;
    assert!((m - want_m).abs() <= 1e-12 * p * 10.0, "{m} vs {want_m}");
}

/// Straight P1 edges: `p L` into the body, split in halves; a pressure all around a closed
/// boundary has no resultant.
#[test]
fn straight_p1_edge_gets_p_times_length() {
    let (w, h, p) = (2.5, 1.2, 7.0e3);
    let mesh = Mesh::rectangle(&[0.0, 1.0, w], &[0.0, 0.4, h], ElementOrder::P1).unwrap();
    let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
    let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
    for (set, want) in [("top", [0.0, -p * w]), ("right", [-p * h, 0.0])] {
        let edges = &mesh.edge_sets[set];
        let forces = nodal(&dofs, &asm.pressure(&mesh, edges, p).unwrap());
        let (r, _) = resultant_and_moment(&mesh, &forces);
        for c in 0..2 {
            assert!((r[c] - want[c]).abs() <= 1e-12 * p * w, "{set}: {r:?}");
        }
        for e in edges {
            let (a, b) = (mesh.nodes[e.nodes[0]], mesh.nodes[e.nodes[1]]);
            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
            let share = asm.pressure(&mesh, std::slice::from_ref(e), p).unwrap();
            for (node, f) in nodal(&dofs, &share).iter().enumerate() {
                let expected = if e.nodes.contains(&node) {
                    0.5 * p * len
                } else {
                    0.0
                };
                assert!(
                    (f[0].hypot(f[1]) - expected).abs() <= 1e-12 * p * w,
                    "{set}: node {node}: {f:?}"
                );
            }
        }
    }
    let all = asm.pressure(&mesh, &mesh.boundary_edges(), p).unwrap();
    let (r, m) = resultant_and_moment(&mesh, &nodal(&dofs, &all));
    assert!(
        r[0].abs() < 1e-10 && r[1].abs() < 1e-10 && m.abs() < 1e-9,
        "{r:?} {m}"
    );
}

#[test]
fn pressure_rejects_bad_input() {
    let mesh = Mesh::rectangle(&[0.0, 1.0, 2.0], &[0.0, 1.0], ElementOrder::P2).unwrap();
    let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
    let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
    let top = &mesh.edge_sets["top"];
    let err = asm.pressure(&mesh, top, f64::NAN).unwrap_err();
    assert!(err.to_string().contains("pressure"), "{err}");
    // the diagonal of the first cell lies between two triangles
    let t = &mesh.triangles[0];
    let interior = mesh
        .triangles
        .iter()
        .skip(1)
        .find_map(|u| {
            [(0, 1, 3), (1, 2, 4), (2, 0, 5)]
                .into_iter()
                .map(|(i, j, k)| (t[i], t[j], t[k]))
                .find(|(a, b, _)| u[..3].contains(a) && u[..3].contains(b))
        })
        .expect("a shared side");
    let edge = BoundaryEdge {
        nodes: vec![interior.0, interior.1, interior.2],
    };
    let err = asm.pressure(&mesh, &[edge], 1.0).unwrap_err();
    assert!(err.to_string().contains("not on the boundary"), "{err}");
    // a P2 side with the wrong mid node
    let e = &top[0];
    let wrong = BoundaryEdge {
        nodes: vec![e.nodes[0], e.nodes[1], e.nodes[0]],
    };
    assert!(asm.pressure(&mesh, &[wrong], 1.0).is_err());
    let lonely = BoundaryEdge {
        nodes: vec![0, 999, 1],
    };
    assert!(asm.pressure(&mesh, &[lonely], 1.0).is_err());
}
