//! The fill-reducing ordering of the Newton matrix's pattern: faer's approximate minimum
//! degree, or nested dissection ([`super::nested_dissection`]) where its factor costs fewer
//! flops. Both symbolic analyses are cheap next to one numeric factorization (0.6 s and
//! 0.5 s + 0.6 s at 400k dofs, where one numeric LU takes seconds), and the choice is
//! made once per pattern from the pattern alone, so it does not depend on the values or
//! on the thread count (`docs/performance.md`, "The factorization").
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::SymbolicSparseColMatRef;
use faer::Side;

use super::nested_dissection::nested_dissection;
use super::SymbolicError;

/// Below this dimension only AMD is tried: on the footing's P2 meshes nested dissection
/// costs 1.3× AMD's flops at 3.8k dofs, 0.83× at 40k, 0.77× at 160k and 0.63× at 400k.
const NESTED_DISSECTION_MIN_DIMENSION: usize = 20_000;

/// The symbolic Cholesky analysis of the lower triangle `lower` of a symmetric pattern
/// under the cheaper of the two orderings.
pub(crate) fn analyse(
    lower: SymbolicSparseColMatRef<'_, usize>,
    params: CholeskySymbolicParams<'_>,
) -> Result<SymbolicCholesky<usize>, SymbolicError> {
    let symbolic = |ordering| {
        factorize_symbolic_cholesky(lower, Side::Lower, ordering, params)
            .map_err(|e| SymbolicError::new(format!("{e:?}")))
    };
    let amd = symbolic(SymmetricOrdering::Amd)?;
    let n = lower.nrows();
    if n < NESTED_DISSECTION_MIN_DIMENSION {
        return Ok(amd);
    }
    let (xadj, adj) = adjacency(lower);
    let fwd = nested_dissection(&xadj, &adj);
    let mut inv = vec![0; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    let nd = symbolic(SymmetricOrdering::Custom(PermRef::new_checked(
        &fwd, &inv, n,
    )))?;
    let (amd_flops, nd_flops) = (factor_flops(&amd), factor_flops(&nd));
    tracing::debug!(
        n,
        amd_flops,
        nd_flops,
        chosen = if nd_flops < amd_flops {
            "nested dissection"
        } else {
            "amd"
        },
        "ordering"
    );
    Ok(if nd_flops < amd_flops { nd } else { amd })
}

/// Both directions of every off-diagonal entry of `lower`, as CSR.
fn adjacency(lower: SymbolicSparseColMatRef<'_, usize>) -> (Vec<usize>, Vec<usize>) {
    let n = lower.nrows();
    let (col_ptr, row_idx) = (lower.col_ptr(), lower.row_idx());
    let mut count = vec![0usize; n + 1];
    for c in 0..n {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            if r != c {
                count[r + 1] += 1;
                count[c + 1] += 1;
            }
        }
    }
    for v in 0..n {
        count[v + 1] += count[v];
    }
    let mut next = count.clone();
    let mut adj = vec![0; count[n]];
    for c in 0..n {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            if r != c {
                adj[next[r]] = c;
                next[r] += 1;
                adj[next[c]] = r;
                next[c] += 1;
            }
        }
    }
    (count, adj)
}

/// `Σⱼ (entries of column j of L below the diagonal)²`: the multiply-adds of a
/// factorization, up to a constant.
fn factor_flops(symbolic: &SymbolicCholesky<usize>) -> f64 {
    let square = |k: usize| (k as f64) * (k as f64);
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => s
            .col_ptr()
            .windows(2)
            .map(|w| square((w[1] - w[0]).saturating_sub(1)))
            .sum(),
        SymbolicCholeskyRaw::Supernodal(sn) => {
            let n = symbolic.nrows();
            let begin = sn.supernode_begin();
            (0..sn.n_supernodes())
                .map(|s| {
                    let end = begin.get(s + 1).copied().unwrap_or(n);
                    let (c, r) = (end - begin[s], sn.supernode(s).pattern().len());
                    (0..c).map(|j| square(c - j - 1 + r)).sum::<f64>()
                })
                .sum()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::nested_dissection::test_meshes::p2_graph;
    use super::*;
    use faer::sparse::{Pair, SymbolicSparseColMat};

    /// Lower triangle (with diagonal) of the 9-point grid graph of `nx × ny` vertices.
    fn grid(nx: usize, ny: usize) -> SymbolicSparseColMat<usize> {
        let mut pairs = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let v = j * nx + i;
                pairs.push(Pair::new(v, v));
                for (di, dj) in [(1, 0), (0, 1), (1, 1)] {
                    if i + di < nx && j + dj < ny {
                        pairs.push(Pair::new((j + dj) * nx + i + di, v));
                    }
                }
                if i > 0 && j + 1 < ny {
                    pairs.push(Pair::new((j + 1) * nx + i - 1, v));
                }
            }
        }
        let n = nx * ny;
        SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
            .expect("pattern")
            .0
    }

    #[test]
    fn adjacency_is_symmetric_without_the_diagonal() {
        let g = grid(7, 5);
        let (xadj, adj) = adjacency(g.as_ref());
        let n = 35;
        for v in 0..n {
            let nb = &adj[xadj[v]..xadj[v + 1]];
            assert!(!nb.contains(&v));
            for &w in nb {
                assert!(adj[xadj[w]..xadj[w + 1]].contains(&v), "{v}–{w}");
            }
        }
        // 9-point stencil: interior vertices have 8 neighbours.
        let interior = 2 * 7 + 3;
        assert_eq!(xadj[interior + 1] - xadj[interior], 8);
    }

    #[test]
    fn the_cheaper_ordering_is_kept_and_small_patterns_keep_amd() {
        let params = CholeskySymbolicParams::default;
        // Small: AMD as before, same factor.
        let small = grid(40, 30);
        let amd = factorize_symbolic_cholesky(
            small.as_ref(),
            Side::Lower,
            SymmetricOrdering::Amd,
            params(),
        )
        .expect("amd");
        let chosen = analyse(small.as_ref(), params()).expect("analyse");
        assert_eq!(chosen.len_val(), amd.len_val());
        // The dof graph of the 104 × 48 P2 footing mesh (40 546 dofs): nested dissection
        // costs 0.83× AMD's flops there (`nested_dissection.rs`, measure), and is chosen.
        let (xadj, adj) = p2_graph(104, 48);
        let n = xadj.len() - 1;
        let pairs: Vec<Pair<usize, usize>> = (0..n)
            .flat_map(|v| {
                let below = adj[xadj[v]..xadj[v + 1]].iter().filter(move |&&w| w > v);
                std::iter::once(Pair::new(v, v)).chain(below.map(move |&w| Pair::new(w, v)))
            })
            .collect();
        let large = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
            .expect("pattern")
            .0;
        let amd = factorize_symbolic_cholesky(
            large.as_ref(),
            Side::Lower,
            SymmetricOrdering::Amd,
            params(),
        )
        .expect("amd");
        let chosen = analyse(large.as_ref(), params()).expect("analyse");
        assert!(factor_flops(&chosen) < 0.9 * factor_flops(&amd));
    }
}
