//! Granular column collapse: the shipped scenes `scenes/column_a*.toml` (cohesionless,
//! non-dilatant Drucker-Prager, φ = 30°, on a Coulomb floor μ = 0.6) against the
//! experimental runout law of Lube, Huppert, Sparks & Freundt (2005), "Collapses of
//! two-dimensional granular columns", Phys. Rev. E 72, 041301:
//! `(L∞ − L₀)/L₀ = 1.2 a` for `a ≲ 1.8`, `1.9 a^(2/3)` for `a ≳ 2.8`, with `a = H₀/L₀`.
//! Tolerance 20% (the issue's). Every step must converge: `advance` fails otherwise.
//!
//! a = 2 lies between the two regimes, where the paper gives no law: it must fall within
//! 20% of the band between them, `[0.8 · 1.2a, 1.2 · 1.9a^(2/3)]`.
//! The front is the largest particle x (particle centres), as in `history.csv`.
use crate::common;
use std::path::Path;

use talus::model::mpm::MpmModel;
use talus::scene::MpmScene;
use talus_mpm::front;

fn final_runout(a: &str) -> f64 {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/column_a{a}.toml"));
    let scene = MpmScene::from_path(&path).unwrap_or_else(|e| panic!("{e}"));
    let model = MpmModel::from_scene(&scene).unwrap_or_else(|e| panic!("{e}"));
    let time = scene.spec.time;
    let name = format!("a = {a}");
    let particles = common::mpm_run_to_end(
        &model,
        time.steps,
        time.step,
        scene.spec.solver.tolerance,
        &name,
    );
    model.runout.normalized(front(&particles))
}

fn check(a: f64, runout: f64, low: f64, high: f64) {
    println!("a = {a}: runout {runout:.3}, accepted [{low:.3}, {high:.3}]");
    assert!(
        (low..=high).contains(&runout),
        "a = {a}: runout (L∞ − L0)/L0 = {runout:.3} outside [{low:.3}, {high:.3}]"
    );
}

#[test]
fn column_a0_5_follows_the_linear_law() {
    let r = final_runout("0.5");
    check(0.5, r, 0.8 * 1.2 * 0.5, 1.2 * 1.2 * 0.5);
}

#[test]
fn column_a1_follows_the_linear_law() {
    let r = final_runout("1");
    check(1.0, r, 0.8 * 1.2, 1.2 * 1.2);
}

#[test]
fn column_a2_lies_in_the_transition_band() {
    let r = final_runout("2");
    let a: f64 = 2.0;
    check(a, r, 0.8 * 1.2 * a, 1.2 * 1.9 * a.powf(2.0 / 3.0));
}

/// The slowest test of the suite (minutes): with h = 2e-3 s this column ran out 25% past
/// the law, with the scenes' h = 1e-3 s 17% (docs/mpm.md).
#[test]
fn column_a4_follows_the_two_thirds_law() {
    let r = final_runout("4");
    let a: f64 = 4.0;
    let law = 1.9 * a.powf(2.0 / 3.0);
    check(a, r, 0.8 * law, 1.2 * law);
}
