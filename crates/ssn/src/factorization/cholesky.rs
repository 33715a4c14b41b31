//! Sparse Cholesky `P A Pᵀ = L Lᵀ` of the Newton matrix of an associative flow rule
//! (symmetric `K`), refactorized every iteration on the same pattern into reused storage:
//! our supernodal [`SymmetricPatternLlt`], parallel over the elimination tree with the
//! same factor on any thread count (`docs/performance.md`, 'The Cholesky on two
//! threads'), in f64, or in f32 for the Krylov path's preconditioner (`docs/krylov.md`,
//! 'A single-precision factor').
use std::sync::Arc;

use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

use super::ordering::{Ordering, SymbolicError};
use super::supernodal_llt::{NotPositiveDefinite, SymmetricPatternLlt};
use super::symmetric_pattern_lu::SymbolicSymmetricPatternLu;

/// Symbolic analysis (fill-reducing [`Ordering`], supernodes) once per pattern; numeric
/// factorizations into reused storage. The factors do not depend on the thread count.
pub struct SupernodalCholesky {
    storage: Storage,
}

enum Storage {
    /// Built by [`SupernodalCholesky::try_new_with`].
    Double(SymmetricPatternLlt),
    /// Built by [`SupernodalCholesky::try_new_single`]: the f32 factor, and an f64 one on
    /// the same analysis allocated by the first [`SupernodalCholesky::factorize`].
    Single {
        single: SymmetricPatternLlt<f32>,
        double: Option<SymmetricPatternLlt>,
    },
}

impl std::fmt::Debug for SupernodalCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SupernodalCholesky")
            .field("single", &matches!(self.storage, Storage::Single { .. }))
            .field("factor_nnz", &self.factor_nnz())
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
        let symbolic = SymbolicSymmetricPatternLu::try_new_with(lower, ordering)?;
        Ok(Self {
            storage: Storage::Double(SymmetricPatternLlt::new(Arc::new(symbolic))),
        })
    }

    /// As [`try_new_with`](Self::try_new_with), for factorizations stored in f32
    /// ([`factorize_single`](Self::factorize_single)); the f64 storage is allocated only
    /// if [`factorize`](Self::factorize) is called.
    pub fn try_new_single(
        lower: SymbolicSparseColMatRef<'_, usize>,
        ordering: Ordering,
    ) -> Result<Self, SymbolicError> {
        let symbolic = SymbolicSymmetricPatternLu::try_new_with(lower, ordering)?;
        Ok(Self {
            storage: Storage::Single {
                single: SymmetricPatternLlt::new(Arc::new(symbolic)),
                double: None,
            },
        })
    }

    /// Stored entries of `L` (its supernodes' dense blocks).
    pub fn factor_nnz(&self) -> usize {
        match &self.storage {
            Storage::Double(llt) => llt.len_val(),
            Storage::Single { single, .. } => single.len_val(),
        }
    }

    /// Bytes of the stored factors (f64 and f32).
    pub fn factor_bytes(&self) -> usize {
        match &self.storage {
            Storage::Double(llt) => 8 * llt.len_val(),
            Storage::Single { single, double } => {
                4 * single.len_val() + double.as_ref().map_or(0, |d| 8 * d.len_val())
            }
        }
    }

    /// Factorizes, in f32, the matrix whose lower triangle is `lower` (rounded to f32).
    /// Only for a solver built by [`try_new_single`](Self::try_new_single).
    pub fn factorize_single(
        &mut self,
        lower: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), NotPositiveDefinite> {
        let Storage::Single { single, .. } = &mut self.storage else {
            panic!("factorize_single on a solver built by try_new_single only");
        };
        single.factorize(lower.val())
    }

    /// `rhs ← A⁻¹ rhs` with the f32 factor (the vector rounded to f32 and back).
    pub fn solve_in_place_single(&mut self, rhs: &mut [f64]) {
        let Storage::Single { single, .. } = &mut self.storage else {
            panic!("solve_in_place_single on a solver built by try_new_single only");
        };
        single.solve_in_place(rhs);
    }

    /// Factorizes the matrix whose lower triangle is `lower` (the analysed pattern).
    pub fn factorize(
        &mut self,
        lower: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), NotPositiveDefinite> {
        match &mut self.storage {
            Storage::Double(llt) => llt.factorize(lower.val()),
            Storage::Single { single, double } => double
                .get_or_insert_with(|| SymmetricPatternLlt::new(Arc::clone(single.symbolic())))
                .factorize(lower.val()),
        }
    }

    /// Solves `A x = b` in place with the last successful factorization.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        match &mut self.storage {
            Storage::Double(llt) => llt.solve_in_place(rhs),
            Storage::Single { double, .. } => double
                .as_mut()
                .expect("solve_in_place before a successful factorize")
                .solve_in_place(rhs),
        }
    }
}
