//! The a = 2 column matched to Newton's implicit MPM (issue 24, item 4):
//! `scenes/column_newton.toml` (h = 1/60 s) and its accuracy reference
//! `scenes/column_newton_fine.toml` (h = 1e-3 s) load as the issue specifies them: 4050
//! particles of 0.2 × 0.4 m against a slip wall at x = 0 on a Coulomb floor μ = 0.5, Newton's
//! cone (tan φ = 0.5, k_d = √2, ψ = 0, c = 0), ρ = 1500, E = 1e7, quadratic B-splines with
//! dx = 0.2/15, FLIP 0.95, 1 s of collapse; the grid reaches past the runout both codes
//! measured. Then two steps at h = 1/60 s from rest, which must converge.
use std::path::Path;

use talus::model::mpm::MpmModel;
use talus::scene::MpmScene;
use talus_bipotential::Material;
use talus_engine::Stepper;
use talus_mpm::{front, MpmState, ShapeFunction, Side, WallCondition};

fn model(name: &str) -> (MpmScene, MpmModel) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/{name}.toml"));
    let scene = MpmScene::from_path(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    let model = MpmModel::from_scene(&scene).unwrap_or_else(|e| panic!("{name}: {e}"));
    (scene, model)
}

fn check_matched_physics(name: &str, step: f64, steps: usize) {
    let (scene, model) = model(name);
    let mpm = &*model.mpm;
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);

    // 15 × 30 cells of 3 × 3 particles, each of ρ dx² / 9.
    let particles = &model.particles;
    assert_eq!(particles.len(), 4050, "{name}: particle count");
    let dx = 0.2 / 15.0;
    assert!(close(mpm.grid().spacing(), dx), "{name}: dx");
    assert_eq!(mpm.grid().shape(), ShapeFunction::QuadraticBSpline);
    let mass: f64 = particles.mass.iter().sum();
    assert!(close(mass, 1500.0 * 0.2 * 0.4), "{name}: mass {mass}");
    let (x_max, y_max) = particles
        .position
        .iter()
        .fold((0.0f64, 0.0f64), |(a, b), x| (a.max(x[0]), b.max(x[1])));
    assert!(x_max < 0.2 && x_max > 0.2 - dx / 3.0, "{name}: width");
    assert!(y_max < 0.4 && y_max > 0.4 - dx / 3.0, "{name}: height");

    // Newton's cone: tan φ = 0.5, k_d = √2, ψ = 0, c = 0; E = 1e7 Pa.
    let [Material::DruckerPrager(sand)] = mpm.materials() else {
        panic!("{name}: one Drucker-Prager material expected");
    };
    let p = sand.parameters();
    assert!(
        close(sand.k_d(), std::f64::consts::SQRT_2),
        "{name}: k_d = {}",
        sand.k_d()
    );
    assert!(
        close(p.friction_angle.to_radians().tan(), 0.5),
        "{name}: tan φ = {}",
        p.friction_angle.to_radians().tan()
    );
    assert_eq!(p.dilatancy_angle, 0.0, "{name}: ψ");
    assert_eq!(p.cohesion, 0.0, "{name}: c");
    assert_eq!(p.young_modulus, 1e7, "{name}: E");

    // Slip wall at x = 0, Coulomb floor μ = 0.5, nothing else.
    let walls = &mpm.boundary().walls;
    assert_eq!(walls.len(), 2, "{name}: walls");
    assert!(walls
        .iter()
        .any(|w| w.side == Side::Left && w.condition == WallCondition::Slip));
    assert!(walls
        .iter()
        .any(|w| w.side == Side::Bottom
            && w.condition == WallCondition::Friction { coefficient: 0.5 }));
    assert_eq!(mpm.grid().origin(), [0.0, 0.0]);

    // FLIP 0.95, the step and 1 s of collapse.
    assert_eq!(mpm.settings().flip_ratio, 0.95, "{name}: FLIP");
    assert!(close(scene.spec.time.step, step), "{name}: h");
    assert_eq!(scene.spec.time.steps, steps, "{name}: steps");

    // The grid holds the runout the two codes measured ((L − L0)/L0 = 3.26 and 3.45) with
    // room to spare: 1.6 × 3.5 L0 + L0.
    assert!(
        mpm.grid().end()[0] >= 1.6 * 3.5 * 0.2 + 0.2 - 1e-9,
        "{name}: grid length"
    );
}

#[test]
fn the_matched_column_is_the_issues() {
    check_matched_physics("column_newton", 1.0 / 60.0, 60);
}

#[test]
fn the_accuracy_reference_differs_only_by_its_step() {
    check_matched_physics("column_newton_fine", 1e-3, 1000);
    let read = |name: &str| {
        std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/{name}.toml")),
        )
        .unwrap()
    };
    // Same keys outside [time] and the title: same physics.
    let strip = |text: String| -> Vec<String> {
        let mut table = String::new();
        text.lines()
            .filter_map(|l| {
                let l = l.split('#').next().unwrap().trim().to_string();
                if l.starts_with('[') {
                    table = l.clone();
                }
                (!l.is_empty() && table != "[time]" && !l.starts_with("title")).then_some(l)
            })
            .collect()
    };
    assert_eq!(
        strip(read("column_newton")),
        strip(read("column_newton_fine"))
    );
}

/// The first two steps at h = 1/60 s from rest converge (halvings allowed) and the column
/// starts to spread.
#[test]
fn the_matched_column_takes_its_first_steps() {
    let (scene, model) = model("column_newton");
    let mut stepper = Stepper::new(&model.mpm, model.step_settings);
    let mut state = MpmState {
        time: 0.0,
        particles: model.particles.clone(),
    };
    let h = scene.spec.time.step;
    let start = front(&state.particles);
    for step in 0..2 {
        let report = stepper
            .advance(&mut state, h)
            .unwrap_or_else(|e| panic!("step {step}: {e}"));
        assert!(report.relative_residual <= scene.spec.solver.tolerance);
    }
    assert!((state.time - 2.0 * h).abs() < 1e-12);
    assert!(front(&state.particles) > start, "the column spreads");
}
