//! Sparse LU without pivoting on a structurally symmetric pattern, laid out on the
//! supernodal Cholesky structure of that pattern.
//!
//! The Newton matrix of the Schur path, `M + h² Σ Bᵢᵀ Cᵢ Bᵢ`, has the symmetric pattern of
//! `Bᵀ B` but unsymmetric values (non-associative flow). Measured on our own Newton matrices
//! (`docs/performance.md`, "The factorization"), an LU without row exchanges on a symmetric
//! fill-reducing ordering gives the same residual and fill as partial pivoting, for about
//! twice a Cholesky's flops: `L` has the Cholesky pattern and `U` its transpose. A pivoting
//! LU reserves room for row exchanges and pays 2.5–5× that. Pivots are guarded
//! ([`PivotBreakdown`]); the caller falls back to a pivoting LU when one is refused.
//!
//! Symbolic phase once per pattern ([`SymbolicSymmetricPatternLu`], shareable), numeric
//! phase per matrix ([`SymmetricPatternLu::factorize`]) into storage reused across calls.
//! Disjoint subtrees of the elimination tree factorize on rayon's threads, their common
//! ancestors after them (`subtrees`); each supernode applies its updates in one fixed
//! order, so the factors do not depend on the thread count.
use std::sync::Arc;

use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_unit_lower_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::{CholeskySymbolicParams, SymbolicCholeskyRaw};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{Pair, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Accum, MatMut, MatRef, Par};
use rayon::prelude::*;

use super::dense_lu::{lu_in_place, par_for};
use super::ordering::{symbolic_cholesky, Ordering, SymbolicError};
use super::real::Real;
use super::subtrees::Schedule;

/// Default pivot guard: `|u_jj| ≤ 1e-10 |a_jj|` is refused. The Newton matrices seen never
/// come within 1e-4 of it (`docs/performance.md`); a matrix that needs row exchanges does.
pub const DEFAULT_PIVOT_TOLERANCE: f64 = 1e-10;

/// Below this many multiply-adds an update is done by plain loops (faer's product has a
/// fixed cost per call that the smallest supernodes would pay many times over).
const SMALL_UPDATE: usize = 512;

/// The numeric factorization met a pivot it does not trust.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("pivot {pivot:e} at column {column} (|a_jj| = {diagonal:e}) is below the guard")]
pub struct PivotBreakdown {
    /// Column of the input matrix (original numbering).
    pub column: usize,
    pub pivot: f64,
    /// `|a_jj|` of the input: the guard's scale.
    pub diagonal: f64,
}

/// What one descendant supernode `d` subtracts from a supernode `s`: the rows of `d`'s
/// pattern from `start` on lie in `s` or beyond, the first `mid` of them inside `s`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Update {
    pub(super) d: usize,
    pub(super) start: usize,
    pub(super) mid: usize,
}

/// The symbolic analysis of [`SymmetricPatternLu`] for one pattern: the fill-reducing
/// ordering (approximate minimum degree on the pattern), the supernodes of the Cholesky
/// factor of the permuted pattern, which supernode updates which, and where each stored
/// entry of the input lands in the factors.
#[derive(Debug)]
pub struct SymbolicSymmetricPatternLu {
    pub(super) n: usize,
    pub(super) input_nnz: usize,
    /// `perm_fwd[new] = old`.
    pub(super) perm_fwd: Vec<usize>,
    /// `n_supernodes + 1` column boundaries.
    pub(super) supernode_begin: Vec<usize>,
    /// Off-diagonal-block rows of each supernode (permuted numbering, ascending).
    pub(super) pattern_ptr: Vec<usize>,
    pub(super) pattern: Vec<usize>,
    /// Each supernode's `(ncols + pattern) × ncols` column-major block, in `L` and in `Uᵀ`.
    pub(super) value_ptr: Vec<usize>,
    pub(super) update_ptr: Vec<usize>,
    pub(super) updates: Vec<Update>,
    /// `(input position, destination)` of each stored input entry, grouped by the
    /// supernode it lands in (`scatter_ptr`), so that a supernode's blocks are zeroed and
    /// filled right before it is factorized (one pass over memory, not two). Destinations
    /// are in `L`'s values when below `len_val` (the diagonal blocks hold `L` and `U`
    /// together), in `Uᵀ`'s at `len_val + offset` otherwise.
    pub(super) scatter_ptr: Vec<usize>,
    pub(super) scatter: Vec<(usize, usize)>,
    /// Input position of `a_jj` for each permuted column (`usize::MAX` if not stored).
    pub(super) diagonal: Vec<usize>,
    pub(super) update_scratch: usize,
    pub(super) schedule: Schedule,
}

impl SymbolicSymmetricPatternLu {
    /// Analyses a square pattern (CSC, sorted rows) under AMD. An unsymmetric pattern is
    /// analysed as its symmetric closure `A + Aᵀ`.
    pub fn try_new(pattern: SymbolicSparseColMatRef<'_, usize>) -> Result<Self, SymbolicError> {
        Self::try_new_with(pattern, Ordering::Amd)
    }

    /// As [`try_new`](Self::try_new), under `ordering`.
    pub fn try_new_with(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        ordering: Ordering,
    ) -> Result<Self, SymbolicError> {
        let n = pattern.nrows();
        if pattern.ncols() != n {
            return Err(SymbolicError::new(format!(
                "matrix is {}×{}, not square",
                n,
                pattern.ncols()
            )));
        }
        let (col_ptr, row_idx) = (pattern.col_ptr(), pattern.row_idx());
        let input_nnz = row_idx.len();
        if n == 0 {
            // No unknown (every dof prescribed): no supernode; faer's analysis of an empty
            // pattern is simplicial.
            return Ok(Self {
                n,
                input_nnz,
                perm_fwd: Vec::new(),
                supernode_begin: vec![0],
                pattern_ptr: vec![0],
                pattern: Vec::new(),
                value_ptr: vec![0],
                update_ptr: vec![0],
                updates: Vec::new(),
                scatter_ptr: vec![0],
                scatter: Vec::new(),
                diagonal: Vec::new(),
                update_scratch: 0,
                schedule: Schedule::new(&[], &[]),
            });
        }
        // Lower triangle of the symmetric closure, diagonal always present.
        let mut pairs: Vec<Pair<usize, usize>> = (0..n).map(|j| Pair::new(j, j)).collect();
        for c in 0..n {
            for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
                if r != c {
                    pairs.push(Pair::new(r.max(c), r.min(c)));
                }
            }
        }
        let (lower, _) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
            .map_err(|e| SymbolicError::new(format!("{e:?}")))?;
        let cholesky = symbolic_cholesky(
            lower.as_ref(),
            ordering,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )?;
        let (perm_fwd, perm_inv) = match cholesky.perm() {
            Some(p) => {
                let (fwd, inv) = p.arrays();
                (fwd.to_vec(), inv.to_vec())
            }
            None => ((0..n).collect(), (0..n).collect()),
        };
        let SymbolicCholeskyRaw::Supernodal(sn) = cholesky.raw() else {
            return Err(SymbolicError::new(
                "faer chose a simplicial structure".into(),
            ));
        };
        let n_super = sn.n_supernodes();
        let mut supernode_begin = sn.supernode_begin().to_vec();
        supernode_begin.push(n);
        let mut pattern_ptr = vec![0];
        let mut pattern_rows = Vec::new();
        let mut value_ptr = vec![0];
        for s in 0..n_super {
            let rows = sn.supernode(s).pattern();
            if rows.windows(2).any(|w| w[0] >= w[1]) {
                return Err(SymbolicError::new(format!(
                    "supernode {s}: unsorted pattern"
                )));
            }
            pattern_rows.extend_from_slice(rows);
            pattern_ptr.push(pattern_rows.len());
            let ncols = supernode_begin[s + 1] - supernode_begin[s];
            value_ptr.push(value_ptr[s] + (ncols + rows.len()) * ncols);
        }
        let mut col_to_super = vec![0; n];
        for s in 0..n_super {
            col_to_super[supernode_begin[s]..supernode_begin[s + 1]].fill(s);
        }

        // Which supernodes each supernode updates, bucketed by target in ascending d.
        let mut by_target: Vec<(usize, Update)> = Vec::new();
        let mut update_scratch = 0;
        for d in 0..n_super {
            let rows = &pattern_rows[pattern_ptr[d]..pattern_ptr[d + 1]];
            let mut i = 0;
            while i < rows.len() {
                let s = col_to_super[rows[i]];
                let mid = rows[i..]
                    .iter()
                    .take_while(|&&r| r < supernode_begin[s + 1])
                    .count();
                by_target.push((s, Update { d, start: i, mid }));
                update_scratch = update_scratch.max((rows.len() - i) * mid);
                i += mid;
            }
        }
        let mut update_ptr = vec![0; n_super + 1];
        for (s, _) in &by_target {
            update_ptr[s + 1] += 1;
        }
        for s in 0..n_super {
            update_ptr[s + 1] += update_ptr[s];
        }
        let mut fill = update_ptr.clone();
        let mut updates = vec![
            Update {
                d: 0,
                start: 0,
                mid: 0
            };
            by_target.len()
        ];
        for (s, u) in by_target {
            updates[fill[s]] = u;
            fill[s] += 1;
        }

        let len_val = value_ptr[n_super];
        let local_row = |s: usize, row: usize| -> Result<usize, SymbolicError> {
            let (begin, end) = (supernode_begin[s], supernode_begin[s + 1]);
            if row < end {
                return Ok(row - begin);
            }
            pattern_rows[pattern_ptr[s]..pattern_ptr[s + 1]]
                .binary_search(&row)
                .map(|k| end - begin + k)
                .map_err(|_| SymbolicError::new(format!("row {row} missing from supernode {s}")))
        };
        let mut scatter_by: Vec<(usize, usize, usize)> = Vec::with_capacity(input_nnz);
        let mut diagonal = vec![usize::MAX; n];
        for c in 0..n {
            for (p, &r) in row_idx[col_ptr[c]..col_ptr[c + 1]].iter().enumerate() {
                let (i, j) = (perm_inv[r], perm_inv[c]);
                if i == j {
                    diagonal[j] = col_ptr[c] + p;
                }
                let owner = col_to_super[i.min(j)];
                let dest = if i >= j {
                    let s = col_to_super[j];
                    let nrows = supernode_begin[s + 1] - supernode_begin[s] + pattern_ptr[s + 1]
                        - pattern_ptr[s];
                    value_ptr[s] + (j - supernode_begin[s]) * nrows + local_row(s, i)?
                } else {
                    // U entry (i, j), i < j: row j of the transposed block of i's supernode.
                    let s = col_to_super[i];
                    let nrows = supernode_begin[s + 1] - supernode_begin[s] + pattern_ptr[s + 1]
                        - pattern_ptr[s];
                    let base = value_ptr[s] + (i - supernode_begin[s]) * nrows + local_row(s, j)?;
                    if j < supernode_begin[s + 1] {
                        // Inside the diagonal block: U shares L's storage, at (i, j).
                        value_ptr[s] + (j - supernode_begin[s]) * nrows + (i - supernode_begin[s])
                    } else {
                        len_val + base
                    }
                };
                scatter_by.push((owner, col_ptr[c] + p, dest));
            }
        }
        // Stable by supernode: within one, input order (the sum of duplicates keeps it).
        scatter_by.sort_by_key(|&(owner, _, _)| owner);
        let mut scatter_ptr = vec![0; n_super + 1];
        for &(owner, _, _) in &scatter_by {
            scatter_ptr[owner + 1] += 1;
        }
        for k in 0..n_super {
            scatter_ptr[k + 1] += scatter_ptr[k];
        }
        let scatter = scatter_by.into_iter().map(|(_, p, d)| (p, d)).collect();
        // A supernode's parent owns its first off-diagonal row; its flops ~ ncols · nrows².
        let parent: Vec<Option<usize>> = (0..n_super)
            .map(|s| {
                pattern_rows[pattern_ptr[s]..pattern_ptr[s + 1]]
                    .first()
                    .map(|&r| col_to_super[r])
            })
            .collect();
        let work: Vec<f64> = (0..n_super)
            .map(|s| {
                let ncols = (supernode_begin[s + 1] - supernode_begin[s]) as f64;
                let nrows = ncols + (pattern_ptr[s + 1] - pattern_ptr[s]) as f64;
                ncols * nrows * nrows
            })
            .collect();
        let schedule = Schedule::new(&parent, &work);
        Ok(Self {
            n,
            input_nnz,
            perm_fwd,
            supernode_begin,
            pattern_ptr,
            pattern: pattern_rows,
            value_ptr,
            update_ptr,
            updates,
            scatter_ptr,
            scatter,
            diagonal,
            update_scratch,
            schedule,
        })
    }

    /// Order of the matrix.
    pub fn dimension(&self) -> usize {
        self.n
    }

    /// Stored entries of `L` and `U` (diagonal counted once, explicit zeros of relaxed
    /// supernodes included): the fill.
    pub fn factor_nnz(&self) -> usize {
        let mut nnz = 0;
        for s in 0..self.n_supernodes() {
            let (ncols, npat) = self.shape(s);
            nnz += ncols * ncols + 2 * ncols * npat;
        }
        nnz
    }

    /// Subtrees of the elimination tree a factorization on several threads takes apart (0:
    /// it stays on one thread, e.g. below about 1e7 flops). The factors are the same either
    /// way.
    pub fn parallel_subtrees(&self) -> usize {
        self.schedule.tasks.len()
    }

    /// The fill-reducing permutation, `permutation()[new] = old`.
    pub fn permutation(&self) -> &[usize] {
        &self.perm_fwd
    }

    pub fn n_supernodes(&self) -> usize {
        self.supernode_begin.len() - 1
    }

    /// Columns and off-diagonal rows of supernode `s`.
    pub(super) fn shape(&self, s: usize) -> (usize, usize) {
        (
            self.supernode_begin[s + 1] - self.supernode_begin[s],
            self.pattern_ptr[s + 1] - self.pattern_ptr[s],
        )
    }

    pub(super) fn rows(&self, s: usize) -> &[usize] {
        &self.pattern[self.pattern_ptr[s]..self.pattern_ptr[s + 1]]
    }

    pub(super) fn len_val(&self) -> usize {
        self.value_ptr[self.n_supernodes()]
    }
}

/// The numeric LU `P A Pᵀ = L U` (no row exchanges) for one [`SymbolicSymmetricPatternLu`],
/// its storage reused by every [`factorize`](Self::factorize).
#[derive(Debug)]
pub struct SymmetricPatternLu {
    symbolic: Arc<SymbolicSymmetricPatternLu>,
    /// `L` (with `U`'s diagonal blocks) then `Uᵀ`'s off-diagonal blocks.
    values: Vec<f64>,
    reference: Vec<f64>,
    /// One per task of the schedule (at least one), reused across factorizations.
    scratch: Vec<Scratch<f64>>,
    work: Vec<f64>,
    gathered: Vec<f64>,
    factorized: bool,
}

impl SymmetricPatternLu {
    pub fn new(symbolic: Arc<SymbolicSymmetricPatternLu>) -> Self {
        let n = symbolic.n;
        Self {
            values: vec![0.0; 2 * symbolic.len_val()],
            reference: vec![0.0; n],
            scratch: vec![Scratch::new(&symbolic)],
            work: vec![0.0; n],
            gathered: Vec::new(),
            factorized: false,
            symbolic,
        }
    }

    pub fn symbolic(&self) -> &Arc<SymbolicSymmetricPatternLu> {
        &self.symbolic
    }

    /// Factorizes the matrix whose stored values, in the order of the analysed pattern,
    /// are `values`. A pivot `|u_jj| ≤ pivot_tolerance · |a_jj|` (or not finite) stops
    /// the factorization with [`PivotBreakdown`]; the factors are then unusable.
    pub fn factorize(
        &mut self,
        values: &[f64],
        pivot_tolerance: f64,
    ) -> Result<(), PivotBreakdown> {
        let sym = Arc::clone(&self.symbolic);
        assert_eq!(
            values.len(),
            sym.input_nnz,
            "values do not match the analysed pattern"
        );
        self.factorized = false;
        for (j, &p) in sym.diagonal.iter().enumerate() {
            self.reference[j] = if p == usize::MAX {
                0.0
            } else {
                values[p].abs()
            };
        }
        let (l_all, u_all) = self.values.split_at_mut(sym.len_val());
        let reference = &self.reference;
        run_schedule(
            &sym,
            [l_all, u_all],
            &mut self.scratch,
            |s, [l, u], origin, scratch, par| {
                factor_supernode(
                    &sym,
                    s,
                    values,
                    reference,
                    pivot_tolerance,
                    (l, u, origin),
                    scratch,
                    par,
                )
            },
        )?;
        self.factorized = true;
        Ok(())
    }

    /// `(j, u_jj)` in the permuted order, of the last successful factorization (`None`
    /// before one).
    fn pivots(&self) -> Option<impl Iterator<Item = (usize, f64)> + '_> {
        let sym = &*self.symbolic;
        self.factorized.then(|| {
            (0..sym.n_supernodes()).flat_map(move |s| {
                let begin = sym.supernode_begin[s];
                let (ncols, npat) = sym.shape(s);
                let nrows = ncols + npat;
                let ls = &self.values[sym.value_ptr[s]..sym.value_ptr[s + 1]];
                (0..ncols).map(move |j| (begin + j, ls[j * nrows + j]))
            })
        })
    }

    /// `min_j |u_jj| / |a_jj|` of the last successful factorization (columns with
    /// `a_jj = 0` skipped): how far the factorization stayed from the pivot guard.
    /// `None` before a successful factorization.
    pub fn smallest_pivot_ratio(&self) -> Option<f64> {
        let ratios = self.pivots()?.filter_map(|(j, u)| {
            let reference = self.reference[j];
            (reference > 0.0).then(|| u.abs() / reference)
        });
        Some(ratios.fold(f64::INFINITY, f64::min))
    }

    /// Negative pivots `u_jj` of the last successful factorization: `det A < 0` when their
    /// number is odd. The Newton matrix `K` of a converged step has none; a
    /// non-associative step past its fold shows them (`docs/solver.md`, 'Why the full step
    /// fails there'). `None` before a successful factorization.
    pub fn negative_pivots(&self) -> Option<usize> {
        Some(self.pivots()?.filter(|&(_, u)| u < 0.0).count())
    }

    /// Solves `A x = b` in place with the last successful factorization.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let sym = &*self.symbolic;
        assert!(
            self.factorized,
            "solve_in_place before a successful factorize"
        );
        let (l_all, u_all) = self.values.split_at(sym.len_val());
        let gathered = &mut self.gathered;
        permuted(sym, rhs, &mut self.work, |x| {
            forward_substitution(sym, l_all, x, gathered, true);
            // U x = y, backwards.
            for s in (0..sym.n_supernodes()).rev() {
                let begin = sym.supernode_begin[s];
                let (ncols, npat) = sym.shape(s);
                let nrows = ncols + npat;
                let ls = &l_all[sym.value_ptr[s]..sym.value_ptr[s + 1]];
                let us = &u_all[sym.value_ptr[s]..sym.value_ptr[s + 1]];
                gathered.clear();
                gathered.extend(sym.rows(s).iter().map(|&r| x[r]));
                for j in 0..ncols {
                    let col = &us[j * nrows + ncols..(j + 1) * nrows];
                    // One running sum, not `dot`'s partial sums: the non-associative
                    // runs keep their bits (the a = 2 column's folds went 65.1 → 71.2
                    // Newton iterations a step with the other rounding, docs/krylov.md).
                    let acc: f64 = col.iter().zip(gathered.iter()).map(|(u, x)| u * x).sum();
                    x[begin + j] -= acc;
                }
                for j in (0..ncols).rev() {
                    let col = &ls[j * nrows..j * nrows + ncols];
                    x[begin + j] /= col[j];
                    let xj = x[begin + j];
                    for (i, u) in col[..j].iter().enumerate() {
                        x[begin + i] -= u * xj;
                    }
                }
            }
        });
    }
}

/// Runs `factor(s, arrays, origin, scratch, par)` on every supernode `s` of `sym`, each
/// array holding `len_val` values laid out by `value_ptr` (`L`, `Uᵀ`): on one thread in
/// ascending order, or, with several threads and a [`Schedule`] with tasks, the tasks'
/// subtrees in parallel (each on its own contiguous stretch of every array, from
/// `value_ptr` = `origin` on, with its own [`Scratch`]), then the top on this thread
/// with the large dense blocks on every thread (`par`). Every supernode applies its
/// updates in one fixed order whichever the thread: the same bits. A failure in a task
/// re-runs everything on one thread, so that the error is the one the one-thread order
/// meets first.
pub(super) fn run_schedule<const K: usize, T: Real, E>(
    sym: &SymbolicSymmetricPatternLu,
    arrays: [&mut [T]; K],
    scratch: &mut Vec<Scratch<T>>,
    factor: impl Fn(usize, [&mut [T]; K], usize, &mut Scratch<T>, Par) -> Result<(), E> + Sync,
) -> Result<(), E> {
    let mut arrays = arrays;
    let schedule = &sym.schedule;
    let threads = rayon::current_num_threads();
    let par = if threads > 1 {
        Par::rayon(threads)
    } else {
        Par::Seq
    };
    if scratch.is_empty() {
        scratch.push(Scratch::new(sym));
    }
    let sequential = |arrays: &mut [&mut [T]; K], scratch: &mut Scratch<T>| {
        (0..sym.n_supernodes())
            .try_for_each(|s| factor(s, arrays.each_mut().map(|a| &mut **a), 0, scratch, par))
    };
    if schedule.tasks.is_empty() || threads == 1 {
        return sequential(&mut arrays, &mut scratch[0]);
    }
    while scratch.len() < schedule.tasks.len() {
        scratch.push(Scratch::new(sym));
    }
    // Each task owns its subtree's contiguous stretch of every array.
    let mut chunks = Vec::with_capacity(schedule.tasks.len());
    let mut rest = arrays.each_mut().map(|a| &mut **a);
    let mut offset = 0;
    for (task, scratch) in schedule.tasks.iter().zip(scratch.iter_mut()) {
        let (a, b) = (sym.value_ptr[task.start], sym.value_ptr[task.end]);
        let mut own: [&mut [T]; K] = std::array::from_fn(|_| <&mut [T]>::default());
        for (own, rest) in own.iter_mut().zip(rest.iter_mut()) {
            let (chunk, tail) = std::mem::take(rest)[a - offset..].split_at_mut(b - a);
            (*own, *rest) = (chunk, tail);
        }
        offset = b;
        chunks.push((task.clone(), own, scratch));
    }
    let failed = chunks.into_par_iter().any(|(task, mut own, scratch)| {
        let origin = sym.value_ptr[task.start];
        task.into_iter().any(|s| {
            factor(
                s,
                own.each_mut().map(|a| &mut **a),
                origin,
                scratch,
                Par::Seq,
            )
            .is_err()
        })
    });
    if failed {
        return sequential(&mut arrays, &mut scratch[0]);
    }
    schedule.top.iter().try_for_each(|&s| {
        factor(
            s,
            arrays.each_mut().map(|a| &mut **a),
            0,
            &mut scratch[0],
            par,
        )
    })
}

/// The work buffers of one thread: where a supernode's rows sit in its block, the rows a
/// descendant's update lands in, and the update's product.
#[derive(Debug)]
pub(super) struct Scratch<T> {
    pub(super) global_to_local: Vec<usize>,
    pub(super) local_rows: Vec<usize>,
    pub(super) update: Vec<T>,
}

impl<T: Real> Scratch<T> {
    pub(super) fn new(sym: &SymbolicSymmetricPatternLu) -> Self {
        Self {
            global_to_local: vec![usize::MAX; sym.n],
            local_rows: Vec::new(),
            update: vec![T::ZERO; sym.update_scratch],
        }
    }
}

/// Factorizes supernode `s` (left-looking: its input, every descendant's update in
/// ascending order, the dense LU of its diagonal block, the off-diagonal solves) into
/// `factors = (l, u, origin)`, the stretch of `L` and `Uᵀ`'s values from `value_ptr` =
/// `origin` on that holds `s` and all its descendants.
fn factor_supernode(
    sym: &SymbolicSymmetricPatternLu,
    s: usize,
    values: &[f64],
    reference: &[f64],
    pivot_tolerance: f64,
    factors: (&mut [f64], &mut [f64], usize),
    scratch: &mut Scratch<f64>,
    par: Par,
) -> Result<(), PivotBreakdown> {
    let (l_all, u_all, origin) = factors;
    let len_val = sym.len_val();
    let (begin, end) = (sym.supernode_begin[s], sym.supernode_begin[s + 1]);
    let (ncols, npat) = sym.shape(s);
    let nrows = ncols + npat;
    let (l_done, l_rest) = l_all.split_at_mut(sym.value_ptr[s] - origin);
    let (u_done, u_rest) = u_all.split_at_mut(sym.value_ptr[s] - origin);
    let ls = &mut l_rest[..nrows * ncols];
    let us = &mut u_rest[..nrows * ncols];
    ls.fill(0.0);
    us.fill(0.0);
    let base = sym.value_ptr[s];
    for &(p, dest) in &sym.scatter[sym.scatter_ptr[s]..sym.scatter_ptr[s + 1]] {
        if dest < len_val {
            ls[dest - base] += values[p];
        } else {
            us[dest - len_val - base] += values[p];
        }
    }
    for_each_update(sym, s, origin, scratch, |u, local_rows, update| {
        let (ld, ud) = (&l_done[u.range.clone()], &u_done[u.range.clone()]);
        // L and U's diagonal block: rows ≥ begin of L_d times the mid rows of U_dᵀ.
        subtract_product(
            ls,
            nrows,
            local_rows,
            &local_rows[..u.k],
            ld,
            ud,
            u.d_nrows,
            u.d_ncols,
            u.first,
            u.m,
            u.first,
            u.k,
            update,
            par,
            false,
        );
        // Uᵀ below the diagonal block: rows past `end` of U_dᵀ times the mid rows of L_d.
        if u.m > u.k {
            subtract_product(
                us,
                nrows,
                &local_rows[u.k..],
                &local_rows[..u.k],
                ud,
                ld,
                u.d_nrows,
                u.d_ncols,
                u.first + u.k,
                u.m - u.k,
                u.first,
                u.k,
                update,
                par,
                false,
            );
        }
    });
    let block = MatMut::from_column_major_slice_mut(ls, nrows, ncols);
    let (mut top, mut bottom) = block.split_at_row_mut(ncols);
    lu_in_place(top.rb_mut(), &reference[begin..end], pivot_tolerance, par).map_err(|p| {
        PivotBreakdown {
            column: sym.perm_fwd[begin + p.column],
            pivot: p.pivot,
            diagonal: reference[begin + p.column],
        }
    })?;
    if npat > 0 {
        // L21 = A21 U11⁻¹ and (U12)ᵀ = (L11⁻¹ A12)ᵀ.
        let par = par_for(ncols * ncols * npat, par);
        solve_lower_triangular_in_place(top.rb().transpose(), bottom.rb_mut().transpose_mut(), par);
        let ut = MatMut::from_column_major_slice_mut(us, nrows, ncols);
        let (_, mut ut_bottom) = ut.split_at_row_mut(ncols);
        solve_unit_lower_triangular_in_place(top.rb(), ut_bottom.rb_mut().transpose_mut(), par);
    }
    Ok(())
}

/// `solve` on `P rhs` (in `x`, `x[new] = rhs[old]`, rounded to `T`), and the result back
/// into `rhs` in the input's numbering.
pub(super) fn permuted<T: Real>(
    sym: &SymbolicSymmetricPatternLu,
    rhs: &mut [f64],
    x: &mut [T],
    solve: impl FnOnce(&mut [T]),
) {
    assert_eq!(rhs.len(), sym.n);
    for (new, &old) in sym.perm_fwd.iter().enumerate() {
        x[new] = T::from_f64(rhs[old]);
    }
    solve(x);
    for (new, &old) in sym.perm_fwd.iter().enumerate() {
        rhs[old] = x[new].to_f64();
    }
}

/// `L y = x` in place for the supernodal `L` (values `l`, laid out by `value_ptr`),
/// supernode by supernode: the diagonal block, then the rows below through a dense buffer
/// (contiguous columns, one scatter). `unit_diagonal`: `L`'s diagonal is 1 (the LU's; the
/// stored diagonal is `U`'s), else the stored one (the Cholesky's).
pub(super) fn forward_substitution<T: Real>(
    sym: &SymbolicSymmetricPatternLu,
    l: &[T],
    x: &mut [T],
    gathered: &mut Vec<T>,
    unit_diagonal: bool,
) {
    for s in 0..sym.n_supernodes() {
        let begin = sym.supernode_begin[s];
        let (ncols, npat) = sym.shape(s);
        let nrows = ncols + npat;
        let ls = &l[sym.value_ptr[s]..sym.value_ptr[s + 1]];
        gathered.clear();
        gathered.resize(npat, T::ZERO);
        for j in 0..ncols {
            let col = &ls[j * nrows..(j + 1) * nrows];
            if !unit_diagonal {
                x[begin + j] /= col[j];
            }
            let xj = x[begin + j];
            for (i, l) in (j + 1..ncols).zip(&col[j + 1..ncols]) {
                x[begin + i] -= l * xj;
            }
            for (g, l) in gathered.iter_mut().zip(&col[ncols..]) {
                *g += l * xj;
            }
        }
        for (&r, g) in sym.rows(s).iter().zip(gathered.iter()) {
            x[r] -= *g;
        }
    }
}

/// Where one update of a supernode `s` reads from a descendant `d`: `d`'s block in the
/// factor arrays (`range`, from the caller's `origin`), its leading dimension `d_nrows`
/// and columns `d_ncols`, the block row `first` where the update's `m` rows start, the
/// first `k` of them inside `s`.
pub(super) struct UpdateBlock {
    pub(super) range: std::ops::Range<usize>,
    pub(super) d_nrows: usize,
    pub(super) d_ncols: usize,
    pub(super) first: usize,
    pub(super) m: usize,
    pub(super) k: usize,
}

/// Calls `apply(block, local_rows, product)` for every update of supernode `s` in its one
/// fixed order (ascending descendants: the same bits on any thread), `local_rows` the
/// update's rows in `s`'s block numbering and `product` the scratch for its product.
pub(super) fn for_each_update<T: Real>(
    sym: &SymbolicSymmetricPatternLu,
    s: usize,
    origin: usize,
    scratch: &mut Scratch<T>,
    mut apply: impl FnMut(&UpdateBlock, &[usize], &mut [T]),
) {
    let (begin, end) = (sym.supernode_begin[s], sym.supernode_begin[s + 1]);
    let ncols = end - begin;
    let Scratch {
        global_to_local,
        local_rows,
        update,
    } = scratch;
    for (k, &r) in sym.rows(s).iter().enumerate() {
        global_to_local[r] = ncols + k;
    }
    for upd in &sym.updates[sym.update_ptr[s]..sym.update_ptr[s + 1]] {
        let (d_ncols, d_npat) = sym.shape(upd.d);
        let d_rows = &sym.rows(upd.d)[upd.start..];
        local_rows.clear();
        local_rows.extend(d_rows.iter().map(|&r| {
            if r < end {
                r - begin
            } else {
                global_to_local[r]
            }
        }));
        let block = UpdateBlock {
            range: sym.value_ptr[upd.d] - origin..sym.value_ptr[upd.d + 1] - origin,
            d_nrows: d_ncols + d_npat,
            d_ncols,
            first: d_ncols + upd.start,
            m: d_rows.len(),
            k: upd.mid,
        };
        apply(&block, local_rows, update);
    }
    for &r in sym.rows(s) {
        global_to_local[r] = usize::MAX;
    }
}

/// `target[rows[i], cols[j]] −= Σ_c a[a_first + i, c] · b[b_first + j, c]` for the
/// column-major `(.. × d_ncols)` blocks `a`, `b` of leading dimension `d_nrows`, into the
/// column-major `target` of leading dimension `ld`. With `top_lower` (a Cholesky's
/// update: `a = b`, `a_first = b_first`, so the top `k × k` of the product is
/// symmetric) a large product computes that top's lower triangle only, and what lands
/// above the target's diagonal is not to be read.
#[allow(clippy::too_many_arguments)]
pub(super) fn subtract_product<T: Real>(
    target: &mut [T],
    ld: usize,
    rows: &[usize],
    cols: &[usize],
    a: &[T],
    b: &[T],
    d_nrows: usize,
    d_ncols: usize,
    a_first: usize,
    m: usize,
    b_first: usize,
    k: usize,
    scratch: &mut [T],
    par: Par,
    top_lower: bool,
) {
    if m * k * d_ncols <= SMALL_UPDATE {
        // The product into `scratch` (dense, column-major), then one scatter.
        let product = &mut scratch[..m * k];
        product.fill(T::ZERO);
        for j in 0..k {
            let p = &mut product[j * m..(j + 1) * m];
            for c in 0..d_ncols {
                let bj = b[c * d_nrows + b_first + j];
                let ac = &a[c * d_nrows + a_first..c * d_nrows + a_first + m];
                for (pi, aic) in p.iter_mut().zip(ac) {
                    *pi += *aic * bj;
                }
            }
        }
    } else {
        let a_block =
            MatRef::from_column_major_slice_with_stride(&a[a_first..], m, d_ncols, d_nrows);
        let b_block =
            MatRef::from_column_major_slice_with_stride(&b[b_first..], k, d_ncols, d_nrows);
        let par = par_for(m * k * d_ncols, par);
        let product = MatMut::from_column_major_slice_mut(&mut scratch[..m * k], m, k);
        if top_lower {
            let (top, bottom) = product.split_at_row_mut(k);
            let (a_top, a_bottom) = a_block.split_at_row(k);
            triangular::matmul(
                top,
                BlockStructure::TriangularLower,
                Accum::Replace,
                a_top,
                BlockStructure::Rectangular,
                b_block.transpose(),
                BlockStructure::Rectangular,
                T::ONE,
                par,
            );
            matmul(
                bottom,
                Accum::Replace,
                a_bottom,
                b_block.transpose(),
                T::ONE,
                par,
            );
        } else {
            matmul(
                product,
                Accum::Replace,
                a_block,
                b_block.transpose(),
                T::ONE,
                par,
            );
        }
    }
    for (j, &cj) in cols.iter().enumerate() {
        let t = &mut target[cj * ld..(cj + 1) * ld];
        let p = &scratch[j * m..(j + 1) * m];
        for (&ri, &v) in rows.iter().zip(p) {
            t[ri] -= v;
        }
    }
}
