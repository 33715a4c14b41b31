use crate::Report;

/// Why a solve did not give a solution.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// The data do not describe a solvable problem; nothing was computed.
    #[error("invalid {field}: {reason}")]
    InvalidInput { field: &'static str, reason: String },
    /// Newton stopped without converging; `σ` holds the last iterate, not a solution.
    #[error("semi-smooth Newton did not converge: {} after {} iterations, residual {:.3e}", .0.status, .0.iterations, .0.residual)]
    NotConverged(Box<Report>),
}

pub(crate) fn invalid(field: &'static str, reason: impl Into<String>) -> SolveError {
    SolveError::InvalidInput {
        field,
        reason: reason.into(),
    }
}
