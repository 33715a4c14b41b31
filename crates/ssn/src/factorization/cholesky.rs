//! Sparse Cholesky `P A Pᵀ = L Lᵀ` of the Newton matrix of an associative flow rule
//! (symmetric `K`), refactorized every iteration on the same pattern into reused storage.
//! In f64 it is our supernodal [`SymmetricPatternLlt`], parallel over the elimination
//! tree with the same factor on any thread count (`docs/performance.md`, 'The Cholesky on
//! two threads'); the f32 factor of the Krylov path (`docs/krylov.md`, 'A
//! single-precision factor') is faer's supernodal one, sequential.
use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use super::ordering::{symbolic_cholesky, Ordering, SymbolicError};
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
    /// Built by [`SupernodalCholesky::try_new_single`]: faer's symbolic analysis, the
    /// f32 factor, and an f64 one allocated by the first [`SupernodalCholesky::factorize`].
    Single(Box<FaerFactors>),
}

struct FaerFactors {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    factor_scratch: Option<MemBuffer>,
    solve_scratch: Option<MemBuffer>,
    factorized: bool,
    single: Single,
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
            .field("single", &matches!(self.storage, Storage::Single(_)))
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
            storage: Storage::Single(Box::new(FaerFactors {
                values: Vec::new(),
                symbolic,
                factor_scratch: None,
                solve_scratch: None,
                factorized: false,
                single,
            })),
        })
    }

    /// Stored entries of `L` (its supernodes' dense blocks).
    pub fn factor_nnz(&self) -> usize {
        match &self.storage {
            Storage::Double(llt) => llt.len_val(),
            Storage::Single(f) => f.symbolic.len_val(),
        }
    }

    /// Bytes of the stored factors (f64 and f32).
    pub fn factor_bytes(&self) -> usize {
        match &self.storage {
            Storage::Double(llt) => 8 * llt.len_val(),
            Storage::Single(f) => 8 * f.values.len() + 4 * f.single.values.len(),
        }
    }

    /// Factorizes, in f32, the matrix whose lower triangle is `lower` (rounded to f32).
    /// Only for a solver built by [`try_new_single`](Self::try_new_single).
    pub fn factorize_single(
        &mut self,
        lower: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), NotPositiveDefinite> {
        let Storage::Single(f) = &mut self.storage else {
            panic!("factorize_single on a solver built by try_new_single only");
        };
        let single = &mut f.single;
        single.factorized = false;
        for (s, v) in single.input.iter_mut().zip(lower.val()) {
            *s = *v as f32;
        }
        let lower32 = SparseColMatRef::new(lower.symbolic(), &single.input);
        f.symbolic
            .factorize_numeric_llt::<f32>(
                &mut single.values,
                lower32,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut single.factor_scratch),
                Default::default(),
            )
            .map_err(not_positive_definite)?;
        single.factorized = true;
        Ok(())
    }

    /// `rhs ← A⁻¹ rhs` with the f32 factor (the vector rounded to f32 and back).
    pub fn solve_in_place_single(&mut self, rhs: &mut [f64]) {
        let Storage::Single(f) = &mut self.storage else {
            panic!("solve_in_place_single on a solver built by try_new_single only");
        };
        let single = &mut f.single;
        assert!(
            single.factorized,
            "solve before a successful factorize_single"
        );
        let n = rhs.len();
        for (s, v) in single.work.iter_mut().zip(rhs.iter()) {
            *s = *v as f32;
        }
        LltRef::new(&f.symbolic, &single.values).solve_in_place_with_conj(
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
        let f = match &mut self.storage {
            Storage::Double(llt) => return llt.factorize(lower.val()),
            Storage::Single(f) => f,
        };
        f.factorized = false;
        if f.values.len() != f.symbolic.len_val() {
            f.values = vec![0.0; f.symbolic.len_val()];
        }
        let symbolic = &f.symbolic;
        let scratch = f.factor_scratch.get_or_insert_with(|| {
            MemBuffer::new(
                symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            )
        });
        f.symbolic
            .factorize_numeric_llt::<f64>(
                &mut f.values,
                lower,
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(scratch),
                Default::default(),
            )
            .map_err(not_positive_definite)?;
        f.factorized = true;
        Ok(())
    }

    /// Solves `A x = b` in place with the last successful factorization.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let f = match &mut self.storage {
            Storage::Double(llt) => return llt.solve_in_place(rhs),
            Storage::Single(f) => f,
        };
        assert!(f.factorized, "solve_in_place before a successful factorize");
        let n = rhs.len();
        let symbolic = &f.symbolic;
        let scratch = f.solve_scratch.get_or_insert_with(|| {
            MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq))
        });
        LltRef::new(&f.symbolic, &f.values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            Par::Seq,
            MemStack::new(scratch),
        );
    }
}

fn not_positive_definite(e: faer::linalg::solvers::LltError) -> NotPositiveDefinite {
    let faer::linalg::solvers::LltError::NonPositivePivot { index } = e;
    NotPositiveDefinite { column: index }
}
