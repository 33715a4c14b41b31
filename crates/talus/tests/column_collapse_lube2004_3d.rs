//! Axisymmetric granular column collapse in 3D: the shipped scenes `scenes/column_3d.toml`
//! (a = 0.5) and `scenes/column_3d_a1.toml` (a = 1), quarter cylinders R₀ = 0.1 m of
//! cohesionless, non-dilatant Drucker-Prager sand (φ = 30°, plane-strain cone fit) on a
//! Coulomb floor μ = 0.6, against the experimental runout law of Lube, Huppert, Sparks &
//! Hallworth (2004), "Axisymmetric collapses of granular columns", J. Fluid Mech. 508,
//! 175–199: `(R∞ − R₀)/R₀ = 1.24 a` for `a < 1.7` (`1.6 √a` above), `a = H₀/R₀`.
//! Tolerance 15% (the issue's). Every step must converge: `advance` fails otherwise.
//!
//! The scenes' dx = R₀/5 runs out 16% short at both a (the runout grows with resolution,
//! docs/3d-mpm.md, 'The 3D column collapse against Lube et al. (2004)'), so the test runs
//! them refined to dx = R₀/7.5 over the same domain: 0.5674 (8.5% short, 1432 particles)
//! and 1.1545 (6.9% short, 2685 particles), as `talus run` at that spacing. About 5 and
//! 13 minutes of CPU (together 1050 s, 946 s wall on two threads), beyond the CI's budget:
//! ignored, run with
//! `cargo test --release -p talus --test suite column_collapse_lube2004_3d:: -- --ignored`.
//! At dx = R₀/5 the a = 0.5 test fails (0.5219, 15.8% short).
//! The front is the largest distance of a particle centre from the axis, as `history.csv`'s
//! `front`.
use crate::common;
use talus::model::mpm::MpmModel;

/// Cells per R₀ of the shipped scenes and of the run.
const SHIPPED_PER_R0: f64 = 5.0;
const PER_R0: f64 = 7.5;

/// `(R∞ − R₀)/R₀` at the scene's t_end, on its grid refined from R₀/5 to R₀/7.5 (the same
/// origin; the cell counts rounded up, so the domain is at least the scene's).
fn final_runout(name: &str) -> f64 {
    let mut scene = common::shipped_mpm_scene_3d(name);
    let refine = PER_R0 / SHIPPED_PER_R0;
    let grid = &mut scene.spec.grid;
    grid.spacing /= refine;
    grid.cells = grid.cells.map(|n| (n as f64 * refine).ceil() as usize);
    let model = MpmModel::from_scene_3d(&scene).unwrap_or_else(|e| panic!("{e}"));
    let time = scene.spec.time;
    let particles = common::mpm_run_to_end(
        &model,
        time.steps,
        time.step,
        scene.spec.solver.tolerance,
        name,
    );
    println!(
        "{name}: dx = {} m, {} particles, {} steps",
        scene.spec.grid.spacing,
        particles.len(),
        time.steps
    );
    model.runout.normalized(model.runout.front(&particles))
}

/// Lube et al. (2004)'s law for `a < 1.7`, within 15%.
fn check(a: f64, runout: f64) {
    let law = 1.24 * a;
    let error = runout / law - 1.0;
    println!(
        "a = {a}: (R∞ − R0)/R0 = {runout:.4}, Lube et al. {law:.3}, {:+.1}%",
        100.0 * error
    );
    assert!(
        error.abs() <= 0.15,
        "a = {a}: (R∞ − R0)/R0 = {runout:.4}, {:+.1}% from Lube et al.'s 1.24 a = {law:.3}",
        100.0 * error
    );
}

/// Lube et al.'s first regime (a < 0.74: the top stays undisturbed, a truncated cone).
/// About 5 minutes of CPU.
#[test]
#[ignore = "about 5 min of CPU: cargo test --release -p talus --test suite column_collapse_lube2004_3d:: -- --ignored"]
fn column_3d_a0_5_follows_the_linear_law() {
    check(0.5, final_runout("column_3d.toml"));
}

/// The second regime (0.74 < a < 1.7: the whole top moves, a cone). About 13 minutes of
/// CPU.
#[test]
#[ignore = "about 13 min of CPU: cargo test --release -p talus --test suite column_collapse_lube2004_3d:: -- --ignored"]
fn column_3d_a1_follows_the_linear_law() {
    check(1.0, final_runout("column_3d_a1.toml"));
}
