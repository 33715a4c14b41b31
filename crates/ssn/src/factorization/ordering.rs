//! The fill-reducing ordering of the factorizations' symbolic analysis: faer's approximate
//! minimum degree (the default), or METIS' nested dissection (cargo feature `metis`, which
//! builds METIS 5.2 from source). Measured on the 3D footing's `K` (`docs/3d.md`, 'Memory
//! and speed in 3D'): nested dissection stores 0.56× AMD's `nnz(L)` at 50k unknowns and
//! 0.46× at 200k, and factorizes 2.7–3.9× faster; in 2D, AMD from the mesh numbering is as
//! good (`docs/performance.md`, 'Open').
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::SymbolicSparseColMatRef;
use faer::Side;

pub use super::symbolic_error::SymbolicError;

/// Which fill-reducing ordering the symbolic analysis uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Ordering {
    /// faer's approximate minimum degree (every factorization before this setting).
    #[default]
    Amd,
    /// METIS' multilevel nested dissection (`METIS_NodeND`, default options) of the
    /// pattern's graph.
    #[cfg(feature = "metis")]
    NestedDissection,
}

/// faer's symbolic Cholesky of the lower triangle `lower` under `ordering`.
pub(crate) fn symbolic_cholesky(
    lower: SymbolicSparseColMatRef<'_, usize>,
    ordering: Ordering,
    params: CholeskySymbolicParams<'_>,
) -> Result<SymbolicCholesky<usize>, SymbolicError> {
    let analyse = |ordering: SymmetricOrdering<'_, usize>| {
        factorize_symbolic_cholesky(lower, Side::Lower, ordering, params)
            .map_err(|e| SymbolicError::new(format!("{e:?}")))
    };
    match ordering {
        Ordering::Amd => analyse(SymmetricOrdering::Amd),
        #[cfg(feature = "metis")]
        Ordering::NestedDissection => {
            let (fwd, inv) = postordered(lower, nested_dissection(lower)?);
            let n = lower.nrows();
            analyse(SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(
                &fwd, &inv, n,
            )))
        }
    }
}

/// METIS' nested dissection of the graph of a square pattern (either triangle, or both:
/// the graph is its symmetric closure without the diagonal). Returns `(fwd, inv)` with
/// `fwd[new] = old` (faer's forward array; METIS' `perm`) and `inv[old] = new`.
#[cfg(feature = "metis")]
pub fn nested_dissection(
    pattern: SymbolicSparseColMatRef<'_, usize>,
) -> Result<(Vec<usize>, Vec<usize>), SymbolicError> {
    let n = pattern.nrows();
    let mut graph = super::metis_graph::MetisGraph::of_pattern(pattern)?;
    if n == 0 {
        return Ok((Vec::new(), Vec::new()));
    }
    graph.nested_dissection()
}

/// `(fwd, inv)` renumbered along a postorder of the elimination tree of the permuted
/// pattern: an equivalent ordering (the same fill and flops) in which every subtree is a
/// contiguous range of columns, as the factorizations' parallel schedule needs
/// (`subtrees.rs`; METIS' numbering is not always one). The tree by Liu's algorithm with
/// path compression; children visited in ascending order.
#[cfg_attr(not(feature = "metis"), allow(dead_code))]
pub(crate) fn postordered(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    (fwd, inv): (Vec<usize>, Vec<usize>),
) -> (Vec<usize>, Vec<usize>) {
    let n = fwd.len();
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    // Each new column's neighbours of smaller new index, from either triangle (CSR).
    let inv = &inv;
    let pairs = || {
        (0..pattern.ncols().min(n)).flat_map(move |c| {
            ri[cp[c]..cp[c + 1]].iter().filter_map(move |&r| {
                let (i, j) = (inv[r], inv[c]);
                (i != j).then_some((i.max(j), i.min(j)))
            })
        })
    };
    let mut below_ptr = vec![0usize; n + 1];
    for (k, _) in pairs() {
        below_ptr[k + 1] += 1;
    }
    for k in 0..n {
        below_ptr[k + 1] += below_ptr[k];
    }
    let mut below = vec![0usize; below_ptr[n]];
    let mut next = below_ptr.clone();
    for (k, i) in pairs() {
        below[next[k]] = i;
        next[k] += 1;
    }
    let (mut parent, mut ancestor) = (vec![usize::MAX; n], next);
    ancestor.fill(usize::MAX);
    for k in 0..n {
        for &i in &below[below_ptr[k]..below_ptr[k + 1]] {
            let mut r = i;
            while ancestor[r] != usize::MAX && ancestor[r] != k {
                let next = ancestor[r];
                ancestor[r] = k;
                r = next;
            }
            if ancestor[r] == usize::MAX {
                ancestor[r] = k;
                parent[r] = k;
            }
        }
    }
    drop((below, below_ptr, ancestor));
    // Children as linked lists, ascending (built from the last).
    let (mut first_child, mut sibling) = (vec![usize::MAX; n], vec![usize::MAX; n]);
    for k in (0..n).rev() {
        let p = parent[k];
        if p != usize::MAX {
            sibling[k] = first_child[p];
            first_child[p] = k;
        }
    }
    let mut post = Vec::with_capacity(n);
    let mut stack: Vec<(usize, usize)> = Vec::new();
    for root in (0..n).filter(|&k| parent[k] == usize::MAX) {
        stack.push((root, first_child[root]));
        while let Some((k, child)) = stack.pop() {
            if child == usize::MAX {
                post.push(k);
            } else {
                stack.push((k, sibling[child]));
                stack.push((child, first_child[child]));
            }
        }
    }
    let fwd: Vec<usize> = post.iter().map(|&k| fwd[k]).collect();
    let mut inv = vec![0; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    (fwd, inv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::{Pair, SymbolicSparseColMat};

    /// The arrow matrix numbered so that its tree is not a postorder: column 0 is a child
    /// of column 2, column 1 of column 3 (`0 → 2 → 3 ← 1`). The postorder puts each
    /// subtree first and contiguous, and is a permutation.
    #[test]
    fn subtrees_become_contiguous() {
        let edges = [(2, 0), (3, 1), (3, 2)];
        let pairs: Vec<Pair<usize, usize>> = (0..4)
            .map(|j| Pair::new(j, j))
            .chain(edges.iter().map(|&(r, c)| Pair::new(r, c)))
            .collect();
        let (lower, _) = SymbolicSparseColMat::try_new_from_indices(4, 4, &pairs).unwrap();
        let identity: Vec<usize> = (0..4).collect();
        let (fwd, inv) = postordered(lower.as_ref(), (identity.clone(), identity));
        // Tree: 0's parent 2, 1's parent 3, 2's parent 3. Postorder: 0 2 1 3 or 1 0 2 3
        // (children ascending: 3's children are 1 and 2, so 1 first, then 0 2).
        assert_eq!(fwd, [1, 0, 2, 3]);
        for (new, &old) in fwd.iter().enumerate() {
            assert_eq!(inv[old], new);
        }
    }
}
