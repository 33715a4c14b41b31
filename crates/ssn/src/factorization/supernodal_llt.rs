//! Sparse Cholesky `P A Pᵀ = L Lᵀ` on the supernodal structure of
//! [`SymbolicSymmetricPatternLu`], factorized by the same schedule as the no-pivot LU:
//! disjoint subtrees of the elimination tree on rayon's threads, their common ancestors
//! after them with the large dense blocks on every thread (`docs/performance.md`, 'The
//! Cholesky on two threads'). Each supernode applies its updates in one fixed order, so
//! the factor does not depend on the thread count. It is the LU's left-looking supernode
//! with `U = Lᵀ`: one product per update instead of two, half the storage.
use std::sync::Arc;

use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{MatMut, Par};

use super::dense_llt::llt_in_place;
use super::dense_lu::par_for;
use super::real::Real;
use super::symmetric_pattern_lu::{
    for_each_update, forward_substitution, permuted, run_schedule, subtract_product, Scratch,
    SymbolicSymmetricPatternLu,
};

/// The matrix is not (numerically) positive definite.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("Cholesky: non-positive pivot at column {column}")]
pub struct NotPositiveDefinite {
    /// Column of the permuted matrix where the factorization stopped.
    pub column: usize,
}

/// The numeric Cholesky of a symmetric matrix given by **one triangle** (every
/// off-diagonal pair stored once, e.g. the lower triangle whose pattern
/// [`SymbolicSymmetricPatternLu`] analysed as its symmetric closure), stored in `T`
/// (f64, or f32 for a preconditioner: the input is rounded as it is scattered), storage
/// reused by every [`factorize`](Self::factorize).
#[derive(Debug)]
pub struct SymmetricPatternLlt<T: Real = f64> {
    symbolic: Arc<SymbolicSymmetricPatternLu>,
    values: Vec<T>,
    scratch: Vec<Scratch<T>>,
    work: Vec<T>,
    gathered: Vec<T>,
    factorized: bool,
}

impl<T: Real> SymmetricPatternLlt<T> {
    pub fn new(symbolic: Arc<SymbolicSymmetricPatternLu>) -> Self {
        let (len_val, n) = (symbolic.len_val(), symbolic.n);
        Self {
            values: vec![T::ZERO; len_val],
            scratch: Vec::new(),
            work: vec![T::ZERO; n],
            gathered: Vec::new(),
            factorized: false,
            symbolic,
        }
    }

    pub fn symbolic(&self) -> &Arc<SymbolicSymmetricPatternLu> {
        &self.symbolic
    }

    /// Stored values of `L` (the supernodes' dense blocks, their diagonal blocks whole).
    pub fn len_val(&self) -> usize {
        self.values.len()
    }

    /// Factorizes the matrix whose stored values, in the order of the analysed pattern,
    /// are `values` (one triangle). A non-positive (or non-finite) pivot stops it with
    /// its column in the permuted order; the factor is then unusable.
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), NotPositiveDefinite> {
        let sym = Arc::clone(&self.symbolic);
        assert_eq!(
            values.len(),
            sym.input_nnz,
            "values do not match the analysed pattern"
        );
        self.factorized = false;
        run_schedule(
            &sym,
            [&mut self.values[..]],
            &mut self.scratch,
            |s, [l], origin, scratch, par| {
                factor_supernode(&sym, s, values, (l, origin), scratch, par)
            },
        )?;
        self.factorized = true;
        Ok(())
    }

    /// Solves `A x = b` in place with the last successful factorization (in `T`: `b`
    /// rounded to it, `x` widened back).
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let sym = &*self.symbolic;
        assert!(
            self.factorized,
            "solve_in_place before a successful factorize"
        );
        let (values, gathered) = (&self.values, &mut self.gathered);
        permuted(sym, rhs, &mut self.work, |x| {
            forward_substitution(sym, values, x, gathered, false);
            // Lᵀ x = y, backwards: each column's dot product with the rows below.
            for s in (0..sym.n_supernodes()).rev() {
                let begin = sym.supernode_begin[s];
                let (ncols, npat) = sym.shape(s);
                let nrows = ncols + npat;
                let ls = &values[sym.value_ptr[s]..sym.value_ptr[s + 1]];
                gathered.clear();
                gathered.extend(sym.rows(s).iter().map(|&r| x[r]));
                for j in (0..ncols).rev() {
                    let col = &ls[j * nrows..(j + 1) * nrows];
                    let below = dot(&col[ncols..], gathered);
                    let inside = dot(&col[j + 1..ncols], &x[begin + j + 1..begin + ncols]);
                    x[begin + j] = (x[begin + j] - below - inside) / col[j];
                }
            }
        });
    }
}

/// Factorizes supernode `s` (left-looking: its input, every descendant's update in
/// ascending order, the dense Cholesky of its diagonal block, the solve below it) into
/// `factor = (l, origin)`, the stretch of `L`'s values from `value_ptr` = `origin` on
/// that holds `s` and all its descendants.
fn factor_supernode<T: Real>(
    sym: &SymbolicSymmetricPatternLu,
    s: usize,
    values: &[f64],
    factor: (&mut [T], usize),
    scratch: &mut Scratch<T>,
    par: Par,
) -> Result<(), NotPositiveDefinite> {
    let (l_all, origin) = factor;
    let begin = sym.supernode_begin[s];
    let (ncols, npat) = sym.shape(s);
    let nrows = ncols + npat;
    let (l_done, l_rest) = l_all.split_at_mut(sym.value_ptr[s] - origin);
    let ls = &mut l_rest[..nrows * ncols];
    ls.fill(T::ZERO);
    // The LU's scatter: an entry it puts in `Uᵀ` (past `len_val`, laid out as `L`) is its
    // transpose in `L`; one it puts above the diagonal block's diagonal is folded below
    // it before any update (one triangle given: each pair lands once).
    let (base, len_val) = (sym.value_ptr[s], sym.len_val());
    for &(p, dest) in &sym.scatter[sym.scatter_ptr[s]..sym.scatter_ptr[s + 1]] {
        let dest = if dest >= len_val {
            dest - len_val
        } else {
            dest
        };
        ls[dest - base] += T::from_f64(values[p]);
    }
    for c in 1..ncols {
        for r in 0..c {
            let above = std::mem::replace(&mut ls[c * nrows + r], T::ZERO);
            ls[r * nrows + c] += above;
        }
    }
    for_each_update(sym, s, origin, scratch, |u, local_rows, update| {
        // Rows ≥ begin of L_d times its mid rows, transposed.
        let ld = &l_done[u.range.clone()];
        subtract_product(
            ls,
            nrows,
            local_rows,
            &local_rows[..u.k],
            ld,
            ld,
            u.d_nrows,
            u.d_ncols,
            u.first,
            u.m,
            u.first,
            u.k,
            update,
            par,
            true,
        );
    });
    let block = MatMut::from_column_major_slice_mut(ls, nrows, ncols);
    let (mut top, mut bottom) = block.split_at_row_mut(ncols);
    llt_in_place(top.rb_mut(), par).map_err(|p| NotPositiveDefinite {
        column: begin + p.column,
    })?;
    if npat > 0 {
        // L21 = A21 L11⁻ᵀ.
        let par = par_for(ncols * ncols * npat, par);
        solve_lower_triangular_in_place(top.rb(), bottom.rb_mut().transpose_mut(), par);
    }
    Ok(())
}

/// `Σ aᵢ bᵢ` over the shorter slice, in 16 interleaved partial sums added pairwise at the
/// end: a fixed order (the same bits every call) that vectorizes, where a single running
/// sum is a chain of dependent additions (the back-substitution was bound by it).
fn dot<T: Real>(a: &[T], b: &[T]) -> T {
    const LANES: usize = 16;
    let n = a.len().min(b.len());
    let split = n - n % LANES;
    let (a_body, a_tail) = a[..n].split_at(split);
    let (b_body, b_tail) = b[..n].split_at(split);
    let mut acc = [T::ZERO; LANES];
    for (x, y) in a_body.chunks_exact(LANES).zip(b_body.chunks_exact(LANES)) {
        for k in 0..LANES {
            acc[k] += x[k] * y[k];
        }
    }
    let mut width = LANES;
    while width > 1 {
        width /= 2;
        for k in 0..width {
            acc[k] += acc[k + width];
        }
    }
    a_tail
        .iter()
        .zip(b_tail)
        .fold(acc[0], |sum, (&x, &y)| sum + x * y)
}
