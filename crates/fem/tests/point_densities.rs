//! A mass density per Gauss point (soil layers, saturated soil below a water table):
//! `Assembly::with_point_densities` and `Assembly::body_force_at_points`.
//!
//! - A constant vector gives the bits of the scalar entry points (`with_geometry`,
//!   `body_force`): the same operations in the same order.
//! - Two layers meeting on an element boundary: the total mass is `ρ₁A₁ + ρ₂A₂` (plane
//!   strain, per metre) or `Σ ρ_i ∫ r dA = Σ ρ_i R²/2 · h_i` (axisymmetric, per radian, a
//!   full disc of radius R), and the total weight that times `g`; the rules are exact for
//!   these integrands on affine triangles (P1: `r` linear at the centroid; P2: `r det J`
//!   linear with the degree-2 rule; `Σ_a N_a = 1`).
//! - The density enters point by point: raising it by `Δρ` at one Gauss point adds
//!   `Δρ V_p / 3` to each vertex of a P1 triangle, and `Δρ V_p / 19` to each vertex and
//!   `16 Δρ V_p / 57` to each mid node of an affine P2 triangle (HRZ, the weights of
//!   `mass.rs`), and nothing elsewhere.
use talus_fem::{Assembly, Constraint, Dof, DofMap, ElementOrder, FemError, Geometry, Mesh};

const ORDERS: [ElementOrder; 2] = [ElementOrder::P1, ElementOrder::P2];
const GEOMETRIES: [Geometry; 2] = [Geometry::PlaneStrain, Geometry::Axisymmetric];

/// An uneven rectangle `[0, 3] × [0, 2]` (left side on the axis in axisymmetry) with its
/// interior nodes moved a little, so that no volume or shape function value is round.
fn jittered(order: ElementOrder) -> Mesh {
    let mut mesh = Mesh::rectangle(
        &[0.0, 0.37, 1.1, 1.9, 3.0],
        &[0.0, 0.45, 0.5, 1.3, 2.0],
        order,
    )
    .unwrap();
    for (i, p) in mesh.nodes.iter_mut().enumerate() {
        if p[0] > 0.0 && p[0] < 3.0 && p[1] > 0.0 && p[1] < 2.0 {
            p[0] += 0.004 * (i as f64 * 1.7).sin();
            p[1] += 0.003 * (i as f64 * 2.3).cos();
        }
    }
    mesh
}

/// Bottom fixed, and the axis nodes' `u_r` prescribed in axisymmetry.
fn dofs_for(mesh: &Mesh, geometry: Geometry) -> DofMap {
    DofMap::new(
        mesh.nodes.len(),
        &[
            (mesh.node_sets["bottom"].clone(), Constraint::Fixed),
            (geometry.axis_nodes(mesh), Constraint::FixX),
        ],
    )
    .unwrap()
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Mass of every node (both components of a node carry it).
fn node_masses(dofs: &DofMap, asm: &Assembly) -> Vec<f64> {
    (0..dofs.n_nodes())
        .map(|n| match dofs.dof(n, 0).unwrap() {
            Dof::Free(i) => asm.lumped_mass_free[i],
            Dof::Prescribed(j) => asm.lumped_mass_prescribed[j],
        })
        .collect()
}

/// Sum of each force component over all nodes, free and prescribed dofs together.
fn totals(dofs: &DofMap, f: &(Vec<f64>, Vec<f64>)) -> [f64; 2] {
    let mut t = [0.0; 2];
    for n in 0..dofs.n_nodes() {
        for (c, tc) in t.iter_mut().enumerate() {
            *tc += match dofs.dof(n, c).unwrap() {
                Dof::Free(i) => f.0[i],
                Dof::Prescribed(j) => f.1[j],
            };
        }
    }
    t
}

#[test]
fn constant_densities_give_the_bits_of_the_scalar_entry_points() {
    let g = [0.3, -9.81];
    for order in ORDERS {
        for geometry in GEOMETRIES {
            let mesh = jittered(order);
            let dofs = dofs_for(&mesh, geometry);
            for rho in [1.0, 1900.0, 2713.3] {
                let scalar = Assembly::with_geometry(&mesh, &dofs, rho, geometry).unwrap();
                let n = scalar.n_points();
                let per_point =
                    Assembly::with_point_densities(&mesh, &dofs, &vec![rho; n], geometry).unwrap();
                let what = format!("{order:?}, {geometry:?}, ρ = {rho}");
                assert_eq!(
                    bits(&per_point.lumped_mass_free),
                    bits(&scalar.lumped_mass_free),
                    "{what}: free masses"
                );
                assert_eq!(
                    bits(&per_point.lumped_mass_prescribed),
                    bits(&scalar.lumped_mass_prescribed),
                    "{what}: prescribed masses"
                );
                assert_eq!(per_point.gauss_points, scalar.gauss_points, "{what}");
                assert_eq!(
                    bits(&per_point.gauss_volumes),
                    bits(&scalar.gauss_volumes),
                    "{what}"
                );
                // the weight, with a density other than the inertial one, and weightless
                for weight_density in [0.9 * rho, 0.0] {
                    let a = scalar.body_force(weight_density, g).unwrap();
                    let b = scalar
                        .body_force_at_points(&vec![weight_density; n], g)
                        .unwrap();
                    assert_eq!(bits(&a.0), bits(&b.0), "{what}: free weight");
                    assert_eq!(bits(&a.1), bits(&b.1), "{what}: prescribed weight");
                }
            }
        }
    }
}

/// Density 1000 kg/m³ below y = 0.5, 3000 above, on a grid with a row of element sides at
/// y = 0.5 (affine triangles). Plane strain, `[0, 2.5] × [0, 1.4]`: `M = 1000 · 2.5 · 0.5 +
/// 3000 · 2.5 · 0.9 = 8000` kg/m. Axisymmetric, the disc `r ≤ 2.5`: `M = Σ ρ_i · 2.5²/2 ·
/// h_i = 3.125 · (1000 · 0.5 + 3000 · 0.9) = 10000` kg/rad. Weight: `M g`.
#[test]
fn two_layers_have_the_mass_and_weight_of_their_areas() {
    let (rho_low, rho_high, y_layer) = (1000.0, 3000.0, 0.5);
    let (width, height) = (2.5, 1.4);
    let g = [0.4, -9.81];
    for order in ORDERS {
        for geometry in GEOMETRIES {
            let mesh = Mesh::rectangle(
                &[0.0, 0.4, 1.0, 1.7, 2.5],
                &[0.0, 0.2, 0.5, 0.9, 1.4],
                order,
            )
            .unwrap();
            let dofs = dofs_for(&mesh, geometry);
            let unit = Assembly::with_geometry(&mesh, &dofs, 1.0, geometry).unwrap();
            let densities: Vec<f64> = unit
                .gauss_points
                .iter()
                .map(|x| if x[1] < y_layer { rho_low } else { rho_high })
                .collect();
            let asm = Assembly::with_point_densities(&mesh, &dofs, &densities, geometry).unwrap();
            // ∫ w dA over [0, W] × [y0, y1]: h (plane strain) or W²/2 · h (per radian)
            let measure = |h: f64| match geometry {
                Geometry::PlaneStrain => width * h,
                Geometry::Axisymmetric => width * width / 2.0 * h,
                Geometry::ThreeDimensional => unreachable!("a triangle mesh is 2D"),
            };
            let want = rho_low * measure(y_layer) + rho_high * measure(height - y_layer);
            let what = format!("{order:?}, {geometry:?}");
            let masses = node_masses(&dofs, &asm);
            let total: f64 = masses.iter().sum();
            assert!(
                (total - want).abs() <= 1e-12 * want,
                "{what}: mass {total}, want {want}"
            );
            let weight = totals(&dofs, &asm.body_force_at_points(&densities, g).unwrap());
            for c in 0..2 {
                let w = want * g[c];
                assert!(
                    (weight[c] - w).abs() <= 1e-12 * w.abs(),
                    "{what}: weight[{c}] = {}, want {w}",
                    weight[c]
                );
            }
            // a node inside one layer has that layer's density times its unit mass; the
            // nodes on y = 0.5 lie in between
            let unit_masses = node_masses(&dofs, &unit);
            for (n, x) in mesh.nodes.iter().enumerate() {
                let (m, m1) = (masses[n], unit_masses[n]);
                if x[1] != y_layer {
                    let rho = if x[1] < y_layer { rho_low } else { rho_high };
                    assert!(
                        (m - rho * m1).abs() <= 1e-14 * rho * m1,
                        "{what}: node {n} at {x:?}: {m} vs {rho} × {m1}"
                    );
                } else {
                    assert!(
                        rho_low * m1 < m && m < rho_high * m1,
                        "{what}: node {n} at {x:?}: {m}"
                    );
                }
            }
        }
    }
}

/// Raising the density of one Gauss point by Δρ adds `Δρ V_p × (the HRZ or row-sum share)`
/// to the nodes of its triangle and nothing elsewhere (plane strain, affine triangles: P1
/// 1/3 per vertex; P2 1/19 per vertex, 16/57 per mid node).
#[test]
fn one_point_density_reaches_only_its_triangle_with_the_lumping_shares() {
    let delta = 500.0;
    for order in ORDERS {
        let mesh = Mesh::rectangle(&[0.0, 0.6, 1.5], &[0.0, 0.8, 1.3], order).unwrap();
        let dofs = dofs_for(&mesh, Geometry::PlaneStrain);
        let base = Assembly::new(&mesh, &dofs, 1800.0).unwrap();
        let m0 = node_masses(&dofs, &base);
        for p in 0..base.n_points() {
            let mut densities = vec![1800.0; base.n_points()];
            densities[p] += delta;
            let asm =
                Assembly::with_point_densities(&mesh, &dofs, &densities, Geometry::PlaneStrain)
                    .unwrap();
            let m = node_masses(&dofs, &asm);
            let tri = &mesh.triangles[asm.gauss_element[p]];
            let added = delta * asm.gauss_volumes[p];
            for n in 0..mesh.nodes.len() {
                let want = match tri.iter().position(|&t| t == n) {
                    None => 0.0,
                    Some(_) if order == ElementOrder::P1 => added / 3.0,
                    Some(k) if k < 3 => added / 19.0,
                    Some(_) => added * 16.0 / 57.0,
                };
                let got = m[n] - m0[n];
                assert!(
                    (got - want).abs() <= 1e-12 * m0[n],
                    "{order:?}: point {p}, node {n}: +{got}, want +{want}"
                );
            }
        }
    }
}

fn invalid(e: FemError) -> (&'static str, String) {
    match e {
        FemError::InvalidInput { field, reason } => (field, reason),
        other => panic!("expected an invalid input, got {other:?}"),
    }
}

#[test]
fn bad_densities_are_refused_with_their_index_value_and_expected_length() {
    for order in ORDERS {
        let mesh = jittered(order);
        let dofs = dofs_for(&mesh, Geometry::PlaneStrain);
        let asm = Assembly::new(&mesh, &dofs, 2000.0).unwrap();
        let n = asm.n_points();
        let build = |d: &[f64]| {
            Assembly::with_point_densities(&mesh, &dofs, d, Geometry::PlaneStrain).map(|_| ())
        };
        // length: one per Gauss point
        for len in [0, n - 1, n + 1] {
            let (field, reason) = invalid(build(&vec![2000.0; len]).unwrap_err());
            assert_eq!(field, "densities", "{order:?}: {reason}");
            assert!(
                reason.contains(&format!("{len} values")) && reason.contains(&format!("{n}")),
                "{order:?}: {reason}"
            );
            let (field, reason) = invalid(
                asm.body_force_at_points(&vec![2000.0; len], [0.0, -9.81])
                    .unwrap_err(),
            );
            assert_eq!(field, "densities", "{order:?}: {reason}");
            assert!(reason.contains(&format!("expected {n}")), "{reason}");
        }
        // the first bad entry, by index and value
        for (index, value, text) in [
            (5, 0.0, "0"),
            (0, -1.5, "-1.5"),
            (n - 1, f64::NAN, "NaN"),
            (3, f64::INFINITY, "inf"),
        ] {
            let mut d = vec![2000.0; n];
            d[index] = value;
            d[n - 1] = if index == n - 1 { value } else { -7.0 }; // a later bad one
            let (field, reason) = invalid(build(&d).unwrap_err());
            assert_eq!(field, "densities", "{order:?}: {reason}");
            assert!(
                reason.contains(&format!("densities[{index}] = {text} kg/m³")),
                "{order:?}: {reason}"
            );
            // the weight accepts 0 (a weightless layer), nothing below or non-finite
            let weight = asm.body_force_at_points(&d[..], [0.0, -9.81]);
            if value == 0.0 {
                let (field, reason) = invalid(weight.unwrap_err());
                assert!(field == "densities" && reason.contains(&format!("densities[{}]", n - 1)));
            } else {
                let (field, reason) = invalid(weight.unwrap_err());
                assert_eq!(field, "densities");
                assert!(
                    reason.contains(&format!("densities[{index}] = {text}")),
                    "{reason}"
                );
            }
        }
        let (field, _) = invalid(
            asm.body_force_at_points(&vec![2000.0; n], [f64::NAN, -9.81])
                .unwrap_err(),
        );
        assert_eq!(field, "gravity");
        // the mesh is checked before the densities: a dof map of the wrong size is named
        let other = DofMap::new(3, &[]).unwrap();
        let (field, _) = invalid(
            Assembly::with_point_densities(&mesh, &other, &[1.0; 2], Geometry::PlaneStrain)
                .unwrap_err(),
        );
        assert_eq!(field, "dofs");
    }
}
