//! Loads varying in space and point loads: `Assembly::pressure_with` (a pressure `p(x)`,
//! compression positive, against the outward normal) and `Assembly::point_force`.
//!
//! Closed forms, water of unit weight `γ_w` on a vertical wall of height `H`
//! (`p = γ_w (H − y)`):
//! - plane strain, per metre: resultant `∫₀^H p dy = γ_w H²/2`, moment about the base
//!   `∫₀^H p y dy = γ_w H³/6`, so the line of action lies at `H/3` above the base;
//! - axisymmetric, a cylinder wall `r = R`, per radian: `R γ_w H²/2` and `R γ_w H³/6`
//!   (same line of action).
//!
//! The nodal forces reproduce both exactly: `Σ_a N_a = 1` and `Σ_a N_a y_a = y` on an
//! isoparametric edge, and the rule integrates the linear pressure exactly.
use talus_fem::{
    Assembly, BoundaryEdge, Constraint, Dof, DofMap, ElementOrder, FemError, Geometry, Mesh,
    MeshError,
};

const ORDERS: [ElementOrder; 2] = [ElementOrder::P1, ElementOrder::P2];
const GEOMETRIES: [Geometry; 2] = [Geometry::PlaneStrain, Geometry::Axisymmetric];
const GAMMA_W: f64 = 9810.0;

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

fn max_abs(f: &(Vec<f64>, Vec<f64>)) -> f64 {
    f.0.iter().chain(&f.1).fold(0.0, |m, v| m.max(v.abs()))
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

/// `[x0, x0 + 3] × [0, 2]` on an uneven grid, its interior nodes moved a little and, in P2,
/// the mid nodes of the right side pushed out (curved edges).
fn uneven(order: ElementOrder, x0: f64, curved: bool) -> Mesh {
    let xs: Vec<f64> = [0.0, 0.37, 1.1, 1.9, 3.0].iter().map(|x| x0 + x).collect();
    let mut mesh = Mesh::rectangle(&xs, &[0.0, 0.45, 0.5, 1.3, 2.0], order).unwrap();
    let right = x0 + 3.0;
    for (i, p) in mesh.nodes.iter_mut().enumerate() {
        if p[0] > x0 && p[0] < right && p[1] > 0.0 && p[1] < 2.0 {
            p[0] += 0.004 * (i as f64 * 1.7).sin();
            p[1] += 0.003 * (i as f64 * 2.3).cos();
        }
    }
    if curved && order == ElementOrder::P2 {
        for e in &mesh.edge_sets["right"] {
            let (a, b) = (mesh.nodes[e.nodes[0]], mesh.nodes[e.nodes[1]]);
            let bulge = 0.08 * (b[1] - a[1]).abs();
            mesh.nodes[e.nodes[2]][0] = right + bulge;
        }
    }
    mesh.validate().unwrap();
    mesh
}

fn assembly(mesh: &Mesh, geometry: Geometry) -> (DofMap, Assembly) {
    let dofs = dofs_for(mesh, geometry);
    let asm = Assembly::with_geometry(mesh, &dofs, 2000.0, geometry).unwrap();
    (dofs, asm)
}

/// A constant `p` through the 4-point rule gives the forces of `pressure` (3-point rule)
/// to rounding, on straight and curved edges, the whole boundary and each side.
#[test]
fn constant_pressure_matches_pressure() {
    let p = 1.3e5;
    for order in ORDERS {
        for geometry in GEOMETRIES {
            let mesh = uneven(order, 0.0, true);
            let (_, asm) = assembly(&mesh, geometry);
            let mut sets: Vec<(String, Vec<BoundaryEdge>)> = mesh
                .edge_sets
                .iter()
                .map(|(k, v)| (k.clone(), v.clone()))
                .collect();
            sets.push(("boundary".into(), mesh.boundary_edges()));
            for (name, edges) in sets {
                let want = asm.pressure(&mesh, &edges, p).unwrap();
                let got = asm.pressure_with(&mesh, &edges, |_| p).unwrap();
                let scale = max_abs(&want); // 0 on the axis: then equal exactly
                for (a, b) in got.0.iter().chain(&got.1).zip(want.0.iter().chain(&want.1)) {
                    assert!(
                        (a - b).abs() <= 1e-14 * scale,
                        "{order:?}, {geometry:?}, {name}: {a} vs {b}"
                    );
                }
            }
        }
    }
}

/// Resultant (x, y) and moment about the base `Σ f_x y` of the nodal forces.
fn wall_resultant(mesh: &Mesh, forces: &[[f64; 2]]) -> ([f64; 2], f64) {
    let (mut r, mut m) = ([0.0; 2], 0.0);
    for (x, f) in mesh.nodes.iter().zip(forces) {
        r[0] += f[0];
        r[1] += f[1];
        m += f[0] * x[1];
    }
    (r, m)
}

/// Water of height H = 2 m against the left side (outward normal −x: pushed towards +x)
/// and the right side (pushed towards −x) of a block. Plane strain: `±γ_w H²/2` at `H/3`.
/// Axisymmetric, a thick cylinder `R_in = 1.5 ≤ r ≤ 4.5`: `±R γ_w H²/2` per radian at
/// `H/3`, with `R` the loaded wall's radius. No vertical force on a vertical wall.
#[test]
fn hydrostatic_wall_force_and_line_of_action() {
    let h = 2.0;
    let water = |x: [f64; 2]| GAMMA_W * (h - x[1]);
    for order in ORDERS {
        for geometry in GEOMETRIES {
            let x0 = match geometry {
                Geometry::PlaneStrain => 0.0,
                Geometry::Axisymmetric => 1.5,
                Geometry::ThreeDimensional => unreachable!("a triangle mesh is 2D"),
            };
            let mesh = uneven(order, x0, false);
            let (dofs, asm) = assembly(&mesh, geometry);
            for (side, radius, sign) in [("left", x0, 1.0), ("right", x0 + 3.0, -1.0)] {
                let per_unit = match geometry {
                    Geometry::PlaneStrain => 1.0,
                    Geometry::Axisymmetric => radius,
                    Geometry::ThreeDimensional => unreachable!("a triangle mesh is 2D"),
                };
                let f = asm
                    .pressure_with(&mesh, &mesh.edge_sets[side], water)
                    .unwrap();
                let (r, m) = wall_resultant(&mesh, &nodal(&dofs, &f));
                let force = sign * per_unit * GAMMA_W * h * h / 2.0;
                let moment = sign * per_unit * GAMMA_W * h * h * h / 6.0;
                let what = format!("{order:?}, {geometry:?}, {side}");
                assert!(
                    (r[0] - force).abs() <= 1e-12 * force.abs(),
                    "{what}: force {}, want {force}",
                    r[0]
                );
                assert!(
                    r[1].abs() <= 1e-12 * force.abs(),
                    "{what}: vertical {}",
                    r[1]
                );
                assert!(
                    (m - moment).abs() <= 1e-12 * moment.abs(),
                    "{what}: moment {m}, want {moment}"
                );
                let line = m / r[0];
                assert!(
                    (line - h / 3.0).abs() <= 1e-12 * h,
                    "{what}: line of action at {line}, want {}",
                    h / 3.0
                );
            }
        }
    }
}

/// Axisymmetric, a pressure linear in `r` on the top of a full disc `r ≤ R`, `y = 2`
/// (outward normal +y: pushed down): `p = a + b r` gives the axial force per radian
/// `−∫₀^R (a + b r) r dr = −(a R²/2 + b R³/3)`, whose integrand against `N_a` has degree
/// 4 on straight P2 edges; its moment about the axis `Σ f_y r = −(a R³/3 + b R⁴/4)`.
#[test]
fn axisymmetric_pressure_linear_in_r_on_a_disc() {
    let (a, b, radius): (f64, f64, f64) = (2.0e4, 3.5e4, 3.0);
    for order in ORDERS {
        let mesh = uneven(order, 0.0, false);
        let (dofs, asm) = assembly(&mesh, Geometry::Axisymmetric);
        let f = asm
            .pressure_with(&mesh, &mesh.edge_sets["top"], |x| a + b * x[0])
            .unwrap();
        let forces = nodal(&dofs, &f);
        let fy: f64 = forces.iter().map(|f| f[1]).sum();
        let fx: f64 = forces.iter().map(|f| f[0]).sum();
        let my: f64 = mesh
            .nodes
            .iter()
            .zip(&forces)
            .map(|(x, f)| f[1] * x[0])
            .sum();
        let want = -(a * radius.powi(2) / 2.0 + b * radius.powi(3) / 3.0);
        let want_m = -(a * radius.powi(3) / 3.0 + b * radius.powi(4) / 4.0);
        assert!(
            (fy - want).abs() <= 1e-12 * want.abs(),
            "{order:?}: {fy} vs {want}"
        );
        assert!(
            (my - want_m).abs() <= 1e-12 * want_m.abs(),
            "{order:?}: {my}"
        );
        assert!(fx.abs() <= 1e-12 * want.abs(), "{order:?}: {fx}");
    }
}

/// `−∫ p N_a n r ds` per node, by a composite 3-point Gauss rule on 64 pieces of each
/// edge (exact to rounding for these polynomial integrands), as an independent reference.
fn reference(
    mesh: &Mesh,
    dofs: &DofMap,
    geometry: Geometry,
    edges: &[BoundaryEdge],
    p: impl Fn([f64; 2]) -> f64,
) -> Vec<[f64; 2]> {
    let edges = mesh.orient_boundary_edges(edges).unwrap();
    let gl = [
        (0.5 - 0.5 * (0.6f64).sqrt(), 5.0 / 18.0),
        (0.5, 8.0 / 18.0),
        (0.5 + 0.5 * (0.6f64).sqrt(), 5.0 / 18.0),
    ];
    let pieces = 64;
    let mut out = vec![[0.0; 2]; dofs.n_nodes()];
    for e in &edges {
        let x: Vec<[f64; 2]> = e.nodes.iter().map(|&n| mesh.nodes[n]).collect();
        for k in 0..pieces {
            for (t, w) in gl {
                let s = (k as f64 + t) / pieces as f64;
                let (n, dn) = if x.len() == 2 {
                    (vec![1.0 - s, s], vec![-1.0, 1.0])
                } else {
                    (
                        vec![
                            (1.0 - s) * (1.0 - 2.0 * s),
                            s * (2.0 * s - 1.0),
                            4.0 * s * (1.0 - s),
                        ],
                        vec![4.0 * s - 3.0, 4.0 * s - 1.0, 4.0 - 8.0 * s],
                    )
                };
                let mut pos = [0.0; 2];
                let mut tan = [0.0; 2];
                for a in 0..x.len() {
                    for c in 0..2 {
                        pos[c] += n[a] * x[a][c];
                        tan[c] += dn[a] * x[a][c];
                    }
                }
                let r = geometry.weight(pos);
                let ds = w / pieces as f64;
                for (a, &node) in e.nodes.iter().enumerate() {
                    // −p n ds with n ds = (y′, −x′) ds
                    out[node][0] -= ds * r * p(pos) * n[a] * tan[1];
                    out[node][1] += ds * r * p(pos) * n[a] * tan[0];
                }
            }
        }
    }
    out
}

/// On the curved P2 side, a pressure linear in x and y gives the reference nodal forces in
/// both geometries (axisymmetric: degree 7 in s, the 4-point rule's limit).
#[test]
fn linear_pressure_on_curved_edges_is_exact() {
    let p = |x: [f64; 2]| 1.0e5 + 2.0e4 * x[0] - 3.0e4 * x[1];
    for geometry in GEOMETRIES {
        for (order, curved) in [(ElementOrder::P2, true), (ElementOrder::P1, false)] {
            let mesh = uneven(order, 0.5, curved);
            let (dofs, asm) = assembly(&mesh, geometry);
            let edges = mesh.boundary_edges();
            let got = nodal(&dofs, &asm.pressure_with(&mesh, &edges, p).unwrap());
            let want = reference(&mesh, &dofs, geometry, &edges, p);
            let scale = want.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            for (n, (g, w)) in got.iter().zip(&want).enumerate() {
                for c in 0..2 {
                    assert!(
                        (g[c] - w[c]).abs() <= 1e-13 * scale,
                        "{order:?}, {geometry:?}, node {n}[{c}]: {} vs {}",
                        g[c],
                        w[c]
                    );
                }
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

/// A NaN or infinite pressure at a quadrature point is refused, naming the edge (index in
/// the list, nodes) and the point.
#[test]
fn non_finite_pressure_names_edge_and_point() {
    for order in ORDERS {
        let mesh = uneven(order, 0.0, false);
        let (_, asm) = assembly(&mesh, Geometry::PlaneStrain);
        let edges = &mesh.edge_sets["left"];
        // NaN from y > 1.4 on: the first edge (in list order) reaching above it
        let first = edges
            .iter()
            .position(|e| e.nodes.iter().any(|&n| mesh.nodes[n][1] > 1.4))
            .unwrap();
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let err = asm
                .pressure_with(&mesh, edges, |x| if x[1] > 1.4 { bad } else { 1.0e4 })
                .unwrap_err();
            let (field, reason) = invalid(err);
            assert_eq!(field, "pressure", "{reason}");
            assert!(
                reason.contains(&format!("edge {first} (nodes {:?})", edges[first].nodes))
                    && reason.contains("quadrature point")
                    && reason.contains(&format!("p = {bad} Pa")),
                "{order:?}: {reason}"
            );
        }
        let (_, reason) = invalid(asm.pressure_with(&mesh, edges, |_| f64::NAN).unwrap_err());
        assert!(
            reason.contains("quadrature point 0 ") && reason.contains("edge 0 "),
            "{reason}"
        );
        // an interior edge is still refused by the orientation, as in `pressure`
        let tri = &mesh.triangles[0];
        let boundary = mesh.boundary_edges();
        let interior = (0..3)
            .map(|k| {
                let mut nodes = vec![tri[k], tri[(k + 1) % 3]];
                if order == ElementOrder::P2 {
                    nodes.push(tri[3 + k]);
                }
                BoundaryEdge { nodes }
            })
            .find(|e| {
                !boundary.iter().any(|b| {
                    b.nodes[..2] == e.nodes[..2] || b.nodes[..2] == [e.nodes[1], e.nodes[0]]
                })
            })
            .unwrap();
        let err = asm
            .pressure_with(&mesh, std::slice::from_ref(&interior), |_| 1.0)
            .unwrap_err();
        assert!(
            matches!(
                &err,
                FemError::Mesh(MeshError::InvalidInput { field: "edges", .. })
            ),
            "{err:?}"
        );
        assert_eq!(err, asm.pressure(&mesh, &[interior], 1.0).unwrap_err());
    }
}

/// A point force lands on its node's dofs, free or prescribed, and nowhere else.
#[test]
fn point_force_goes_to_its_node_free_or_prescribed() {
    let force = [3.5e3, -7.25e4];
    for order in ORDERS {
        for geometry in GEOMETRIES {
            let mesh = uneven(order, 0.0, false);
            let (dofs, asm) = assembly(&mesh, geometry);
            let top_right = mesh
                .nodes
                .iter()
                .position(|x| x[0] == 3.0 && x[1] == 2.0)
                .unwrap();
            let bottom = mesh.node_sets["bottom"][1];
            let mut nodes = vec![top_right, bottom];
            if geometry == Geometry::Axisymmetric {
                // on the axis: u_r prescribed, u_y free
                let axis_top = mesh
                    .nodes
                    .iter()
                    .position(|x| x[0] == 0.0 && x[1] == 2.0)
                    .unwrap();
                assert!(dofs.prescribed(axis_top, 0).is_some() && dofs.free(axis_top, 1).is_some());
                nodes.push(axis_top);
            }
            for node in nodes {
                let f = asm.point_force(node, force).unwrap();
                assert_eq!(f.0.len(), dofs.n_free());
                assert_eq!(f.1.len(), dofs.n_prescribed());
                let forces = nodal(&dofs, &f);
                for (n, fa) in forces.iter().enumerate() {
                    let want = if n == node { force } else { [0.0; 2] };
                    assert_eq!(*fa, want, "{order:?}, {geometry:?}, node {n}");
                }
                // one entry per component, in the vector of its dof's kind
                let free = (0..2).filter(|&c| dofs.free(node, c).is_some()).count();
                assert_eq!(f.0.iter().filter(|v| **v != 0.0).count(), free);
                assert_eq!(f.1.iter().filter(|v| **v != 0.0).count(), 2 - free);
            }
            // a fixed bottom node's force enters only the prescribed vector
            let f = asm.point_force(bottom, force).unwrap();
            assert!(f.0.iter().all(|v| *v == 0.0));
            assert_eq!(f.1.iter().sum::<f64>(), force[0] + force[1]);
            // errors name the field
            let (field, reason) = invalid(asm.point_force(mesh.nodes.len(), force).unwrap_err());
            assert_eq!(field, "node");
            assert!(
                reason.contains(&format!("{} nodes", mesh.nodes.len())),
                "{reason}"
            );
            for bad in [[f64::NAN, 0.0], [0.0, f64::INFINITY]] {
                let (field, _) = invalid(asm.point_force(top_right, bad).unwrap_err());
                assert_eq!(field, "force");
            }
        }
    }
}
