//! What a step did, and why one failed.
use talus_ssn::{SolveError, Status};

/// Where a sub-step's Newton iteration started.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Predictor {
    /// `σₙ + h σ̇`, the rate of the last accepted sub-step (smooth loading).
    Extrapolated,
    /// The elastic predictor: first step, right after a jump in the loading rate, or on
    /// every sub-step with [`PredictorRule::Elastic`](crate::PredictorRule::Elastic).
    Elastic,
    /// `σₙ`.
    Previous,
}

/// What one step did (all its sub-steps together). `S` is what the discretization
/// measured on the step's last sub-step.
#[derive(Debug, Clone, PartialEq)]
pub struct StepReport<S> {
    /// Time at the end of the step (s).
    pub time: f64,
    /// The step asked for (s).
    pub h: f64,
    /// Sub-steps taken: 1 unless a failed solve split the step, or the step started at a
    /// smaller sub-step size the step control kept (`StepControl`). A solve that ends at its
    /// round-off floor is accepted, not split (see `statuses`).
    pub substeps: usize,
    /// Smallest sub-step used (s).
    pub smallest_h: f64,
    /// Newton iterations of the accepted sub-steps (all their solves).
    pub newton_iterations: usize,
    /// The most Newton iterations of one accepted sub-step.
    pub max_newton_iterations: usize,
    /// Newton iterations of the attempts that failed and were redone as two half steps
    /// (not in `newton_iterations`).
    pub failed_newton_iterations: usize,
    /// Line-search backtracks of the accepted sub-steps.
    pub backtracks: usize,
    /// Iterations and backtracks of the accepted sub-steps' first solves.
    pub first_solve_iterations: usize,
    pub first_solve_backtracks: usize,
    /// Backtracks of the failed attempts.
    pub failed_backtracks: usize,
    /// Most solves one sub-step took (MPM: friction passes; 1 otherwise).
    pub solves_per_substep: usize,
    /// Later solves of a sub-step that kept the first one's Schur analysis.
    pub reused_analyses: usize,
    /// How each accepted sub-step's last solve ended.
    pub statuses: Vec<Status>,
    /// Where each accepted sub-step's Newton iteration started.
    pub predictors: Vec<Predictor>,
    /// Final `‖F‖∞` of the last sub-step, and the same over `max(1, ‖σ‖∞)`: the quantity
    /// compared with the tolerance.
    pub residual: f64,
    pub relative_residual: f64,
    /// `‖F‖∞ / max(1, ‖σ‖∞)` per iteration, per accepted sub-step's solve.
    pub residual_histories: Vec<Vec<f64>>,
    /// `‖F_ρ‖₂ / max(1, ‖σ‖∞)` with the iteration's ρ, per iteration, per solve.
    pub merit_histories: Vec<Vec<f64>>,
    /// What the discretization measured on the last sub-step.
    pub stats: Option<S>,
    /// Wall time of the step and of its Newton solves, failed ones included (s).
    pub seconds: f64,
    pub solve_seconds: f64,
}

impl<S> StepReport<S> {
    pub(crate) fn new(time: f64, h: f64) -> Self {
        Self {
            time,
            h,
            substeps: 0,
            smallest_h: h,
            newton_iterations: 0,
            max_newton_iterations: 0,
            failed_newton_iterations: 0,
            backtracks: 0,
            first_solve_iterations: 0,
            first_solve_backtracks: 0,
            failed_backtracks: 0,
            solves_per_substep: 0,
            reused_analyses: 0,
            statuses: Vec::new(),
            predictors: Vec::new(),
            residual: 0.0,
            relative_residual: 0.0,
            residual_histories: Vec::new(),
            merit_histories: Vec::new(),
            stats: None,
            seconds: 0.0,
            solve_seconds: 0.0,
        }
    }

    /// Newton iterations of the step, failed attempts included: its cost.
    pub fn total_newton_iterations(&self) -> usize {
        self.newton_iterations + self.failed_newton_iterations
    }
}

#[derive(Debug, thiserror::Error)]
pub enum StepError<E: std::error::Error + 'static> {
    #[error("step to t = {time:.6} s did not converge even with h = {h:e} s ({halvings} halvings): {report_status} after {iterations} Newton iterations, residual {residual:.3e}")]
    NotConverged {
        time: f64,
        h: f64,
        halvings: usize,
        report_status: Status,
        iterations: usize,
        /// `‖F‖∞ / max(1, ‖σ‖∞)` of the last attempt.
        residual: f64,
    },
    #[error("solver setup: {0}")]
    Solver(SolveError),
    #[error(transparent)]
    Discretization(E),
}
