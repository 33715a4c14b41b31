//! Sparse Cholesky `P A Pᵀ = L Lᵀ` through faer's supernodal factorization, with the
//! factor's storage and both workspaces kept across factorizations: the Newton matrix of an
//! associative flow rule is refactorized every iteration on the same pattern, and faer's
//! `Llt` would allocate (and zero) the whole factor each time.
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use super::ordering::{symbolic_cholesky, Ordering};
use super::SymbolicError;

/// The matrix is not (numerically) positive definite.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("Cholesky: non-positive pivot at column {column}")]
pub struct NotPositiveDefinite {
    /// Column of the permuted matrix where the factorization stopped.
    pub column: usize,
}

/// Symbolic analysis (fill-reducing [`Ordering`], supernodes) once per pattern; numeric factorizations
/// into reused storage. Sequential: the factors do not depend on the thread count.
pub struct SupernodalCholesky {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    factor_scratch: MemBuffer,
    solve_scratch: MemBuffer,
    factorized: bool,
}

impl std::fmt::Debug for SupernodalCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SupernodalCholesky")
            .field("dimension", &self.symbolic.nrows())
            .field("factor_nnz", &self.values.len())
            .field("factorized", &self.factorized)
            .finish()
    }
}

impl SupernodalCholesky {
    /// Analyses the lower triangle `lower` of a symmetric pattern (AMD ordering).
    pub fn try_new(lower: SymbolicSparseColMatRef<'_, usize>) -> Result<Self, SymbolicError> {
        Self::try_new_with(lower, Ordering::Amd)
    }

    /// Analyses the lower triangle `lower` of a symmetric pattern under `ordering`.
    pub fn try_new_with(
        lower: SymbolicSparseColMatRef<'_, usize>,
        ordering: Ordering,
    ) -> Result<Self, SymbolicError> {
        let symbolic = symbolic_cholesky(lower, ordering, Default::default())?;
        let factor_scratch = MemBuffer::try_new(
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        )
        .map_err(|e| SymbolicError::new(format!("{e:?}")))?;
        let solve_scratch = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq))
            .map_err(|e| SymbolicError::new(format!("{e:?}")))?;
        Ok(Self {
            values: vec![0.0; symbolic.len_val()],
            symbolic,
            factor_scratch,
            solve_scratch,
            factorized: false,
        })
    }

    /// Stored entries of `L`.
    pub fn factor_nnz(&self) -> usize {
        self.values.len()
    }

    /// Factorizes the matrix whose lower triangle is `lower` (the analysed pattern).
    pub fn factorize(
        &mut self,
        lower: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), NotPositiveDefinite> {
        self.factorized = false;
        self.symbolic
            .factorize_numeric_llt::<f64>(
                &mut self.values,
                lower,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut self.factor_scratch),
                Default::default(),
            )
            .map_err(|e| {
                let faer::linalg::solvers::LltError::NonPositivePivot { index } = e;
                NotPositiveDefinite { column: index }
            })?;
        self.factorized = true;
        Ok(())
    }

    /// Solves `A x = b` in place with the last successful factorization.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        assert!(
            self.factorized,
            "solve_in_place before a successful factorize"
        );
        let n = rhs.len();
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            Par::Seq,
            MemStack::new(&mut self.solve_scratch),
        );
    }
}
