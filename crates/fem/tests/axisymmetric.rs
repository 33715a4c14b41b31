//! Axisymmetric operators (`docs/axisymmetry.md`): `x = r`, `y` the axis, everything per
//! radian. Checked against exact integrals over the solid of revolution, the uniform
//! strain patch test with the hoop strain `u_r / r`, and the equilibrium of a uniform
//! stress with the r-weighted boundary pressure (the B rows and the edge loads carry the
//! same `r`).
use crate::common;

use common::{affine_field, distorted_rectangle, AREA};
use talus_fem::{Assembly, Constraint, DofMap, ElementOrder, FemError, Geometry, Mesh, MeshError};

const ORDERS: [ElementOrder; 2] = [ElementOrder::P1, ElementOrder::P2];

/// `mesh` (its left side on the axis) with the axis nodes' u_r prescribed, as the geometry
/// requires.
fn axisymmetric_on(mesh: Mesh) -> (Mesh, DofMap, Assembly) {
    let constraints = vec![(Geometry::Axisymmetric.axis_nodes(&mesh), Constraint::FixX)];
    let dofs = DofMap::new(mesh.nodes.len(), &constraints).unwrap();
    let asm = Assembly::with_geometry(&mesh, &dofs, 2000.0, Geometry::Axisymmetric).unwrap();
    (mesh, dofs, asm)
}

/// The uneven grid of `distorted_rectangle` without the jitter: affine triangles, on which
/// the rules integrate `r det J`, `r ∂N/∂x det J` and `N r` exactly.
fn straight(order: ElementOrder) -> (Mesh, DofMap, Assembly) {
    let mesh = Mesh::rectangle(&[0.0, 0.7, 1.5, 2.2, 3.0], &[0.0, 0.6, 1.3, 2.0], order).unwrap();
    axisymmetric_on(mesh)
}

/// Pappus: the volume of revolution of the rectangle is `2π · ∫ r dA = 2π · 3²/2 · 2`, and
/// every Gauss point lies off the axis (P1 centroid, P2 interior points: `u_r / r` is
/// never evaluated at r = 0).
#[test]
fn volumes_are_r_weighted_and_gauss_points_avoid_the_axis() {
    for order in ORDERS {
        let (mesh, _, asm) = straight(order);
        let on_axis = if order == ElementOrder::P1 { 4 } else { 7 };
        assert_eq!(Geometry::Axisymmetric.axis_nodes(&mesh).len(), on_axis);
        let per_radian: f64 = asm.gauss_volumes.iter().sum();
        assert!((per_radian - 9.0).abs() < 1e-12, "{order:?}: {per_radian}");
        let r_min = asm
            .gauss_points
            .iter()
            .map(|p| p[0])
            .fold(f64::INFINITY, f64::min);
        assert!(r_min > 0.0, "{order:?}: a Gauss point at r = {r_min}");
        // Plane strain on the same mesh: the area.
        let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
        let plane = Assembly::new(&mesh, &dofs, 2000.0).unwrap();
        let area: f64 = plane.gauss_volumes.iter().sum();
        assert!((area - AREA).abs() < 1e-12);
    }
}

/// Patch test: `u_r = α r`, `u_y = γ y + δ r` (the fields an axisymmetric body can take
/// with a uniform strain) give `(α, γ, α, √2 δ/2)` at every Gauss point, the hoop strain
/// `u_r / r = α` included; a constant `u_r = β` away from the axis gives `β / r_p`.
#[test]
fn uniform_strain_and_hoop_strain_are_exact() {
    let (alpha, gamma, delta) = (1.3e-3, -0.7e-3, 0.4e-3);
    for order in ORDERS {
        // Curved P2 triangles too: the isoparametric space holds these fields.
        let (mesh, dofs, asm) = axisymmetric_on(distorted_rectangle(order));
        let (free, prescribed) =
            affine_field(&mesh, &dofs, [0.0, 0.0], [[alpha, 0.0], [delta, gamma]]);
        let exact = [alpha, gamma, alpha, std::f64::consts::FRAC_1_SQRT_2 * delta];
        for e in asm.strain(&free, &prescribed).unwrap() {
            for k in 0..4 {
                assert!((e[k] - exact[k]).abs() < 1e-15, "{order:?} {k}: {}", e[k]);
            }
        }
    }
    // u_r = β: only the hoop strain, β / r at each point (mesh off the axis).
    for order in ORDERS {
        let mesh = Mesh::rectangle(&[1.0, 1.5, 2.5], &[0.0, 1.0], order).unwrap();
        let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
        let asm = Assembly::with_geometry(&mesh, &dofs, 1.0, Geometry::Axisymmetric).unwrap();
        let beta = 2e-3;
        let (free, prescribed) = affine_field(&mesh, &dofs, [beta, 0.0], [[0.0; 2]; 2]);
        for (e, x) in asm
            .strain(&free, &prescribed)
            .unwrap()
            .iter()
            .zip(&asm.gauss_points)
        {
            assert!((e[2] - beta / x[0]).abs() < 1e-15, "{order:?}");
            assert!(e[0].abs() < 1e-15 && e[1].abs() < 1e-15 && e[3].abs() < 1e-15);
        }
    }
}

/// A uniform stress `σ = −p 1` is in equilibrium with the pressure `p` on the boundary:
/// `∫ Bᵀσ r dA = −p ∮ N n r ds` dof by dof (the divergence theorem on `∂(N r)/∂r`; both
/// integrals exact with the rules used), so the r in the volume weights and in the edge
/// loads agree. Free and prescribed dofs alike.
#[test]
fn uniform_pressure_is_in_equilibrium_dof_by_dof() {
    let p = 1.0e5;
    for order in ORDERS {
        let (mesh, _, asm) = straight(order);
        let sigma: Vec<f64> = (0..asm.n_points())
            .flat_map(|_| [-p, -p, -p, 0.0])
            .collect();
        let (int_f, int_p) = asm.internal_force(&sigma).unwrap();
        let edges: Vec<_> = ["right", "bottom", "top"]
            .iter()
            .flat_map(|s| mesh.edge_sets[*s].clone())
            .collect();
        let (ext_f, ext_p) = asm.pressure(&mesh, &edges, p).unwrap();
        // On the axis (left) the edge term vanishes with r: no pressure there.
        for (a, b) in int_f.iter().chain(&int_p).zip(ext_f.iter().chain(&ext_p)) {
            assert!((a - b).abs() < 1e-9 * p, "{order:?}: {a} vs {b}");
        }
    }
}

/// Resultants per radian: a side pressure on r = R over height H pushes `p R H` inwards,
/// a top pressure `p R²/2` down, the weight is `ρ g R² H / 2`, the mass `ρ R² H / 2`.
#[test]
fn loads_and_mass_are_r_weighted() {
    let (r, h, p, rho, g) = (3.0, 2.0, 1.0e5, 2000.0, 9.81);
    for order in ORDERS {
        let (mesh, dofs, asm) = straight(order);
        let sum_comp = |f: &(Vec<f64>, Vec<f64>), comp: usize| -> f64 {
            (0..mesh.nodes.len())
                .map(|n| match dofs.dof(n, comp).unwrap() {
                    talus_fem::Dof::Free(i) => f.0[i],
                    talus_fem::Dof::Prescribed(j) => f.1[j],
                })
                .sum()
        };
        let side = asm.pressure(&mesh, &mesh.edge_sets["right"], p).unwrap();
        assert!(
            (sum_comp(&side, 0) + p * r * h).abs() < 1e-9 * p,
            "{order:?}"
        );
        let top = asm.pressure(&mesh, &mesh.edge_sets["top"], p).unwrap();
        assert!(
            (sum_comp(&top, 1) + p * r * r / 2.0).abs() < 1e-9 * p,
            "{order:?}"
        );
        let traction = asm
            .traction(&mesh, &mesh.edge_sets["top"], [0.0, -p])
            .unwrap();
        assert!((sum_comp(&traction, 1) + p * r * r / 2.0).abs() < 1e-9 * p);
        let weight = asm.body_force(rho, [0.0, -g]).unwrap();
        let exact = rho * g * r * r * h / 2.0;
        assert!(
            (sum_comp(&weight, 1) + exact).abs() < 1e-12 * exact,
            "{order:?}"
        );
        // Both components of a node carry its mass: sum one of them.
        let mass: f64 = (0..mesh.nodes.len())
            .map(|n| match dofs.dof(n, 1).unwrap() {
                talus_fem::Dof::Free(i) => asm.lumped_mass_free[i],
                talus_fem::Dof::Prescribed(j) => asm.lumped_mass_prescribed[j],
            })
            .sum();
        assert!(
            (mass - rho * r * r * h / 2.0).abs() < 1e-10 * mass,
            "{order:?}"
        );
        assert!(asm.lumped_mass_free.iter().all(|m| *m > 0.0));
    }
}

#[test]
fn meshes_across_the_axis_and_free_axis_nodes_are_refused() {
    let mesh = Mesh::rectangle(&[-0.5, 0.0, 1.0], &[0.0, 1.0], ElementOrder::P1).unwrap();
    let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
    let err = Assembly::with_geometry(&mesh, &dofs, 1.0, Geometry::Axisymmetric).unwrap_err();
    assert!(
        matches!(&err, FemError::Mesh(MeshError::InvalidInput { field: "mesh", reason }) if reason.contains("r ≥ 0") && reason.contains("-5e-1")),
        "{err}"
    );
    let mesh = Mesh::rectangle(&[0.0, 1.0], &[0.0, 1.0], ElementOrder::P2).unwrap();
    let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
    let err = Assembly::with_geometry(&mesh, &dofs, 1.0, Geometry::Axisymmetric).unwrap_err();
    assert!(err.to_string().contains("free radial velocity"), "{err}");
    // Plane strain takes both.
    assert!(Assembly::new(&mesh, &dofs, 1.0).is_ok());
}
