use talus_ssn::SolveError;

/// Why an MPM step could not be taken. The particles are left as they were.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MpmError {
    /// A bad input, naming the field and the value.
    #[error("invalid {field}: {reason}")]
    Invalid { field: String, reason: String },
    /// A particle's shape-function support left the grid (with its ghost layers).
    #[error("particle {particle} at ({}) m left the grid; enlarge the grid or add a wall", coordinates(.position))]
    ParticleLeftGrid {
        particle: usize,
        /// Its coordinates, 2 or 3 (m).
        position: Vec<f64>,
    },
    /// A particle's volume would become ≤ 0 (`det(I + h ∇v) ≤ 0`): the step is too large
    /// for the deformation.
    #[error(
        "particle {particle} would invert (det(I + h ∇v) = {jacobian:.3e}) in a step of {h:e} s"
    )]
    Inverted {
        particle: usize,
        jacobian: f64,
        h: f64,
    },
    /// The solver refused the reduced problem.
    #[error("solver: {0}")]
    Solver(SolveError),
}

impl MpmError {
    pub(crate) fn invalid(field: impl Into<String>, reason: impl Into<String>) -> Self {
        MpmError::Invalid {
            field: field.into(),
            reason: reason.into(),
        }
    }
}

/// `x, y[, z]` to 6 decimals.
fn coordinates(x: &[f64]) -> String {
    x.iter()
        .map(|v| format!("{v:.6}"))
        .collect::<Vec<_>>()
        .join(", ")
}
