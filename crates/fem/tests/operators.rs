//! Gauss volumes, lumped masses, the strain operator `B` and the compliance blocks against
//! closed forms.
use crate::common;

use common::{affine_field, distorted_rectangle, mandel_sym, AREA};
use nalgebra::SMatrix;
use talus_fem::{Assembly, Constraint, DofMap, ElementOrder, Mesh};

const ORDERS: [ElementOrder; 2] = [ElementOrder::P1, ElementOrder::P2];
const RHO: f64 = 1800.0;

/// Supports of a soil box: smooth base (FixY), rollers on the left (FixX), a fixed corner.
fn box_dofs(mesh: &Mesh) -> DofMap {
    DofMap::new(
        mesh.nodes.len(),
        &[
            (mesh.node_sets["bottom"].clone(), Constraint::FixY),
            (mesh.node_sets["left"].clone(), Constraint::FixX),
            (vec![0], Constraint::Fixed),
        ],
    )
    .unwrap()
}

#[test]
fn gauss_volumes_sum_to_domain_area() {
    for order in ORDERS {
        let mesh = distorted_rectangle(order);
        let asm = Assembly::new(&mesh, &box_dofs(&mesh), RHO).unwrap();
        let total: f64 = asm.gauss_volumes.iter().sum();
        assert!((total - AREA).abs() < 1e-13, "{order:?}: {total}");
        assert!(asm.gauss_volumes.iter().all(|v| *v > 0.0));
        let per_element = if order == ElementOrder::P1 { 1 } else { 3 };
        assert_eq!(asm.n_points(), per_element * mesh.triangles.len());
        assert_eq!(asm.gauss_element.len(), asm.n_points());
    }
}

#[test]
fn lumped_mass_totals_density_times_area() {
    for order in ORDERS {
        let mesh = distorted_rectangle(order);
        let asm = Assembly::new(&mesh, &box_dofs(&mesh), RHO).unwrap();
        let total: f64 = asm
            .lumped_mass_free
            .iter()
            .chain(&asm.lumped_mass_prescribed)
            .sum();
        // every node carries its mass in both components
        assert!(
            (total - 2.0 * RHO * AREA).abs() < 1e-9,
            "{order:?}: {total}"
        );
        assert!(
            asm.lumped_mass_free
                .iter()
                .chain(&asm.lumped_mass_prescribed)
                .all(|m| *m > 0.0),
            "{order:?}: a non-positive mass"
        );
    }
}

/// HRZ on one affine P2 triangle: vertex masses m_e/19, mid-node masses 16 m_e/57
/// (consistent diagonal 6 : 32, scaled to the element mass).
#[test]
fn p2_hrz_lumping_gives_vertex_one_nineteenth() {
    // One cell cut along (0,0)–(2,1): the corner (2, 0) and the mid node (1, 0) belong to
    // one triangle only.
    let mesh = Mesh::rectangle(&[0.0, 2.0], &[0.0, 1.0], ElementOrder::P2).unwrap();
    let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
    let asm = Assembly::new(&mesh, &dofs, RHO).unwrap();
    let m_e = RHO * 1.0; // each triangle has area 1
    let corner = mesh.nodes.iter().position(|p| *p == [2.0, 0.0]).unwrap();
    let mid_bottom = mesh.nodes.iter().position(|p| *p == [1.0, 0.0]).unwrap();
    let mass = |n: usize| asm.lumped_mass_free[dofs.free(n, 0).unwrap()];
    assert!((mass(corner) - m_e / 19.0).abs() < 1e-12 * m_e);
    assert!((mass(mid_bottom) - 16.0 * m_e / 57.0).abs() < 1e-12 * m_e);
}

/// For `v(x) = v0 + G x`, `B v` is exactly `V_p · sym G` (Mandel) at every Gauss point, on
/// curved P2 triangles too (isoparametric elements reproduce affine fields).
#[test]
fn b_times_affine_velocity_is_volume_times_sym_gradient() {
    let g = [[0.3, -1.1], [0.7, 0.2]];
    for order in ORDERS {
        let mesh = distorted_rectangle(order);
        let dofs = box_dofs(&mesh);
        let asm = Assembly::new(&mesh, &dofs, RHO).unwrap();
        let (vf, vp) = affine_field(&mesh, &dofs, [2.0, -3.0], g);
        let mut bv = vec![0.0; 4 * asm.n_points()];
        for (b, v) in [(&asm.b_free, &vf), (&asm.b_prescribed, &vp)] {
            let (cp, ri, val) = (b.symbolic().col_ptr(), b.symbolic().row_idx(), b.val());
            for j in 0..b.ncols() {
                for k in cp[j]..cp[j + 1] {
                    bv[ri[k]] += val[k] * v[j];
                }
            }
        }
        let e = mandel_sym(g);
        for (p, vol) in asm.gauss_volumes.iter().enumerate() {
            for r in 0..4 {
                let want = vol * e[r];
                assert!(
                    (bv[4 * p + r] - want).abs() < 1e-13,
                    "{order:?}: point {p}, row {r}: {} vs {want}",
                    bv[4 * p + r]
                );
            }
        }
    }
}

/// The single-element closed form: P1 triangle (0,0), (1,0), (0,1), area 1/2, so
/// `B = ½ [[−1, 0, 1, 0, 0, 0], [0, −1, 0, 0, 0, 1], 0, [−1, −1, 0, 1, 1, 0]/√2]`.
#[test]
fn b_of_reference_p1_triangle_matches_hand_computation() {
    let mesh = Mesh {
        order: ElementOrder::P1,
        nodes: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
        triangles: vec![vec![0, 1, 2]],
        node_sets: Default::default(),
        edge_sets: Default::default(),
        element_sets: Default::default(),
    };
    let dofs = DofMap::new(3, &[]).unwrap();
    let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
    let b = common::dense(&asm.b_free);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let want = SMatrix::<f64, 4, 6>::from_row_slice(&[
        -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, //
        0.0, -1.0, 0.0, 0.0, 0.0, 1.0, //
        0.0, 0.0, 0.0, 0.0, 0.0, 0.0, //
        -s, -s, 0.0, s, s, 0.0,
    ]) * 0.5;
    assert!((b - want).amax() < 1e-15);
    assert_eq!(asm.gauss_points, vec![[1.0 / 3.0, 1.0 / 3.0]]);
}

#[test]
fn compliance_blocks_carry_the_gauss_volume() {
    let mesh = distorted_rectangle(ElementOrder::P2);
    let asm = Assembly::new(&mesh, &box_dofs(&mesh), RHO).unwrap();
    let s0 = talus_bipotential::mandel::isotropic_compliance::<4>(1e7, 0.3);
    let blocks = asm.compliance_blocks(&s0);
    assert_eq!(blocks.len(), asm.n_points());
    for (b, v) in blocks.iter().zip(&asm.gauss_volumes) {
        assert!((b - s0 * *v).amax() == 0.0);
    }
}

/// `Bᵀσ` of a constant stress vanishes at interior free nodes (no net internal force)
/// and is the boundary traction `σ n` integrated on the prescribed ones.
#[test]
fn internal_force_of_uniform_stress_balances() {
    for order in ORDERS {
        let mesh = distorted_rectangle(order);
        let bottom_fixed = DofMap::new(
            mesh.nodes.len(),
            &[(mesh.node_sets["bottom"].clone(), Constraint::Fixed)],
        )
        .unwrap();
        let asm = Assembly::new(&mesh, &bottom_fixed, RHO).unwrap();
        // Uniform σyy = −p (compression).
        let p = 1e3;
        let sigma: Vec<f64> = (0..asm.n_points())
            .flat_map(|_| [0.0, -p, 0.0, 0.0])
            .collect();
        let (ff, fp) = asm.internal_force(&sigma).unwrap();
        // Interior free nodes: zero; the top nodes carry the top's share.
        let top = &mesh.node_sets["top"];
        let mut top_sum = 0.0;
        for n in 0..mesh.nodes.len() {
            if let Some(i) = bottom_fixed.free(n, 1) {
                if top.contains(&n) {
                    top_sum += ff[i];
                } else {
                    assert!(ff[i].abs() < 1e-9, "{order:?}: node {n}: {}", ff[i]);
                }
            }
        }
        // (Bᵀσ)_a = ∫ ∇N_a·σ = ∮ N_a σn: σn = (0, −p) on the top (length 3), (0, +p) on
        // the base.
        assert!((top_sum - (-p * 3.0)).abs() < 1e-9, "{order:?}: {top_sum}");
        let base: f64 = bottom_fixed
            .prescribed_dofs()
            .iter()
            .zip(&fp)
            .filter(|((_, c), _)| *c == 1)
            .map(|(_, f)| f)
            .sum();
        assert!((base - p * 3.0).abs() < 1e-9, "{order:?}: {base}");
    }
}
