//! The no-pivot LU of the Schur system (`docs/solver.md`, "The factorization") against
//! faer's partial-pivoting LU on the Newton systems of the paper footing (Guillet et al.
//! 2024, Fig. 3; `scenes/footing.toml`): one Newton step from the same state, early in the
//! loading and on the force plateau, for the paper's non-associative soil and an
//! associative one, gives the same iterate and the same residual.
use crate::common;

use common::footing::{footing, paper_footing, soil, H};
use talus_engine::{StepSettings, Stepper};
use talus_fem::{Model, State};
use talus_ssn::{LinearSolver, Report, Settings, SolveError, Solver};

/// The state after `steps` steps from `state`.
fn state_after(model: &Model, mut state: State, steps: usize) -> State {
    let mut stepper = Stepper::new(model, StepSettings::fem());
    for _ in 0..steps {
        stepper.advance(&mut state, H).expect("step converges");
    }
    state
}

/// One full Newton step (no line search) from σₙ with the given linear solver.
fn one_newton_step(model: &Model, state: &State, h: f64, ls: LinearSolver) -> (Vec<f64>, Report) {
    let settings = Settings {
        max_iterations: 1,
        line_search: None,
        linear_solver: ls,
        ..Settings::fem()
    };
    let mut solver = Solver::new(model.reduced_system(h).unwrap(), settings).unwrap();
    solver.set_q(model.reduced_rhs(state, h)).unwrap();
    let mut sigma = state.sigma.clone();
    let report = match solver.solve(&mut sigma) {
        Ok(r) => r,
        Err(SolveError::NotConverged(r)) => *r,
        Err(e) => panic!("{e}"),
    };
    (sigma, report)
}

fn check((model, state): (Model, State), steps: usize, label: &str) {
    let state = state_after(&model, state, steps);
    let h = H;
    let (a, ra) = one_newton_step(&model, &state, h, LinearSolver::Auto);
    let (b, rb) = one_newton_step(&model, &state, h, LinearSolver::SchurPivoting);
    assert_eq!(ra.schur_steps, 1, "{label}: the Schur path was taken");
    assert_eq!(
        ra.pivoting_fallbacks, 0,
        "{label}: the no-pivot LU needed no fallback"
    );
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .zip(&b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(
        diff <= 1e-10 * scale,
        "{label}: iterates differ by {diff:e} (‖σ‖∞ = {scale:e})"
    );
    let (fa, fb) = (ra.residual, rb.residual);
    assert!(
        (fa - fb).abs() <= 1e-6 * fb.max(1e-12 * scale),
        "{label}: residual after the step {fa:e} (no pivoting) vs {fb:e} (pivoting)"
    );
}

fn associative() -> (Model, State) {
    footing([32, 14], soil(27.0))
}

#[test]
fn no_pivot_lu_step_equals_pivoting_lu_step_early_non_associative() {
    check(paper_footing([32, 14]), 3, "non-associative, step 4");
}

#[test]
fn no_pivot_lu_step_equals_pivoting_lu_step_on_the_plateau_non_associative() {
    check(paper_footing([32, 14]), 100, "non-associative, step 101");
}

#[test]
fn cholesky_step_equals_pivoting_lu_step_associative() {
    check(associative(), 3, "associative, step 4");
    check(associative(), 100, "associative, step 101");
}

/// A guard that refuses every pivot smaller than its diagonal (`pivot_tolerance = 1`: the
/// Schur complements of these matrices shrink their diagonals, so some pivot always is)
/// sends each iteration to the pivoting LU; the report counts it and the answer is the
/// pivoting LU's.
#[test]
fn a_refused_pivot_falls_back_to_the_pivoting_lu_and_is_reported() {
    let (model, state) = paper_footing([32, 14]);
    let state = state_after(&model, state, 3);
    let h = H;
    let settings = Settings {
        max_iterations: 1,
        line_search: None,
        pivot_tolerance: 1.0,
        ..Settings::fem()
    };
    let mut solver = Solver::new(model.reduced_system(h).unwrap(), settings).unwrap();
    solver.set_q(model.reduced_rhs(&state, h)).unwrap();
    let mut sigma = state.sigma.clone();
    let report = match solver.solve(&mut sigma) {
        Err(SolveError::NotConverged(r)) => *r,
        other => panic!("one iteration cannot converge: {other:?}"),
    };
    assert_eq!(report.pivoting_fallbacks, 1);
    assert_eq!(report.schur_steps, 1);
    let (b, _) = one_newton_step(&model, &state, h, LinearSolver::SchurPivoting);
    assert_eq!(sigma, b, "the fallback is exactly the pivoting LU");
}
