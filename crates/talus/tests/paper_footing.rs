//! The strip footing of Guillet et al. (2024), Fig. 3–4 (`scenes/footing.toml`): every one
//! of the 300 steps converges to the solver tolerance (1e-12 relative) in at most 6 Newton
//! iterations (the paper reports at most 5), and the force reaches a plateau, where the
//! parabolic predictor leaves most steps one Newton iteration (`docs/solver.md`, 'The
//! parabolic predictor').
use talus::model::fem::ReactionForce;
use talus::run::fem::run_scene;
use talus::run::RunOptions;
use talus::scene::builtin_footing;

#[test]
fn paper_footing_converges_in_at_most_six_iterations_and_plateaus() {
    let scene = builtin_footing();
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("paper_footing");
    let summary = run_scene(&scene, &RunOptions::new(out))
        .expect("every step converges (a failed step is an error)");
    assert_eq!(summary.records.len(), 300);
    let worst = summary
        .records
        .iter()
        .map(|r| r.max_newton_iterations)
        .max()
        .unwrap();
    assert!(worst <= 6, "worst step took {worst} Newton iterations");
    assert!(
        summary.records.iter().all(|r| r.substeps == 1),
        "no step needed a smaller h"
    );
    let force: Vec<f64> = summary.records.iter().map(|r| r.reaction_force()).collect();
    // The K0 state carries the 20 kPa surcharge on the 0.5 m footing: 10 kN/m at rest;
    // the plateau is an order of magnitude above, and flat over the last half of the run.
    let plateau = force[299];
    assert!(plateau > 10.0 * 1.0e4, "plateau {plateau:e} N/m");
    let (lo, hi) = force[150..]
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), f| (a.min(*f), b.max(*f)));
    assert!(
        (hi - lo) / plateau < 0.01,
        "force varies by {:.3}% after step 150",
        100.0 * (hi - lo) / plateau
    );
    // Elastic start: the first steps are far below the plateau.
    assert!(force[0] < 0.25 * plateau);
    // On the plateau the line predictor needed 2.05 iterations a step (410 over steps
    // 101–300, measured 2026-11-28), the parabola 1.25: one iteration for most steps.
    let plateau_iterations: usize = summary.records[100..]
        .iter()
        .map(|r| r.newton_iterations)
        .sum();
    assert!(
        plateau_iterations <= 300,
        "{plateau_iterations} Newton iterations over steps 101–300"
    );
    // Displacement grows linearly with the prescribed velocity (1 mm/s, downward positive).
    assert!((summary.displacements[299] - 3.0e-3).abs() < 1e-12);
}
