/// How a solve ended. `Converged` and `RoundOffFloor` are accepted ([`Report::is_accepted`]);
/// only `Converged` met the tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// `‖F‖∞ ≤ tolerance · max(1, ‖σ‖∞)`.
    Converged,
    /// Above the tolerance, but stagnated within a factor of the estimated round-off floor
    /// of `F` (`docs/solver.md`, "The round-off floor"): the best σ floating point allows.
    /// [`Report::round_off_floor`] has the floor reached and the estimate.
    RoundOffFloor,
    /// `max_iterations` reached with the residual above tolerance.
    MaxIterations,
    /// The merit did not fall by [`Stall::decrease`](crate::Stall) over
    /// [`Stall::window`](crate::Stall) iterations, far above the round-off floor.
    Stalled,
    /// The merit stagnated while the Newton matrix had negative pivots
    /// ([`Fold`](crate::Fold)): the signature of a time step past its fold.
    Folded,
    /// No step length gave sufficient decrease of `‖F‖²`.
    LineSearchFailed,
    /// The Newton matrix was singular or its solve inaccurate.
    SingularJacobian,
    /// A NaN or infinity appeared in σ, z or F.
    NonFinite,
}

impl Status {
    /// `converged`, `max_iterations`, … (the CLI's JSON `status`).
    pub fn as_str(&self) -> &'static str {
        match self {
            Status::Converged => "converged",
            Status::RoundOffFloor => "round_off_floor",
            Status::MaxIterations => "max_iterations",
            Status::Stalled => "stalled",
            Status::Folded => "folded",
            Status::LineSearchFailed => "line_search_failed",
            Status::SingularJacobian => "singular_jacobian",
            Status::NonFinite => "non_finite",
        }
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Where a solve ended at its round-off floor, in the units of `Report::residual`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoundOffFloor {
    /// `‖F‖∞` at which the iteration stagnated (equal to `Report::residual`).
    pub reached: f64,
    /// `ε · max(‖σ‖∞, max_i ρ_i (|W||σ| + |q|)_i)` at the last iterate, with the stopping
    /// test's ρ_i: the rounding error of `F` there.
    pub estimate: f64,
}

/// What one solve did.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    pub status: Status,
    /// Newton steps taken.
    pub iterations: usize,
    /// Final `‖F‖∞`.
    pub residual: f64,
    /// `max(1, ‖σ‖∞)` at the end: the stopping test is `residual ≤ tolerance · scale`.
    pub scale: f64,
    /// `‖F‖∞` at the start and after every step.
    pub residual_history: Vec<f64>,
    /// `‖F_ρ‖₂` with the iteration's own ρ at the start and after every step: the map Newton
    /// linearizes, so the one on which to observe its order of convergence.
    pub merit_history: Vec<f64>,
    /// Wall time of the solve, in seconds.
    pub seconds: f64,
    /// Backtracks taken by the line search over the whole solve.
    pub backtracks: usize,
    /// Steps solved through the velocity-sized Schur complement.
    pub schur_steps: usize,
    /// Steps solved through the stress-sized system (including fallbacks).
    pub stress_sized_steps: usize,
    /// Schur steps whose no-pivot LU refused a pivot or gave an inaccurate direction, and
    /// were solved by the pivoting LU instead (`docs/solver.md`, "The factorization").
    pub pivoting_fallbacks: usize,
    /// Schur steps whose no-pivot LU gave an inaccurate direction although its velocity
    /// solve was backward stable: refused at once (the solve ends as `singular_jacobian`),
    /// since a pivoting LU gives the same (`docs/solver.md`, "The factorization").
    pub pivoting_skipped: usize,
    /// Negative pivots of each no-pivot LU factorization of the Newton matrix, in order
    /// (empty for Cholesky, pivoting and stress-sized steps): a converged non-associative
    /// step has none; a step past its fold shows them (`docs/solver.md`, 'Early signs of
    /// a fold').
    pub negative_pivots: Vec<usize>,
    /// Numeric factorizations of a Newton matrix (the velocity-sized one by Cholesky,
    /// no-pivot or pivoting LU, refused ones included; or the stress-sized `J_F`).
    pub factorizations: usize,
    /// Steps whose direction came from GMRES preconditioned by an earlier factorization
    /// ([`NewtonSolve::Krylov`](crate::NewtonSolve)): the reuses.
    pub krylov_solves: usize,
    /// GMRES iterations (solves with reused factors), failed attempts included.
    pub krylov_iterations: usize,
    /// GMRES attempts that missed their tolerance within the cap (or whose direction
    /// failed the accuracy check), after which `K` was refactorized.
    pub krylov_failures: usize,
    /// Smallest and largest ρ over the points.
    pub rho_range: (f64, f64),
    /// `Some` exactly when the status is `RoundOffFloor`.
    pub round_off_floor: Option<RoundOffFloor>,
}

impl Report {
    /// A report before any iteration.
    pub(crate) fn start(rho_range: (f64, f64)) -> Self {
        Self {
            status: Status::MaxIterations,
            iterations: 0,
            residual: f64::NAN,
            scale: 1.0,
            residual_history: Vec::new(),
            merit_history: Vec::new(),
            seconds: 0.0,
            backtracks: 0,
            schur_steps: 0,
            stress_sized_steps: 0,
            pivoting_fallbacks: 0,
            pivoting_skipped: 0,
            negative_pivots: Vec::new(),
            factorizations: 0,
            krylov_solves: 0,
            krylov_iterations: 0,
            krylov_failures: 0,
            rho_range,
            round_off_floor: None,
        }
    }

    /// The tolerance was met.
    pub fn is_converged(&self) -> bool {
        self.status == Status::Converged
    }

    /// σ is a solution to the tolerance or to the problem's round-off floor: a time step
    /// may be accepted (not halved).
    pub fn is_accepted(&self) -> bool {
        matches!(self.status, Status::Converged | Status::RoundOffFloor)
    }
}
