//! The reference tetrahedra (P1 `Tet4`, P2 `Tet10`), their isoparametric map and the 3D
//! Mandel strain rows (`talus_fem::element::tetrahedron`): nodal shape functions, gradients
//! against central differences, exact reproduction of linear (P1) and quadratic (P2)
//! fields, the patch test of the strain rows (a linear velocity gives its symmetric
//! gradient at every stress point; a rigid rotation gives none), equilibrium of a constant
//! stress' nodal forces, and the P2 mass integrals against their closed forms
//! (`∫N_v² = V/70`, `∫N_e² = 8V/105`, from `∫λ^α = 3! α! V / (|α| + 3)!`).
use talus_fem::element::tetrahedron::{
    mandel_strain_rows, map_tetrahedron_point, tetrahedron_jacobian_determinant, MANDEL_3D,
};
use talus_fem::element::ElementOrder;
use talus_fem::quadrature::tetrahedron::{mass_rule, stiffness_rule};

const ORDERS: [ElementOrder; 2] = [ElementOrder::P1, ElementOrder::P2];
const POINTS: [[f64; 3]; 4] = [
    [0.1, 0.2, 0.3],
    [0.0, 0.0, 0.0],
    [0.6, 0.1, 0.2],
    [0.25, 0.25, 0.25],
];

/// A skewed, direct tetrahedron (det of its edge triad > 0), with its P2 nodes at the edge
/// mid-points.
fn tetrahedron(order: ElementOrder) -> Vec<[f64; 3]> {
    let vertices = [
        [0.3, -0.2, 0.1],
        [1.4, 0.1, 0.3],
        [0.2, 1.1, -0.1],
        [0.5, 0.4, 1.2],
    ];
    order
        .tetrahedron_reference_nodes()
        .iter()
        .map(|xi| {
            let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
            std::array::from_fn(|k| (0..4).map(|v| l[v] * vertices[v][k]).sum())
        })
        .collect()
}

fn volume(x: &[[f64; 3]]) -> f64 {
    let e = |i: usize| -> [f64; 3] { std::array::from_fn(|k| x[i][k] - x[0][k]) };
    let (a, b, c) = (e(1), e(2), e(3));
    (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0]))
        / 6.0
}

/// Gmsh's `Tet10` (reference manual, 'Node ordering'): vertices, then the mid-points of
/// edges 01, 12, 20, 30, 32, 31. VTK's type 24 swaps the last two, so a mesh read or
/// written in the other order would be silently wrong.
#[test]
fn p2_nodes_follow_gmsh_order() {
    let nodes = ElementOrder::P2.tetrahedron_reference_nodes();
    let expected = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.5, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.0, 0.5, 0.0],
        [0.0, 0.0, 0.5],
        [0.0, 0.5, 0.5],
        [0.5, 0.0, 0.5],
    ];
    assert_eq!(nodes, expected);
}

#[test]
fn shape_functions_are_nodal_and_partition_unity() {
    for order in ORDERS {
        let nodes = order.tetrahedron_reference_nodes();
        assert_eq!(nodes.len(), order.nodes_per_tetrahedron());
        for (a, xa) in nodes.iter().enumerate() {
            let n = order.tetrahedron_shape_functions(*xa);
            for (b, nb) in n.iter().enumerate() {
                let expected = if a == b { 1.0 } else { 0.0 };
                assert!((nb - expected).abs() < 1e-15, "{order:?} N_{b} at node {a}");
            }
        }
        for xi in POINTS {
            let s: f64 = order.tetrahedron_shape_functions(xi).iter().sum();
            assert!((s - 1.0).abs() < 1e-15);
            let g = order.tetrahedron_reference_gradients(xi);
            for k in 0..3 {
                assert!(g.iter().map(|g| g[k]).sum::<f64>().abs() < 1e-14);
            }
        }
    }
}

#[test]
fn reference_gradients_match_central_differences() {
    let h = 1e-6;
    for order in ORDERS {
        for xi in POINTS {
            let g = order.tetrahedron_reference_gradients(xi);
            for k in 0..3 {
                let (mut p, mut m) = (xi, xi);
                p[k] += h;
                m[k] -= h;
                let np = order.tetrahedron_shape_functions(p);
                let nm = order.tetrahedron_shape_functions(m);
                for a in 0..g.len() {
                    let fd = (np[a] - nm[a]) / (2.0 * h);
                    assert!((fd - g[a][k]).abs() < 1e-8, "{order:?} dN_{a}/dξ_{k}");
                }
            }
        }
    }
}

#[test]
fn the_map_reproduces_linear_and_quadratic_fields() {
    for order in ORDERS {
        let x = tetrahedron(order);
        for xi in POINTS {
            let m = map_tetrahedron_point(order, &x, xi).expect("valid tetrahedron");
            assert!(
                (m.det_j - 6.0 * volume(&x)).abs() < 1e-14,
                "affine: det J = 6V"
            );
            // f = 2x − 3y + 0.5z + 1 has gradient (2, −3, 0.5) on both orders.
            let f = |p: &[f64; 3]| 2.0 * p[0] - 3.0 * p[1] + 0.5 * p[2] + 1.0;
            let grad: [f64; 3] =
                std::array::from_fn(|k| x.iter().zip(&m.gradients).map(|(p, g)| f(p) * g[k]).sum());
            for (k, want) in [2.0, -3.0, 0.5].iter().enumerate() {
                assert!((grad[k] - want).abs() < 1e-13, "{order:?}: {grad:?}");
            }
            let at: f64 = x.iter().zip(&m.shape).map(|(p, n)| f(p) * n).sum();
            assert!((at - f(&m.position)).abs() < 1e-13);
            if order == ElementOrder::P2 {
                // q = x y + z² has gradient (y, x, 2z): P2 interpolates it exactly.
                let q = |p: &[f64; 3]| p[0] * p[1] + p[2] * p[2];
                let p = m.position;
                let grad: [f64; 3] = std::array::from_fn(|k| {
                    x.iter().zip(&m.gradients).map(|(n, g)| q(n) * g[k]).sum()
                });
                let want = [p[1], p[0], 2.0 * p[2]];
                for k in 0..3 {
                    assert!((grad[k] - want[k]).abs() < 1e-13, "P2 quadratic: {grad:?}");
                }
            }
        }
    }
}

#[test]
fn inverted_and_flat_tetrahedra_have_no_map() {
    for order in ORDERS {
        let mut x = tetrahedron(order);
        x.swap(1, 2); // the triad becomes left-handed
        if order == ElementOrder::P2 {
            // keep the mid-edge nodes on their (renamed) edges: 01 ↔ 02, 12 stays, 31 ↔ 32
            x.swap(4, 6);
            x.swap(8, 9);
        }
        assert!(tetrahedron_jacobian_determinant(order, &x, [0.25; 3]) < 0.0);
        assert!(
            map_tetrahedron_point(order, &x, [0.25; 3]).is_none(),
            "{order:?}"
        );
    }
    let flat = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.3, 0.3, 0.0],
    ];
    assert!(map_tetrahedron_point(ElementOrder::P1, &flat, [0.25; 3]).is_none());
}

/// `ε̇` at one stress point from nodal velocities `v`, through the Mandel rows.
fn strain_rate(gradients: &[[f64; 3]], v: &[[f64; 3]]) -> [f64; MANDEL_3D] {
    let mut e = [0.0; MANDEL_3D];
    for (g, va) in gradients.iter().zip(v) {
        for (c, vc) in va.iter().enumerate() {
            for (row, coefficient) in mandel_strain_rows(*g, c) {
                e[row] += coefficient * vc;
            }
        }
    }
    e
}

#[test]
fn linear_velocities_pass_the_patch_test_of_the_strain_rows() {
    let s2 = std::f64::consts::SQRT_2;
    // v = A x + v0 with A = sym + skew.
    let a = [[0.3, -0.7, 0.2], [0.1, -0.4, 0.9], [-0.5, 0.6, 0.25]];
    let sym = |i: usize, j: usize| 0.5 * (a[i][j] + a[j][i]);
    let expected = [
        sym(0, 0),
        sym(1, 1),
        sym(2, 2),
        s2 * sym(1, 2),
        s2 * sym(0, 2),
        s2 * sym(0, 1),
    ];
    for order in ORDERS {
        let x = tetrahedron(order);
        let velocity = |p: &[f64; 3], a: &[[f64; 3]; 3]| -> [f64; 3] {
            std::array::from_fn(|i| (0..3).map(|j| a[i][j] * p[j]).sum::<f64>() + 0.1 * i as f64)
        };
        let v: Vec<[f64; 3]> = x.iter().map(|p| velocity(p, &a)).collect();
        let rule = stiffness_rule(order);
        for xi in rule.points {
            let m = map_tetrahedron_point(order, &x, *xi).unwrap();
            let e = strain_rate(&m.gradients, &v);
            for r in 0..MANDEL_3D {
                assert!(
                    (e[r] - expected[r]).abs() < 1e-13,
                    "{order:?} row {r}: {e:?}"
                );
            }
        }
        // A rigid rotation strains nothing.
        let w = [[0.0, -0.3, 0.8], [0.3, 0.0, -0.2], [-0.8, 0.2, 0.0]];
        let v: Vec<[f64; 3]> = x.iter().map(|p| velocity(p, &w)).collect();
        let m = map_tetrahedron_point(order, &x, [0.2, 0.3, 0.1]).unwrap();
        assert!(strain_rate(&m.gradients, &v)
            .iter()
            .all(|e| e.abs() < 1e-14));
    }
}

#[test]
fn a_constant_stress_gives_nodal_forces_in_equilibrium() {
    let s2 = std::f64::consts::SQRT_2;
    // σ (Pa) in Mandel form; f_a = Σ_p V_p B_paᵀ σ is the element's internal force.
    let sigma = [-1.0e5, -2.0e5, -0.5e5, s2 * 3.0e4, s2 * -1.0e4, s2 * 2.0e4];
    for order in ORDERS {
        let x = tetrahedron(order);
        let rule = stiffness_rule(order);
        let mut f = vec![[0.0; 3]; x.len()];
        let mut total_volume = 0.0;
        for (xi, w) in rule.points.iter().zip(rule.weights) {
            let m = map_tetrahedron_point(order, &x, *xi).unwrap();
            let v = w * m.det_j;
            total_volume += v;
            for (a, g) in m.gradients.iter().enumerate() {
                for c in 0..3 {
                    for (row, coefficient) in mandel_strain_rows(*g, c) {
                        f[a][c] += v * coefficient * sigma[row];
                    }
                }
            }
        }
        assert!((total_volume - volume(&x)).abs() < 1e-15);
        let scale = 2.0e5 * total_volume.cbrt().powi(2);
        for c in 0..3 {
            let sum: f64 = f.iter().map(|fa| fa[c]).sum();
            assert!(sum.abs() < 1e-9 * scale, "{order:?}: Σ f_{c} = {sum}");
        }
        // Σ x_a × f_a = 0: the shear rows put σ's symmetric part where it belongs.
        let mut moment = [0.0; 3];
        for (p, fa) in x.iter().zip(&f) {
            moment[0] += p[1] * fa[2] - p[2] * fa[1];
            moment[1] += p[2] * fa[0] - p[0] * fa[2];
            moment[2] += p[0] * fa[1] - p[1] * fa[0];
        }
        assert!(
            moment.iter().all(|m| m.abs() < 1e-9 * scale),
            "{order:?}: {moment:?}"
        );
    }
}

#[test]
fn the_mass_rule_gives_the_p2_mass_integrals_in_closed_form() {
    let order = ElementOrder::P2;
    let x = tetrahedron(order);
    let v = volume(&x);
    let rule = mass_rule();
    let mut diagonal = [0.0; 10];
    let mut total = 0.0;
    for (xi, w) in rule.points.iter().zip(rule.weights) {
        let m = map_tetrahedron_point(order, &x, *xi).unwrap();
        for (a, n) in m.shape.iter().enumerate() {
            diagonal[a] += w * m.det_j * n * n;
            total += w * m.det_j * n * m.shape.iter().sum::<f64>();
        }
    }
    assert!((total - v).abs() < 1e-15, "Σ_ab ∫N_a N_b = V");
    for a in 0..4 {
        assert!(
            (diagonal[a] - v / 70.0).abs() < 1e-15,
            "vertex {a}: {}",
            diagonal[a]
        );
    }
    for a in 4..10 {
        assert!(
            (diagonal[a] - 8.0 * v / 105.0).abs() < 1e-15,
            "edge {a}: {}",
            diagonal[a]
        );
    }
}
