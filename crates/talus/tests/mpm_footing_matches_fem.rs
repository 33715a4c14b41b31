//! The paper's strip footing (Guillet et al. 2024, Fig. 3–4) by both discretizations on the
//! same solver core: the MPM force–displacement curve (`scenes/mpm_footing.toml`, 2048
//! particles, quadratic B-splines, dx = 1/16 m) stays within 10% of the FEM one
//! (`scenes/footing.toml`, 896 P2 triangles) at every 0.3 mm of settlement, plateau
//! included (the criterion at comparable resolution).
use std::path::Path;

use talus::model::fem::ReactionForce;
use talus::model::mpm::MpmModel;
use talus::run::fem::run_scene;
use talus::run::RunOptions;
use talus::scene::{builtin_footing, MpmScene};
use talus_engine::Stepper;
use talus_mpm::GroupForces;
use talus_mpm::MpmState;

#[test]
fn mpm_footing_follows_the_fem_footing_within_ten_percent() {
    let fem = run_scene(
        &builtin_footing(),
        &RunOptions::new(Path::new(env!("CARGO_TARGET_TMPDIR")).join("fem_footing_for_mpm")),
    )
    .expect("FEM footing converges");
    let fem_force: Vec<f64> = fem.records.iter().map(|r| r.reaction_force()).collect();

    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/mpm_footing.toml");
    let scene = MpmScene::from_path(&path).unwrap_or_else(|e| panic!("{e}"));
    let model = MpmModel::from_scene(&scene).unwrap_or_else(|e| panic!("{e}"));
    let mut stepper = Stepper::new(&model.mpm, model.step_settings);
    let mut state = MpmState {
        time: 0.0,
        particles: model.particles.clone(),
    };
    let group = model.reaction.expect("the scene reports the footing").group;
    let (h, steps) = (scene.spec.time.step, scene.spec.time.steps);
    assert_eq!(steps, fem_force.len(), "both scenes take the same steps");
    let mut worst: f64 = 0.0;
    for step in 1..=steps {
        let report = stepper
            .advance(&mut state, h)
            .unwrap_or_else(|e| panic!("MPM step {step}: {e}"));
        assert!(report.relative_residual <= scene.spec.solver.tolerance);
        if step % 30 == 0 {
            // Push on the soil, downward positive, as the FEM reaction.
            let mpm = -report.group_forces()[group][1];
            let fem = fem_force[step - 1];
            let error = (mpm - fem).abs() / fem;
            println!(
                "settlement {:.1} mm: MPM {:.1} kN/m, FEM {:.1} kN/m ({:+.1}%)",
                step as f64 * h,
                mpm / 1e3,
                fem / 1e3,
                100.0 * (mpm - fem) / fem
            );
            worst = worst.max(error);
        }
    }
    assert!(
        worst <= 0.10,
        "MPM and FEM footing forces differ by {:.1}%",
        100.0 * worst
    );
}
