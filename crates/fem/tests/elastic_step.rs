//! `docs/derivations.md`, 'The reduced system': a purely elastic step of eq. 15–16 must
//! equal a direct velocity solve. With `z = 0`, `Wσ = −q`, `W = S + h² B_f M⁻¹ B_fᵀ` and
//! `q = −(S σ_n + h B_f v_n + h B_p v_p + h² B_f M⁻¹ f)` (prescribed velocities `v_p`
//! enter through `B_p`), then `v = v_n + h M⁻¹ (f − B_fᵀ σ)` must solve
//! `(M + h² B_fᵀ S⁻¹ B_f) v = M v_n + h (f − B_fᵀ σ_n) − h² B_fᵀ S⁻¹ B_p v_p`.
//! This checks that the operators of this crate fit together as the solver uses them.
use crate::common;

use common::{dense, distorted_rectangle};
use nalgebra::{DMatrix, DVector};
use talus_bipotential::mandel::isotropic_compliance;
use talus_fem::{Assembly, Constraint, DofMap, ElementOrder};

#[test]
fn elastic_step_matches_direct_velocity_solve() {
    let (rho, h) = (2000.0, 1e-3);
    for order in [ElementOrder::P1, ElementOrder::P2] {
        let mesh = distorted_rectangle(order);
        let dofs = DofMap::new(
            mesh.nodes.len(),
            &[
                (mesh.node_sets["bottom"].clone(), Constraint::Fixed),
                (mesh.node_sets["left"].clone(), Constraint::FixX),
                (
                    mesh.nodes_in_box([1.0, 2.0], [2.2, 2.0]).unwrap(),
                    Constraint::FixY,
                ),
            ],
        )
        .unwrap();
        let asm = Assembly::new(&mesh, &dofs, rho).unwrap();
        let s0 = isotropic_compliance::<4>(2e7, 0.3);
        let n_s = 4 * asm.n_points();
        let mut s = DMatrix::zeros(n_s, n_s);
        let mut s_inv = DMatrix::zeros(n_s, n_s);
        for (p, block) in asm.compliance_blocks(&s0).iter().enumerate() {
            s.view_mut((4 * p, 4 * p), (4, 4)).copy_from(block);
            s_inv
                .view_mut((4 * p, 4 * p), (4, 4))
                .copy_from(&block.try_inverse().unwrap());
        }
        let (bf, bp) = (dense(&asm.b_free), dense(&asm.b_prescribed));
        let m = DMatrix::from_diagonal(&DVector::from_vec(asm.lumped_mass_free.clone()));
        let m_inv = DMatrix::from_diagonal(&DVector::from_iterator(
            dofs.n_free(),
            asm.lumped_mass_free.iter().map(|m| 1.0 / m),
        ));
        let (f, _) = asm.body_force(rho, [0.0, -9.81]).unwrap();
        let f = DVector::from_vec(f);
        let v_n = DVector::from_fn(dofs.n_free(), |i, _| 1e-3 * ((i as f64) * 0.37).sin());
        let v_p = DVector::from_fn(dofs.n_prescribed(), |j, _| {
            let (n, c) = dofs.prescribed_dofs()[j];
            if c == 1 && mesh.nodes[n][1] == 2.0 {
                -0.01 // the footing pushes down
            } else {
                0.0
            }
        });
        let sigma_n = DVector::from_fn(n_s, |k, _| if k % 4 < 3 { -5e3 } else { 1e3 });

        let w = &s + h * h * &bf * &m_inv * bf.transpose();
        let q = -(&s * &sigma_n + h * &bf * &v_n + h * &bp * &v_p + h * h * &bf * &m_inv * &f);
        let sigma = w.lu().solve(&(-q)).unwrap();
        let v = &v_n + h * &m_inv * (&f - bf.transpose() * &sigma);

        let k = &m + h * h * bf.transpose() * &s_inv * &bf;
        let rhs = &m * &v_n + h * (&f - bf.transpose() * &sigma_n)
            - h * h * bf.transpose() * &s_inv * &bp * &v_p;
        let v_direct = k.cholesky().unwrap().solve(&rhs);
        let scale = v_direct.amax();
        assert!((&v - &v_direct).amax() < 1e-10 * scale, "{order:?}");
        // and σ is the elastic update of the total strain rate
        let sigma_direct = &sigma_n + h * &s_inv * (&bf * &v + &bp * &v_p);
        assert!(
            (&sigma - &sigma_direct).amax() < 1e-8 * sigma_direct.amax(),
            "{order:?}"
        );
    }
}
