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
    /// Empty until the first f64 factorization when built by [`try_new_single`](Self::try_new_single).
    values: Vec<f64>,
    factor_scratch: Option<MemBuffer>,
    solve_scratch: Option<MemBuffer>,
    factorized: bool,
    /// The factor stored in f32 (`docs/krylov.md`, 'A single-precision factor'): half the
    /// memory, a preconditioner only.
    single: Option<Single>,
}

/// The f32 factor, `K`'s values rounded to f32, scratch and a work vector.
struct Single {
    values: Vec<f32>,
    input: Vec<f32>,
    factor_scratch: MemBuffer,
    solve_scratch: MemBuffer,
    work: Vec<f32>,
    factorized: bool,
}

impl std::fmt::Debug for SupernodalCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SupernodalCholesky")
            .field("dimension", &self.symbolic.nrows())
            .field("factor_nnz", &self.factor_nnz())
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
            factor_scratch: Some(factor_scratch),
            solve_scratch: Some(solve_scratch),
            factorized: false,
            single: None,
        })
    }

    /// As [`try_new_with`](Self::try_new_with), for factorizations stored in f32
    /// ([`factorize_single`](Self::factorize_single)); the f64 storage is allocated only
    /// if [`factorize`](Self::factorize) is called.
    pub fn try_new_single(
        lower: SymbolicSparseColMatRef<'_, usize>,
        ordering: Ordering,
    ) -> Result<Self, SymbolicError> {
        let symbolic = symbolic_cholesky(lower, ordering, Default::default())?;
        let memory = |e| SymbolicError::new(format!("{e:?}"));
        let single = Single {
            values: vec![0.0; symbolic.len_val()],
            input: vec![0.0; lower.row_idx().len()],
            factor_scratch: MemBuffer::try_new(
                symbolic.factorize_numeric_llt_scratch::<f32>(Par::Seq, Default::default()),
            )
            .map_err(memory)?,
            solve_scratch: MemBuffer::try_new(symbolic.solve_in_place_scratch::<f32>(1, Par::Seq))
                .map_err(memory)?,
            work: vec![0.0; symbolic.nrows()],
            factorized: false,
        };
        Ok(Self {
            values: Vec::new(),
            symbolic,
            factor_scratch: None,
            solve_scratch: None,
            factorized: false,
            single: Some(single),
        })
    }

    /// Stored entries of `L`.
    pub fn factor_nnz(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Bytes of the stored factors (f64 and f32).
    pub fn factor_bytes(&self) -> usize {
        8 * self.values.len() + self.single.as_ref().map_or(0, |s| 4 * s.values.len())
    }

    /// Factorizes, in f32, the matrix whose lower triangle is `lower` (rounded to f32).
    /// Only for a solver built by [`try_new_single`](Self::try_new_single).
    pub fn factorize_single(
        &mut self,
        lower: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), NotPositiveDefinite> {
        let single = self
            .single
            .as_mut()
            .expect("factorize_single on a solver built by try_new_single");
        single.factorized = false;
        for (s, v) in single.input.iter_mut().zip(lower.val()) {
            *s = *v as f32;
        }
        let lower32 = SparseColMatRef::new(lower.symbolic(), &single.input);
        self.symbolic
            .factorize_numeric_llt::<f32>(
                &mut single.values,
                lower32,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut single.factor_scratch),
                Default::default(),
            )
            .map_err(|e| {
                let faer::linalg::solvers::LltError::NonPositivePivot { index } = e;
                NotPositiveDefinite { column: index }
            })?;
        single.factorized = true;
        Ok(())
    }

    /// `rhs ← A⁻¹ rhs` with the f32 factor (the vector rounded to f32 and back).
    pub fn solve_in_place_single(&mut self, rhs: &mut [f64]) {
        let single = self.single.as_mut().expect("built by try_new_single");
        assert!(
            single.factorized,
            "solve before a successful factorize_single"
        );
        let n = rhs.len();
        for (s, v) in single.work.iter_mut().zip(rhs.iter()) {
            *s = *v as f32;
        }
        LltRef::new(&self.symbolic, &single.values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut single.work, n, 1),
            Par::Seq,
            MemStack::new(&mut single.solve_scratch),
        );
        for (v, s) in rhs.iter_mut().zip(&single.work) {
            *v = *s as f64;
        }
    }

    /// Factorizes the matrix whose lower triangle is `lower` (the analysed pattern).
    pub fn factorize(
        &mut self,
        lower: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), NotPositiveDefinite> {
        self.factorized = false;
        if self.values.len() != self.symbolic.len_val() {
            self.values = vec![0.0; self.symbolic.len_val()];
        }
        let scratch = self.factor_scratch.get_or_insert_with(|| {
            MemBuffer::new(
                self.symbolic
                    .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            )
        });
        self.symbolic
            .factorize_numeric_llt::<f64>(
                &mut self.values,
                lower,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(scratch),
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
        let scratch = self.solve_scratch.get_or_insert_with(|| {
            MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq))
        });
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            Par::Seq,
            MemStack::new(scratch),
        );
    }
}
