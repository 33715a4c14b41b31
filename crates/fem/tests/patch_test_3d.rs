//! The patch test in 3D (Irons; Zienkiewicz & Taylor, *The Finite Element Method*, vol. 1,
//! §9 'Convergence requirements: the patch test'), on `Assembly<6>` over a distorted
//! tetrahedral block (`solid3d::distorted_block`: 4 × 3 × 3 uneven cells, 216 tetrahedra,
//! every vertex moved within the sides it lies on, P2 mid-edge nodes at their edges'
//! mid-points so that the elements are affine and no two alike):
//! - (a) a linear displacement `u = u₀ + G x` gives its constant strain `sym G` (Mandel
//!   `(xx, yy, zz, √2 yz, √2 xz, √2 xy)`) at every Gauss point through `asm.strain`, its
//!   free and prescribed columns together; a rigid motion gives none;
//! - (b) a constant stress `σ` gives internal forces `Bᵀσ` equal to the consistent
//!   tractions `t = σ n` of the six sides (`asm.traction`, face by face) at every node, and
//!   so 0 at interior nodes: the discrete divergence theorem `∫ ∇N_a · σ dV = ∫ N_a σ n dA`,
//!   exact with the stiffness rules on affine elements (`∇N_a` of degree ≤ 1);
//! - (c) prescribing the linear field on the whole boundary and solving the static problem
//!   `K_ff u_f = −K_fp u_p` (`K = Bᵀ blockdiag((V_p S₀)⁻¹) B`) gives back the field at the
//!   interior nodes, to round-off.
//!
//! Tolerances are round-off: 1e-12 relative to each check's scale (`|G|`, `|σ| · 0.5 m²`,
//! `max |u|`); measured, the largest deviations are 1.8e-14 (P1) and 9.2e-14 (P2) in (a),
//! 2.9e-16 and 5.8e-16 in (b), 8.5e-16 (36 free dofs) and 2.9e-15 (525) in (c).
//! `patch_test_3d_detects_a_field_beyond_the_order` guards the checks: the block really is
//! distorted, and a field one degree beyond each order's is not reproduced (spread of
//! `ε_xx` 4.6 for `x²` on P1, 25 for `x³` on P2).
use crate::solid3d;

use nalgebra::{SMatrix, SVector};
use solid3d::{distorted_block, mul, nodal, solve_spd, split, stiffness, vertex_flags, XS};
use talus_bipotential::mandel::isotropic_compliance;
use talus_fem::{Assembly, Constraint, DofMap, ElementOrder, TetrahedralMesh};

const ORDERS: [ElementOrder; 2] = [ElementOrder::P1, ElementOrder::P2];
/// Up to 12 % of the smallest cell side (0.4 m) per axis.
const AMPLITUDE: f64 = 0.05;
/// A displacement gradient with strain and rotation, and a translation.
const G: [[f64; 3]; 3] = [
    [0.013, -0.021, 0.007],
    [0.034, -0.008, -0.015],
    [-0.011, 0.026, 0.019],
];
const U0: [f64; 3] = [0.5, -0.25, 0.125];

fn linear_field(x: [f64; 3], g: [[f64; 3]; 3]) -> [f64; 3] {
    std::array::from_fn(|i| U0[i] + (0..3).map(|j| g[i][j] * x[j]).sum::<f64>())
}

fn mandel_sym(g: [[f64; 3]; 3]) -> SVector<f64, 6> {
    let s = std::f64::consts::SQRT_2;
    let e = |i: usize, j: usize| 0.5 * (g[i][j] + g[j][i]);
    SVector::from([
        e(0, 0),
        e(1, 1),
        e(2, 2),
        s * e(1, 2),
        s * e(0, 2),
        s * e(0, 1),
    ])
}

/// Every node of the six sides.
fn boundary_nodes(mesh: &TetrahedralMesh) -> Vec<usize> {
    let mut nodes: Vec<usize> = ["left", "right", "bottom", "top", "back", "front"]
        .iter()
        .flat_map(|s| mesh.node_sets[*s].clone())
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

#[test]
fn patch_test_3d_linear_field_gives_constant_strain() {
    for order in ORDERS {
        let mesh = distorted_block(order, AMPLITUDE);
        // some dofs prescribed, so that both columns of B take part
        let dofs = DofMap::with_components(
            mesh.nodes.len(),
            3,
            &[
                (mesh.node_sets["bottom"].clone(), Constraint::Fixed),
                (mesh.node_sets["left"].clone(), Constraint::FixX),
                (mesh.node_sets["front"].clone(), Constraint::FixYZ),
            ],
        )
        .unwrap();
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        let (free, prescribed) = split(&dofs, |n, c| linear_field(mesh.nodes[n], G)[c]);
        let expected = mandel_sym(G);
        for (p, e) in asm.strain(&free, &prescribed).unwrap().iter().enumerate() {
            assert!(
                (e - expected).amax() < 1e-12 * expected.amax(),
                "{order:?}: Gauss point {p}: {e} vs {expected}"
            );
        }
        // a rigid rotation (skew G) and translation strain nothing
        let w = [[0.0, -0.03, 0.02], [0.03, 0.0, -0.01], [-0.02, 0.01, 0.0]];
        let (free, prescribed) = split(&dofs, |n, c| linear_field(mesh.nodes[n], w)[c]);
        for e in asm.strain(&free, &prescribed).unwrap() {
            assert!(e.amax() < 1e-14, "{order:?}: rigid motion strains {e}");
        }
    }
}

/// Isoparametric P2 tetrahedra with curved edges (mid-edge nodes off their edges'
/// mid-points) still contain the linear fields, so (a) holds on them too.
#[test]
fn patch_test_3d_curved_p2_elements_keep_linear_fields() {
    let mut mesh = distorted_block(ElementOrder::P2, AMPLITUDE);
    let vertices = vertex_flags(&mesh);
    let mut next = solid3d::jitter(0xD1B5_4A32_D192_ED03);
    let (lo, hi) = (XS[0], XS[XS.len() - 1]);
    for (x, vertex) in mesh.nodes.iter_mut().zip(vertices) {
        if !vertex && x[0] != lo && x[0] != hi {
            for c in x.iter_mut() {
                *c += 0.02 * next();
            }
        }
    }
    mesh.check_elements().unwrap();
    let dofs = DofMap::with_components(mesh.nodes.len(), 3, &[]).unwrap();
    let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
    let (free, prescribed) = split(&dofs, |n, c| linear_field(mesh.nodes[n], G)[c]);
    let expected = mandel_sym(G);
    for e in asm.strain(&free, &prescribed).unwrap() {
        assert!((e - expected).amax() < 1e-12 * expected.amax(), "{e}");
    }
}

#[test]
fn patch_test_3d_constant_stress_balances_the_side_tractions() {
    let s2 = std::f64::consts::SQRT_2;
    // σ (Pa): every component different and non-zero
    let tensor = [
        [-1.0e5, 2.0e4, -1.0e4],
        [2.0e4, -2.0e5, 3.0e4],
        [-1.0e4, 3.0e4, -0.5e5],
    ];
    let mandel = [
        tensor[0][0],
        tensor[1][1],
        tensor[2][2],
        s2 * tensor[1][2],
        s2 * tensor[0][2],
        s2 * tensor[0][1],
    ];
    let sides = [
        ("left", [-1.0, 0.0, 0.0]),
        ("right", [1.0, 0.0, 0.0]),
        ("bottom", [0.0, -1.0, 0.0]),
        ("top", [0.0, 1.0, 0.0]),
        ("back", [0.0, 0.0, -1.0]),
        ("front", [0.0, 0.0, 1.0]),
    ];
    for order in ORDERS {
        let mesh = distorted_block(order, AMPLITUDE);
        let dofs = DofMap::with_components(mesh.nodes.len(), 3, &[]).unwrap();
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        let sigma: Vec<f64> = (0..asm.n_points()).flat_map(|_| mandel).collect();
        let internal = nodal(&dofs, &asm.internal_force(&sigma).unwrap());
        let mut external = vec![[0.0; 3]; mesh.nodes.len()];
        for (side, n) in sides {
            let t: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| tensor[i][j] * n[j]).sum());
            for face in &mesh.face_sets[side] {
                let f = asm.traction(&mesh, std::slice::from_ref(face), t).unwrap();
                for (e, fa) in external.iter_mut().zip(nodal(&dofs, &f)) {
                    for c in 0..3 {
                        e[c] += fa[c];
                    }
                }
            }
        }
        // |σ| times the largest face share: the size of one nodal force
        let scale = 2.0e5 * 0.5;
        let boundary = boundary_nodes(&mesh);
        for (k, (fi, fe)) in internal.iter().zip(&external).enumerate() {
            for c in 0..3 {
                assert!(
                    (fi[c] - fe[c]).abs() < 1e-12 * scale,
                    "{order:?}: node {k} at {:?}: Bᵀσ = {fi:?}, tractions {fe:?}",
                    mesh.nodes[k]
                );
            }
            if boundary.binary_search(&k).is_err() {
                assert!(fe.iter().all(|f| *f == 0.0), "{order:?}: interior node {k}");
            }
        }
        // and the forces are not all zero: P1 loads every side node, P2 none of the
        // vertices but every mid-edge node of the sides
        let loaded = boundary
            .iter()
            .filter(|&&k| internal[k].iter().any(|f| f.abs() > 1e-3 * scale))
            .count();
        assert!(
            loaded > boundary.len() / 2,
            "{order:?}: {loaded} of {}",
            boundary.len()
        );
    }
}

#[test]
fn patch_test_3d_static_solve_reproduces_a_linear_field() {
    let s0 = isotropic_compliance::<6>(2.0e7, 0.3);
    for order in ORDERS {
        let mesh = distorted_block(order, AMPLITUDE);
        let boundary = boundary_nodes(&mesh);
        let dofs =
            DofMap::with_components(mesh.nodes.len(), 3, &[(boundary, Constraint::Fixed)]).unwrap();
        assert!(dofs.n_free() > 0);
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        let (k_ff, k_fp) = stiffness(&asm, &s0);
        let (exact, u_p) = split(&dofs, |n, c| linear_field(mesh.nodes[n], G)[c]);
        let rhs: Vec<f64> = mul(&k_fp, &u_p).iter().map(|f| -f).collect();
        let u_f = solve_spd(&k_ff, &rhs);
        let scale = exact.iter().fold(0.0f64, |m, u| m.max(u.abs()));
        for (i, (a, b)) in u_f.iter().zip(&exact).enumerate() {
            assert!(
                (a - b).abs() < 1e-12 * scale,
                "{order:?}: free dof {i}: {a} vs {b}"
            );
        }
        // the stress is the constant C sym G everywhere
        let c: SMatrix<f64, 6, 6> = s0.try_inverse().unwrap();
        let want = c * mandel_sym(G);
        for e in asm.strain(&u_f, &u_p).unwrap() {
            assert!((c * e - want).amax() < 1e-10 * want.amax());
        }
    }
}

/// Guards the tests: the block really is distorted, and a field one degree beyond each
/// order (P1: `u_x = x²`, P2: `u_x = x³`) does not give a constant strain.
#[test]
fn patch_test_3d_detects_a_field_beyond_the_order() {
    for (order, degree) in [(ElementOrder::P1, 2), (ElementOrder::P2, 3)] {
        let mesh = distorted_block(order, AMPLITUDE);
        let reference =
            TetrahedralMesh::block(&solid3d::XS, &solid3d::YS, &solid3d::ZS, order).unwrap();
        let moved = mesh
            .nodes
            .iter()
            .zip(&reference.nodes)
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            moved > mesh.nodes.len() / 2,
            "{order:?}: {moved} nodes moved"
        );
        let dofs = DofMap::with_components(mesh.nodes.len(), 3, &[]).unwrap();
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        let (free, prescribed) = split(&dofs, |n, c| {
            if c == 0 {
                mesh.nodes[n][0].powi(degree)
            } else {
                0.0
            }
        });
        let strains = asm.strain(&free, &prescribed).unwrap();
        let (lo, hi) = strains
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), e| {
                (l.min(e[0]), h.max(e[0]))
            });
        assert!(hi - lo > 1.0, "{order:?}: ε_xx spread {}", hi - lo);
    }
}
