//! The factorization of the velocity-sized Newton matrix `K = M + h² Σ Bᵢᵀ Cᵢ Bᵢ`
//! (`docs/solver.md`, "The factorization"): Cholesky when `K` is symmetric (associative
//! flow), otherwise the no-pivot LU on the Cholesky structure of K's symmetric pattern, with
//! faer's partial-pivoting LU as the guarded fallback for one iteration.
use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuSymbolicParams, NumericLu, SymbolicLu};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par};

use crate::factorization::{
    Ordering, SupernodalCholesky, SymbolicSymmetricPatternLu, SymmetricPatternLu,
};

/// Which factorization solved this iteration's system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Factorized {
    Cholesky,
    /// With the number of negative pivots (`SymmetricPatternLu::negative_pivots`).
    NoPivotLu(usize),
    /// The pivoting LU, because the no-pivot LU refused a pivot or its direction failed
    /// the accuracy check.
    PivotingLu,
    /// MUMPS over the MPI ranks (`LinearSolver::Distributed`), with its negative pivots
    /// (`DistributedFactor::factorize`).
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    Distributed(usize),
    /// No factorization: GMRES preconditioned by the last one, in `iterations`.
    Reused {
        iterations: usize,
    },
}

/// Which LU a non-symmetric `K` is factorized by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum LuChoice {
    /// The no-pivot LU, refusing `|u_jj| ≤ tolerance · |k_jj|` (then the pivoting LU).
    NoPivot { pivot_tolerance: f64 },
    /// The pivoting LU directly (a retry, or `LinearSolver::SchurPivoting`).
    Pivoting,
}

/// faer's supernodal LU with partial pivoting: built on first use only.
pub(crate) struct PivotingLu {
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    scratch: MemBuffer,
}

impl PivotingLu {
    fn new(pattern: SymbolicSparseColMatRef<'_, usize>) -> Result<Self, String> {
        let symbolic = factorize_symbolic_lu(
            pattern,
            LuSymbolicParams {
                // faer's default picks the simplicial LU for these 2D patterns, several times
                // slower.
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .map_err(|e| format!("{e:?}"))?;
        let req = symbolic
            .factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        Ok(Self {
            symbolic,
            numeric: NumericLu::new(),
            scratch: MemBuffer::try_new(req).map_err(|e| format!("{e:?}"))?,
        })
    }

    fn solve(&mut self, k: SparseColMatRef<'_, usize, f64>, rhs: &mut [f64]) -> Result<(), String> {
        let stack = MemStack::new(&mut self.scratch);
        let lu = self
            .symbolic
            .factorize_numeric_lu(&mut self.numeric, k, Par::Seq, stack, Default::default())
            .map_err(|e| format!("{e:?}"))?;
        let n = rhs.len();
        lu.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            Par::Seq,
            stack,
        );
        Ok(())
    }
}

// One per solver, never moved in a hot loop: its size does not matter.
#[allow(clippy::large_enum_variant)]
pub(crate) enum SchurFactor {
    /// Associative: `ρ A⁻¹ D` is symmetric positive semi-definite, K is SPD.
    Cholesky {
        cholesky: SupernodalCholesky,
        /// The last factorization succeeded: it can precondition a later `K`.
        ready: bool,
        /// Factorizations stored in f32 (`Precision::Single`); `ready` is then the f32
        /// factor's.
        single: bool,
    },
    Lu {
        no_pivot: SymmetricPatternLu,
        pivoting: Option<PivotingLu>,
        /// The no-pivot LU holds the last factorization (not the pivoting fallback).
        ready: bool,
    },
    #[cfg(feature = "mpi")]
    Distributed(super::distributed_factor::DistributedFactor),
}

impl SchurFactor {
    /// The symbolic analysis of `pattern` (the lower triangle only when `symmetric`).
    pub(crate) fn analyse(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        symmetric: bool,
        ordering: Ordering,
        single: bool,
    ) -> Result<Self, String> {
        Ok(if symmetric {
            let cholesky = if single {
                SupernodalCholesky::try_new_single(pattern, ordering)
            } else {
                SupernodalCholesky::try_new_with(pattern, ordering)
            };
            SchurFactor::Cholesky {
                cholesky: cholesky.map_err(|e| e.to_string())?,
                ready: false,
                single,
            }
        } else {
            let symbolic = SymbolicSymmetricPatternLu::try_new_with(pattern, ordering)
                .map_err(|e| e.to_string())?;
            SchurFactor::Lu {
                no_pivot: SymmetricPatternLu::new(Arc::new(symbolic)),
                pivoting: None,
                ready: false,
            }
        })
    }

    /// This rank and the number of ranks of a distributed factorization.
    #[cfg(feature = "mpi")]
    pub(crate) fn world() -> Result<(usize, usize), String> {
        super::distributed_factor::world()
    }

    #[cfg(not(feature = "mpi"))]
    pub(crate) fn world() -> Result<(usize, usize), String> {
        Err("the distributed factorization needs the cargo feature `mpi`".into())
    }

    /// MUMPS' analysis of this rank's entries of `K` (`LinearSolver::Distributed`).
    #[cfg(feature = "mpi")]
    pub(crate) fn distributed(
        n: usize,
        rows: &[usize],
        cols: &[usize],
        symmetric: bool,
        ranks: crate::FactorRanks,
    ) -> Result<Self, String> {
        super::distributed_factor::DistributedFactor::analyse(n, rows, cols, symmetric, ranks)
            .map(SchurFactor::Distributed)
    }

    #[cfg(not(feature = "mpi"))]
    pub(crate) fn distributed(
        _n: usize,
        _rows: &[usize],
        _cols: &[usize],
        _symmetric: bool,
        _ranks: crate::FactorRanks,
    ) -> Result<Self, String> {
        Err("the distributed factorization needs the cargo feature `mpi`".into())
    }

    /// Factorizes this rank's `values` of `K` over the MPI ranks and solves
    /// `K x = rhs` in place (collective).
    pub(crate) fn solve_distributed(
        &mut self,
        values: &[f64],
        rhs: &mut [f64],
    ) -> Result<Factorized, String> {
        match self {
            #[cfg(feature = "mpi")]
            SchurFactor::Distributed(d) => {
                let negative = d.factorize(values)?;
                d.solve_in_place(rhs)?;
                Ok(Factorized::Distributed(negative))
            }
            _ => {
                let _ = (values, rhs);
                Err("not a distributed factorization".into())
            }
        }
    }

    /// Stored entries of the factors (`L`, or `L` and `U`; MUMPS': over all ranks, as
    /// estimated before the first factorization).
    pub(crate) fn factor_nnz(&self) -> usize {
        match self {
            SchurFactor::Cholesky { cholesky, .. } => cholesky.factor_nnz(),
            SchurFactor::Lu { no_pivot, .. } => no_pivot.symbolic().factor_nnz(),
            #[cfg(feature = "mpi")]
            SchurFactor::Distributed(d) => {
                let s = d.statistics();
                s.factor_entries.max(s.estimated_factor_entries).max(0) as usize
            }
        }
    }

    /// Bytes of the stored factors (f64 and f32 storage as allocated; MUMPS': this rank's
    /// share).
    pub(crate) fn factor_bytes(&self) -> usize {
        match self {
            SchurFactor::Cholesky { cholesky, .. } => cholesky.factor_bytes(),
            SchurFactor::Lu { no_pivot, .. } => 8 * no_pivot.symbolic().factor_nnz(),
            #[cfg(feature = "mpi")]
            SchurFactor::Distributed(d) => 8 * self.factor_nnz() / d.ranks(),
        }
    }

    /// Whether a factorization is held that [`precondition`](Self::precondition) can use.
    pub(crate) fn ready(&self) -> bool {
        match self {
            SchurFactor::Cholesky { ready, .. } | SchurFactor::Lu { ready, .. } => *ready,
            #[cfg(feature = "mpi")]
            SchurFactor::Distributed(d) => d.ready,
        }
    }

    /// Whether factorizations are stored in f32 (then only [`factorize_single`]
    /// (Self::factorize_single) and GMRES give directions, [`solve`](Self::solve) being
    /// the f64 fallback).
    pub(crate) fn single(&self) -> bool {
        matches!(self, SchurFactor::Cholesky { single: true, .. })
    }

    /// The f32 factorization of `k` (see [`single`](Self::single)).
    pub(crate) fn factorize_single(
        &mut self,
        k: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), String> {
        match self {
            SchurFactor::Cholesky {
                cholesky,
                ready,
                single: true,
            } => {
                *ready = false;
                cholesky.factorize_single(k).map_err(|e| e.to_string())?;
                *ready = true;
                Ok(())
            }
            _ => Err("single-precision factorizations need the Cholesky".into()),
        }
    }

    /// `x ← K_old⁻¹ x` with the last factorization (see [`ready`](Self::ready)).
    pub(crate) fn precondition(&mut self, x: &mut [f64]) {
        match self {
            SchurFactor::Cholesky {
                cholesky,
                single: true,
                ..
            } => cholesky.solve_in_place_single(x),
            SchurFactor::Cholesky { cholesky, .. } => cholesky.solve_in_place(x),
            SchurFactor::Lu { no_pivot, .. } => no_pivot.solve_in_place(x),
            #[cfg(feature = "mpi")]
            SchurFactor::Distributed(d) => {
                // A failed solve poisons x: GMRES then fails and the caller factorizes.
                if let Err(e) = d.solve_in_place(x) {
                    tracing::debug!(error = %e, "MUMPS solve failed");
                    x.fill(f64::NAN);
                }
            }
        }
    }

    /// Factorizes `k` and solves `k x = rhs` in place (`choice` is ignored for Cholesky).
    pub(crate) fn solve(
        &mut self,
        k: SparseColMatRef<'_, usize, f64>,
        rhs: &mut [f64],
        choice: LuChoice,
    ) -> Result<Factorized, String> {
        match self {
            SchurFactor::Cholesky {
                cholesky,
                ready,
                single,
            } => {
                // The f64 fallback of a single-precision solver leaves its f32 factor
                // as the preconditioner.
                if !*single {
                    *ready = false;
                }
                cholesky.factorize(k).map_err(|e| e.to_string())?;
                if !*single {
                    *ready = true;
                }
                cholesky.solve_in_place(rhs);
                Ok(Factorized::Cholesky)
            }
            SchurFactor::Lu {
                no_pivot,
                pivoting: fallback,
                ready,
            } => {
                *ready = false;
                if let LuChoice::NoPivot { pivot_tolerance } = choice {
                    match no_pivot.factorize(k.val(), pivot_tolerance) {
                        Ok(()) => {
                            *ready = true;
                            if tracing::enabled!(tracing::Level::TRACE) {
                                tracing::trace!(
                                    smallest_pivot_ratio = no_pivot.smallest_pivot_ratio(),
                                    "no-pivot LU"
                                );
                            }
                            no_pivot.solve_in_place(rhs);
                            let negative = no_pivot.negative_pivots().unwrap_or(0);
                            return Ok(Factorized::NoPivotLu(negative));
                        }
                        Err(breakdown) => {
                            tracing::debug!(%breakdown, "no-pivot LU refused: pivoting LU");
                        }
                    }
                }
                if fallback.is_none() {
                    *fallback = Some(PivotingLu::new(k.symbolic())?);
                }
                let lu = fallback.as_mut().expect("just built");
                lu.solve(k, rhs)?;
                Ok(Factorized::PivotingLu)
            }
            // Its values are this rank's entries (`solve_distributed`), not `k`.
            #[cfg(feature = "mpi")]
            SchurFactor::Distributed(_) => {
                Err("the distributed factorization takes its rank's entries only".into())
            }
        }
    }
}
