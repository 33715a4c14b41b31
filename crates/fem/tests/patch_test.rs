//! The patch test (Irons; Zienkiewicz & Taylor, *The Finite Element Method*, vol. 1, §9):
//! on a distorted mesh, prescribe an affine displacement `u = u0 + G x` on the boundary,
//! solve linear elasticity for the interior, and recover the affine field and the constant
//! strain `sym G` at every Gauss point. It checks `B`, the Gauss volumes (`K = Σ V_p B_pᵀ C
//! B_p` is formed as `Bᵀ blockdiag(C / V_p) B` from the volume-weighted `B`) and the
//! isoparametric map together.
use crate::common;

use common::{affine_field, dense, distorted_rectangle, mandel_sym};
use nalgebra::{DMatrix, DVector, SMatrix};
use talus_bipotential::mandel::isotropic_compliance;
use talus_fem::{Assembly, Constraint, DofMap, ElementOrder, Mesh};

const G: [[f64; 2]; 2] = [[0.013, -0.021], [0.034, -0.008]]; // strain plus a rotation
const U0: [f64; 2] = [0.5, -0.25];

fn patch_test(order: ElementOrder) {
    let mesh = distorted_rectangle(order);
    let boundary: Vec<usize> = ["left", "right", "bottom", "top"]
        .iter()
        .flat_map(|s| mesh.node_sets[*s].clone())
        .collect();
    let dofs = DofMap::new(mesh.nodes.len(), &[(boundary, Constraint::Fixed)]).unwrap();
    assert!(dofs.n_free() > 0);
    let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();

    let c: SMatrix<f64, 4, 4> = isotropic_compliance::<4>(1.0, 0.3).try_inverse().unwrap();
    let n_gp = asm.n_points();
    let mut d = DMatrix::zeros(4 * n_gp, 4 * n_gp);
    for (p, v) in asm.gauss_volumes.iter().enumerate() {
        d.view_mut((4 * p, 4 * p), (4, 4)).copy_from(&(c / *v));
    }
    let (bf, bp) = (dense(&asm.b_free), dense(&asm.b_prescribed));
    let k_ff = bf.transpose() * &d * &bf;
    let k_fp = bf.transpose() * &d * &bp;

    let (u_exact, u_p) = affine_field(&mesh, &dofs, U0, G);
    let rhs = -(k_fp * DVector::from_vec(u_p.clone()));
    let u_f = k_ff.cholesky().expect("K_ff is SPD").solve(&rhs);

    for (i, (a, b)) in u_f.iter().zip(&u_exact).enumerate() {
        assert!((a - b).abs() < 1e-12, "{order:?}: free dof {i}: {a} vs {b}");
    }
    let expected = mandel_sym(G);
    let strains = asm.strain(u_f.as_slice(), &u_p).unwrap();
    for (p, e) in strains.iter().enumerate() {
        assert!(
            (e - expected).amax() < 1e-12,
            "{order:?}: Gauss point {p}: strain {e} vs {expected}"
        );
    }
}

#[test]
fn patch_test_uniform_strain_p1() {
    patch_test(ElementOrder::P1);
}

#[test]
fn patch_test_uniform_strain_p2() {
    patch_test(ElementOrder::P2);
}

/// Guards the test itself: a mesh this distorted really makes unequal elements, and a
/// non-affine boundary field is *not* reproduced exactly (the check can fail).
#[test]
fn patch_test_detects_a_non_affine_field() {
    let mesh = distorted_rectangle(ElementOrder::P1);
    let reference = Mesh::rectangle(
        &[0.0, 0.7, 1.5, 2.2, 3.0],
        &[0.0, 0.6, 1.3, 2.0],
        ElementOrder::P1,
    )
    .unwrap();
    assert!(mesh.nodes != reference.nodes);
    let boundary: Vec<usize> = ["left", "right", "bottom", "top"]
        .iter()
        .flat_map(|s| mesh.node_sets[*s].clone())
        .collect();
    let dofs = DofMap::new(mesh.nodes.len(), &[(boundary, Constraint::Fixed)]).unwrap();
    let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
    let mut u_p = vec![0.0; dofs.n_prescribed()];
    for (j, &(n, c)) in dofs.prescribed_dofs().iter().enumerate() {
        let x = mesh.nodes[n];
        u_p[j] = if c == 0 { x[0] * x[0] } else { 0.0 };
    }
    let strains = asm.strain(&vec![0.0; dofs.n_free()], &u_p).unwrap();
    let spread = strains
        .iter()
        .map(|e| e[0])
        .fold(f64::NEG_INFINITY, f64::max)
        - strains.iter().map(|e| e[0]).fold(f64::INFINITY, f64::min);
    assert!(spread > 0.1);
}
