//! FEM and MPM go through the one halving code of the engine (`talus_engine::Stepper`):
//! in each a step forced to fail at its full length is redone as two halves, and what the
//! halved step returns equals the two half steps taken one by one from the same state and
//! predictor, bit for bit (`docs/solver.md`, 'Time stepping').
#[path = "../../mpm/tests/sand_column/mod.rs"]
mod sand_column;

use talus::model::fem::{FromScene, Model};
use talus::run::fem::solver_settings;
use talus::scene::builtin_footing_with_cells;
use talus_engine::{Discretization, StepSettings, Stepper};
use talus_mpm::{MpmState, MpmStepper};

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The first step of `stepper` from `state` that is halved, checked against two half steps
/// taken by a fresh stepper (`fresh`) from the state before it, with the same stress rate.
fn first_halved_step_equals_two_half_steps<D: Discretization>(
    stepper: &mut Stepper<D>,
    fresh: impl Fn() -> Stepper<D>,
    mut state: D::State,
    h: f64,
    steps: usize,
    same: impl Fn(&D::State, &D::State) -> bool,
) {
    for step in 1..=steps {
        let before = state.clone();
        let rate = stepper.stress_rate().map(<[f64]>::to_vec);
        let report = stepper
            .advance(&mut state, h)
            .expect("converges when halved");
        if report.substeps == 1 {
            continue;
        }
        assert_eq!(report.substeps, 2, "step {step}: one halving");
        assert!(
            report.failed_newton_iterations > 0,
            "the failed attempt is counted"
        );
        let mut by_hand = fresh();
        by_hand.set_stress_rate(rate);
        let mut manual = before;
        for _ in 0..2 {
            let r = by_hand.advance(&mut manual, 0.5 * h).expect("half step");
            assert_eq!(r.substeps, 1, "step {step}: a half step converges");
        }
        assert!(
            same(&state, &manual),
            "step {step}: halved step differs from two half steps"
        );
        return;
    }
    panic!("no step was halved in {steps} steps: the test needs one");
}

#[test]
fn fem_footing_halves_through_the_engine() {
    let mut scene = builtin_footing_with_cells([32, 14]);
    let h = scene.spec.time.step;
    let model = Model::from_scene(&scene).expect("model");
    let mut state = model.initial_state(&scene).expect("state");
    let defaults = StepSettings::with_solver(solver_settings(&scene), 1);
    // The first step k whose full-h solve takes more iterations than either of its two
    // halves (`n` against fewer), found at the default settings; `max_iterations = n − 1`
    // then forces exactly one halving there, whatever round-off does to the counts.
    let mut stepper = Stepper::new(&model, defaults);
    let (before, rate, full) = (1..=10)
        .find_map(|_| {
            let before = state.clone();
            let rate = stepper.stress_rate().map(<[f64]>::to_vec);
            let mut halves = Stepper::new(&model, defaults);
            halves.set_stress_rate(rate.clone());
            let mut s = before.clone();
            let half_its = (0..2)
                .map(|_| halves.advance(&mut s, 0.5 * h).expect("half step"))
                .map(|r| r.max_newton_iterations)
                .max()
                .expect("two halves");
            let r = stepper.advance(&mut state, h).expect("full step");
            (r.substeps == 1 && r.max_newton_iterations > half_its).then_some((
                before,
                rate,
                r.max_newton_iterations,
            ))
        })
        .expect("a step of the first 10 whose halves take fewer iterations");
    scene.spec.solver.max_iterations = full - 1;
    let settings = StepSettings::with_solver(solver_settings(&scene), 1);
    let mut stepper = Stepper::new(&model, settings);
    stepper.set_stress_rate(rate);
    first_halved_step_equals_two_half_steps(
        &mut stepper,
        || Stepper::new(&model, settings),
        before,
        h,
        1,
        |a, b| {
            bits(&a.sigma) == bits(&b.sigma)
                && bits(&a.velocity_free) == bits(&b.velocity_free)
                && a.time == b.time
        },
    );
}

#[test]
fn mpm_column_halves_through_the_engine() {
    let (mpm, particles) = sand_column::small_column();
    // The column of `crates/mpm/tests/step_control.rs`: its first step from rest takes 42 iterations
    // at h = 1/60 s and 26 at h/2; one halving allowed.
    let mut settings = StepSettings {
        max_halvings: 1,
        ..StepSettings::mpm()
    };
    settings.solver.max_iterations = 34;
    let state = MpmState {
        time: 0.0,
        particles,
    };
    let mut stepper = Stepper::new(&mpm, settings);
    first_halved_step_equals_two_half_steps(
        &mut stepper,
        || Stepper::new(&mpm, settings),
        state,
        1.0 / 60.0,
        3,
        |a, b| a == b,
    );
    // The convenience stepper is the same engine.
    let _ = MpmStepper::with_settings(mpm.clone(), settings);
}
