//! The error of a symbolic analysis (an ordering, METIS, the symbolic factorizations).

/// The pattern could not be analysed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("symbolic LU: {0}")]
pub struct SymbolicError(String);

impl SymbolicError {
    pub(crate) fn new(message: String) -> Self {
        Self(message)
    }
}
