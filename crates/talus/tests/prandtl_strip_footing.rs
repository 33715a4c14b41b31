//! Prandtl's bearing capacity of a rigid strip footing on a weightless cohesive-frictional
//! soil: the limit pressure is `q_u = c N_c` with `N_c = (N_q − 1) cot φ` and
//! `N_q = e^{π tan φ} tan²(45° + φ/2)` (Prandtl 1920). The scenes `scenes/prandtl_phi20.toml`
//! and `scenes/prandtl_phi30.toml` (geometry, mesh and loading documented there) model half
//! of a smooth footing of width b with an associative Drucker-Prager soil under the
//! plane-strain cone fit, which reproduces the Mohr-Coulomb collapse loads. The footing is
//! driven at constant velocity; the force `F = 2 × reaction` of the half model rises to a
//! plateau, the limit load approached from below, and `F / (b c)` must be within 5% of N_c.
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
use std::path::Path;
use std::time::Instant;

use talus::model::fem::ReactionForce;
use talus::model::fem::{FromScene, Model};
use talus::run::fem::run_scene;
use talus::run::RunOptions;
use talus::scene::{Fix, MeshSpec, Order, Scene, Selection};
use talus_bipotential::ConeFit;

/// Relative tolerance on N_c.
const TOLERANCE: f64 = 0.05;
/// Largest relative change of the force over the last 10% of the steps (the plateau).
const PLATEAU: f64 = 0.01;

/// Prandtl's `N_c(φ)`, φ in degrees.
fn prandtl_nc(phi_deg: f64) -> f64 {
    let phi = phi_deg.to_radians();
    let nq = (PI * phi.tan()).exp() * (FRAC_PI_4 + phi / 2.0).tan().powi(2);
    (nq - 1.0) / phi.tan()
}

/// Extent of Prandtl's mechanism under a smooth footing of width `b`: how far from the
/// footing centre the passive wedge reaches the surface, and how deep the log-spiral fan
/// goes. The active wedge's sides leave the footing edges at 45° + φ/2 below the
/// horizontal (length `r₀ = (b/2) / cos(45° + φ/2)`), the fan turns by 90° with
/// `r = r₀ e^{ψ tan φ}`, and the passive wedge's base meets the surface at 45° − φ/2 over a
/// length `2 r₁ cos(45° − φ/2)`, `r₁ = r₀ e^{(π/2) tan φ}`.
fn prandtl_mechanism(phi_deg: f64, b: f64) -> (f64, f64) {
    let phi = phi_deg.to_radians();
    let r0 = 0.5 * b / (FRAC_PI_4 + phi / 2.0).cos();
    let r1 = r0 * (FRAC_PI_2 * phi.tan()).exp();
    let lateral = 0.5 * b + 2.0 * r1 * (FRAC_PI_4 - phi / 2.0).cos();
    // The fan's rays, by their angle β below the outward horizontal at the footing edge:
    // from 135° − φ/2 (active wedge side) down to 45° − φ/2 (passive wedge side).
    let (start, end) = (3.0 * FRAC_PI_4 - phi / 2.0, FRAC_PI_4 - phi / 2.0);
    let depth = (0..=10_000)
        .map(|i| {
            let beta = start + (end - start) * i as f64 / 10_000.0;
            r0 * ((start - beta) * phi.tan()).exp() * beta.sin()
        })
        .fold(0.0, f64::max);
    (lateral, depth)
}

fn scene(file: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(file);
    Scene::from_path(&path).unwrap_or_else(|e| panic!("{file}: {e}"))
}

fn check(name: &str, scene: Scene, phi_deg: f64, published_nc: f64) {
    // N_c from the formula, and the published value.
    let nc = prandtl_nc(phi_deg);
    assert!(
        (nc - published_nc).abs() < 1e-3,
        "N_c({phi_deg}°) = {nc}, published {published_nc}"
    );

    // The scene is the case described: associative, weightless, plane-strain fit.
    let spec = &scene.spec;
    let m = spec.material.single().unwrap();
    assert_eq!(m.friction_angle, Some(phi_deg));
    assert_eq!(m.dilatancy_angle.unwrap_or(m.friction_angle()), phi_deg);
    assert_eq!(m.cone_fit, Some(ConeFit::PlaneStrain));
    assert!(spec.gravity.is_none() && spec.traction.is_empty());
    assert!(spec.initial_stress.is_none());
    let footing = spec
        .boundary
        .iter()
        .find(|b| b.name.as_deref() == Some("footing"))
        .expect("a boundary named footing");
    assert_eq!(spec.output.reaction.as_deref(), Some("footing"));
    assert_eq!(footing.fix, Fix::Y, "smooth footing");
    let Selection::Box { corners } = footing.nodes else {
        panic!("the footing is a box");
    };
    assert_eq!(
        corners[0],
        [0.0, 0.0],
        "half footing from the symmetry axis"
    );
    assert_eq!(corners[1][1], 0.0, "footing on the surface");
    let b = 2.0 * corners[1][0];
    let speed = -footing.velocity[1];
    assert!(speed > 0.0, "the footing moves down");
    let MeshSpec::Rectangle {
        x, y, order, focus, ..
    } = &spec.mesh
    else {
        panic!("a rectangle mesh");
    };
    assert_eq!(*order, Order::P2);
    assert_eq!(
        *focus,
        Some([0.5 * b, 0.0]),
        "graded toward the footing edge"
    );
    assert_eq!((x[0], y[1]), (0.0, 0.0));
    let (length, height) = (x[1], -y[0]);

    // The boundaries stay clear of Prandtl's mechanism.
    let (lateral, depth) = prandtl_mechanism(phi_deg, b);
    assert!(
        length >= 1.25 * lateral && height >= 1.5 * depth,
        "L = {length}, H = {height} m against a mechanism {lateral:.3} m wide, {depth:.3} m deep"
    );

    let model = Model::from_scene(&scene).expect("model");
    let elements = model.mesh.triangles.len();
    assert!(elements <= 3000, "{elements} elements");
    assert!(
        model
            .mesh
            .nodes
            .iter()
            .any(|p| p[0] == 0.5 * b && p[1] == 0.0),
        "the footing edge is a node"
    );

    let out_dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("prandtl_strip_footing")
        .join(name);
    let start = Instant::now();
    let summary =
        run_scene(&scene, &RunOptions::new(out_dir)).unwrap_or_else(|e| panic!("{name}: {e}"));
    let seconds = start.elapsed().as_secs_f64();

    // F = 2 × the half model's reaction; the limit load is the force at the end.
    let force: Vec<f64> = summary
        .records
        .iter()
        .map(|r| 2.0 * r.reaction_force())
        .collect();
    let n = force.len();
    assert_eq!(n, spec.time.steps);
    let q_u = force[n - 1] / b;
    let nc_fe = q_u / m.cohesion();
    let error = nc_fe / nc - 1.0;
    let at_90 = force[n - 1 - n / 10];
    let plateau = (force[n - 1] - at_90) / force[n - 1];
    let peak = force.iter().copied().fold(f64::MIN, f64::max);
    let max_newton = summary
        .records
        .iter()
        .map(|r| r.max_newton_iterations)
        .max()
        .unwrap_or(0);
    let max_step_newton = summary
        .records
        .iter()
        .map(|r| r.newton_iterations)
        .max()
        .unwrap_or(0);
    let split_steps = summary.records.iter().filter(|r| r.substeps > 1).count();

    // The mechanism computed: where the final velocity exceeds 2% of the footing's.
    let velocity = model
        .assembly
        .dofs()
        .scatter(
            &summary.final_state.velocity_free,
            &summary.final_state.velocity_prescribed,
        )
        .expect("velocity");
    let moving = |k: usize| velocity[k][0].hypot(velocity[k][1]) > 0.02 * speed;
    let nodes = &model.mesh.nodes;
    let fe_lateral = (0..nodes.len())
        .filter(|&k| nodes[k][1] == 0.0 && velocity[k][1] > 0.02 * speed)
        .map(|k| nodes[k][0])
        .fold(0.0, f64::max);
    let fe_depth = (0..nodes.len())
        .filter(|&k| moving(k))
        .map(|k| -nodes[k][1])
        .fold(0.0, f64::max);

    println!(
        "{name}: phi = {phi_deg}°, N_c = {nc:.4} (published {published_nc}); computed \
         F/(b c) = {nc_fe:.4}, error {:+.2}%; {elements} P2 elements, {n} steps, Newton \
         iterations ≤ {max_newton} per solve (≤ {max_step_newton} per step, {split_steps} \
         steps split); force change over the last 10% of steps {:.3}%; mechanism: heave \
         to x = {fe_lateral:.2} m (Prandtl {lateral:.2}), moving to depth {fe_depth:.2} m \
         (Prandtl {depth:.2}) in a {length} × {height} m domain; {seconds:.1} s",
        100.0 * error,
        100.0 * plateau,
    );

    assert!(
        error.abs() < TOLERANCE,
        "{name}: F/(b c) = {nc_fe} against N_c = {nc}: error {:+.2}%",
        100.0 * error
    );
    assert!(
        plateau.abs() < PLATEAU,
        "{name}: the force still changes by {:.3}% over the last 10% of the steps",
        100.0 * plateau
    );
    assert!(
        peak <= force[n - 1] * (1.0 + 1e-3),
        "{name}: the force peaked at {peak} before the end ({})",
        force[n - 1]
    );
    assert!(
        fe_lateral < 0.9 * length && fe_depth < 0.9 * height,
        "{name}: the computed mechanism reaches the boundaries"
    );
}

#[test]
fn prandtl_strip_footing_phi20_p2() {
    check(
        "prandtl_strip_footing_phi20_p2",
        scene("prandtl_phi20.toml"),
        20.0,
        14.835,
    );
}

#[test]
fn prandtl_strip_footing_phi30_p2() {
    check(
        "prandtl_strip_footing_phi30_p2",
        scene("prandtl_phi30.toml"),
        30.0,
        30.140,
    );
}

#[test]
fn prandtl_mechanism_matches_the_textbook_extent() {
    // φ = 30°, b = 1: r₀ = b, the passive wedge reaches 0.5 + 2 · 2.4766 · cos 30° b.
    let (lateral, depth) = prandtl_mechanism(30.0, 1.0);
    assert!(
        (lateral - (0.5 + 2.0 * (FRAC_PI_2 * 30f64.to_radians().tan()).exp() * 0.75f64.sqrt()))
            .abs()
            < 1e-12
    );
    assert!((depth - 1.585).abs() < 1e-3, "{depth}");
    // φ = 0: Prandtl's N_c → π + 2.
    assert!((prandtl_nc(1e-6) - (PI + 2.0)).abs() < 1e-4);
}
