//! `[analysis] kind = "quasi_static"` on the paper footing (`scenes/footing.toml`): its
//! plateau reaction is the dynamic run's once inertia is negligible, and it needs no time
//! step tuned for inertia. The same settlement per step (1e-5 m) in all three runs:
//!
//! - dynamic with a large h = 1 s (footing at 1e-5 m/s): its inertia, `M/h²`, is at most
//!   ~1e-9 of each node's elastic stiffness `K_jj` (measured below), below the
//!   quasi-static default `inertia_ratio` (1e-7), so it is the quasi-static reference;
//! - quasi-static with h = 1e-4 s (footing at 0.1 m/s);
//! - dynamic with the same h = 1e-4 s, which must differ: inertia is then ~1e-1 of the
//!   stiffness and the reaction oscillates about the plateau (the witness that the comparison can fail, e.g.
//!   if the quasi-static run kept the material's mass).
use talus::model::fem::ReactionForce;
use talus::model::fem::{FromScene, Model};
use talus::run::fem::solver_settings;
use talus::scene::{builtin_footing, Scene};
use talus_engine::{StepSettings, Stepper};

const STEPS: usize = 200;

fn footing(h: f64, velocity: f64, quasi_static: bool) -> Scene {
    let mut text = builtin_footing()
        .source
        .replace("step = 1.0e-2", &format!("step = {h:e}"))
        .replace(
            "velocity = [0.0, -1.0e-3]",
            &format!("velocity = [0.0, -{velocity:e}]"),
        );
    if quasi_static {
        text.push_str("\n[analysis]\nkind = \"quasi_static\"\n");
    }
    let scene = Scene::parse(&text, None).unwrap();
    assert_eq!(scene.spec.time.step, h);
    scene
}

/// The reaction (N/m) after each step, and the largest `m_j / (h² K_jj)` of the model.
fn reactions(scene: &Scene) -> (Vec<f64>, f64) {
    let model = Model::from_scene(scene).unwrap();
    let h = scene.spec.time.step;
    let (k_free, _) = model.quasi_static_masses(h, 1.0).expect("stiffness");
    let inertia = model
        .assembly
        .lumped_mass_free
        .iter()
        .zip(&k_free)
        .map(|(m, k)| m / k)
        .fold(0.0f64, f64::max);
    let mut state = model.initial_state(scene).unwrap();
    let mut stepper = Stepper::new(
        &model,
        StepSettings::with_solver(solver_settings(scene), scene.spec.solver.max_step_halvings),
    );
    let mut out = Vec::with_capacity(STEPS);
    let mut iterations = 0;
    for _ in 0..STEPS {
        let record = stepper.advance(&mut state, h).expect("step converges");
        iterations += record.newton_iterations;
        out.push(record.reaction_force());
    }
    println!("h = {h:e}: inertia ratio {inertia:.2e}, {iterations} Newton iterations");
    (out, inertia)
}

#[test]
fn quasi_static_plateau_equals_dynamic_with_a_large_step() {
    let (reference, inertia) = reactions(&footing(1.0, 1.0e-5, false));
    assert!(
        inertia < 1e-8,
        "the large h is not quasi-static: {inertia:.2e}"
    );
    let (quasi_static, ratio) = reactions(&footing(1.0e-4, 0.1, true));
    // The quasi-static masses are inertia_ratio · h² K_jj exactly.
    assert!(
        (ratio / talus::model::fem::DEFAULT_INERTIA_RATIO - 1.0).abs() < 1e-12,
        "{ratio:e}"
    );
    let (dynamic, small_h_inertia) = reactions(&footing(1.0e-4, 0.1, false));
    assert!(small_h_inertia > 1e-2, "{small_h_inertia:.2e}");

    // The plateau: from 1 mm of settlement (step 100) on, the reaction rises by < 0.1%.
    let plateau = 99..STEPS;
    let rise = reference[STEPS - 1] / reference[99] - 1.0;
    assert!((0.0..1e-3).contains(&rise), "not a plateau: {rise:.3e}");
    let largest = |run: &[f64]| {
        plateau
            .clone()
            .map(|k| (run[k] / reference[k] - 1.0).abs())
            .fold(0.0f64, f64::max)
    };
    let (worst, witness) = (largest(&quasi_static), largest(&dynamic));
    println!(
        "plateau {:.10e} N/m: quasi-static differs by at most {worst:.2e}, dynamic at \
         h = 1e-4 by up to {witness:.2e}",
        reference[STEPS - 1]
    );
    assert!(worst < 1e-4, "quasi-static against dynamic: {worst:.3e}");
    assert!(witness > 1e-3, "dynamic at small h: {witness:.3e}");
}
