/// How a solve ended. Only `Converged` is a solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    Converged,
    /// `max_iterations` reached with the residual above tolerance.
    MaxIterations,
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
            Status::MaxIterations => "max_iterations",
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
    /// Smallest and largest ρ over the points.
    pub rho_range: (f64, f64),
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
            rho_range,
        }
    }

    pub fn is_converged(&self) -> bool {
        self.status == Status::Converged
    }
}
