//! The pattern of the Schur matrix `K = M + h² Σ Bᵢᵀ Cᵢ Bᵢ` and where each point's
//! entries land in it, built column by column with a marker (the symbolic product `Bᵀ B`).
//! Sorting every `(row, column)` pair instead costs `Σ nᵢ²` pairs (3 M on a 10k-particle
//! MPM grid) and was most of an MPM step's set-up (`docs/mpm-performance.md`).
use faer::sparse::SymbolicSparseColMat;

use crate::operator::PointBlocks;

pub(crate) struct SchurPattern {
    pub symbolic: SymbolicSparseColMat<usize>,
    /// Where each entry of the assembly order lands in the CSC values: the `n_v`
    /// diagonal entries, then per point `(dofs[a], dofs[b])` for `a`, then `b`, in
    /// `0..nᵢ` (only `dofs[a] ≥ dofs[b]` when `symmetric`: the lower triangle).
    pub positions: Vec<usize>,
}

/// Entries of point `i`'s block in the assembly order, and the index of `(a, b)` in it.
fn block_len(m: usize, symmetric: bool) -> usize {
    if symmetric {
        m * (m + 1) / 2
    } else {
        m * m
    }
}

fn block_index(a: usize, b: usize, m: usize, symmetric: bool) -> usize {
    // A point's dofs are sorted ascending, so dofs[a] ≥ dofs[b] is a ≥ b.
    if symmetric {
        a * (a + 1) / 2 + b
    } else {
        a * m + b
    }
}

pub(crate) fn schur_pattern<const D: usize>(
    n_v: usize,
    blocks: &PointBlocks<D>,
    symmetric: bool,
) -> Result<SchurPattern, String> {
    let n_points = blocks.dof_ptr.len() - 1;
    // Points touching each velocity column, ascending (a counting sort of the dofs).
    let mut point_ptr = vec![0usize; n_v + 1];
    for &j in &blocks.dofs {
        if j >= n_v {
            return Err(format!("velocity column {j} out of {n_v}"));
        }
        point_ptr[j + 1] += 1;
    }
    for j in 0..n_v {
        point_ptr[j + 1] += point_ptr[j];
    }
    let mut fill = point_ptr.clone();
    let mut points = vec![0usize; blocks.dofs.len()];
    for i in 0..n_points {
        for &j in blocks.point(i).0 {
            points[fill[j]] = i;
            fill[j] += 1;
        }
    }

    // Rows of each column: the diagonal and every dof of every point in the column.
    let mut mark = vec![usize::MAX; n_v];
    let mut col_ptr = Vec::with_capacity(n_v + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::new();
    for j in 0..n_v {
        let start = row_idx.len();
        mark[j] = j;
        row_idx.push(j);
        for &i in &points[point_ptr[j]..point_ptr[j + 1]] {
            for &r in blocks.point(i).0 {
                if (!symmetric || r >= j) && mark[r] != j {
                    mark[r] = j;
                    row_idx.push(r);
                }
            }
        }
        row_idx[start..].sort_unstable();
        col_ptr.push(row_idx.len());
    }

    // Positions: column by column, each row's CSC index in a scatter map.
    let mut offset = Vec::with_capacity(n_points + 1);
    offset.push(n_v);
    for i in 0..n_points {
        let m = blocks.point(i).0.len();
        offset.push(offset[i] + block_len(m, symmetric));
    }
    let mut positions = vec![usize::MAX; offset[n_points]];
    let mut at = vec![0usize; n_v];
    for j in 0..n_v {
        for (k, &r) in row_idx
            .iter()
            .enumerate()
            .take(col_ptr[j + 1])
            .skip(col_ptr[j])
        {
            at[r] = k;
        }
        positions[j] = at[j];
        for &i in &points[point_ptr[j]..point_ptr[j + 1]] {
            let dofs = blocks.point(i).0;
            let m = dofs.len();
            let b = dofs
                .binary_search(&j)
                .map_err(|_| format!("point {i} lost column {j}"))?;
            for (a, &r) in dofs.iter().enumerate() {
                if symmetric && a < b {
                    continue;
                }
                positions[offset[i] + block_index(a, b, m, symmetric)] = at[r];
            }
        }
    }
    debug_assert!(positions.iter().all(|&p| p != usize::MAX));
    let symbolic = SymbolicSparseColMat::new_checked(n_v, n_v, col_ptr, None, row_idx);
    Ok(SchurPattern {
        symbolic,
        positions,
    })
}

#[cfg(test)]
mod tests {
    use faer::sparse::{Pair, SparseColMat, Triplet};

    use super::*;

    /// The reference: every `(row, column)` pair of the assembly order, sorted by faer.
    fn by_sorting<const D: usize>(
        n_v: usize,
        blocks: &PointBlocks<D>,
        symmetric: bool,
    ) -> (SymbolicSparseColMat<usize>, Vec<(usize, usize)>) {
        let mut pairs: Vec<Pair<usize, usize>> = (0..n_v).map(|j| Pair::new(j, j)).collect();
        for i in 0..blocks.dof_ptr.len() - 1 {
            let dofs = blocks.point(i).0;
            for &ra in dofs {
                for &cb in dofs {
                    if !symmetric || ra >= cb {
                        pairs.push(Pair::new(ra, cb));
                    }
                }
            }
        }
        let (symbolic, _) = SymbolicSparseColMat::try_new_from_indices(n_v, n_v, &pairs).unwrap();
        (symbolic, pairs.iter().map(|p| (p.row, p.col)).collect())
    }

    #[test]
    fn marker_pattern_equals_sorted_pairs() {
        // Points touching 1–9 scattered columns (a linear congruential generator).
        let mut state = 12345u64;
        let mut next = |n: usize| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) as usize) % n
        };
        let (n_v, n_points) = (60, 40);
        let mut triplets = Vec::new();
        for p in 0..n_points {
            for _ in 0..1 + next(9) {
                let j = next(n_v);
                triplets.push(Triplet::new(4 * p + next(4), j, 1.0 + next(7) as f64));
            }
        }
        let b = SparseColMat::try_new_from_triplets(4 * n_points, n_v, &triplets).unwrap();
        let blocks = PointBlocks::<4>::new(&b, n_points);
        for symmetric in [false, true] {
            let got = schur_pattern(n_v, &blocks, symmetric).unwrap();
            let (want, pairs) = by_sorting(n_v, &blocks, symmetric);
            assert_eq!(
                got.symbolic.col_ptr(),
                want.col_ptr(),
                "symmetric {symmetric}"
            );
            assert_eq!(
                got.symbolic.row_idx(),
                want.row_idx(),
                "symmetric {symmetric}"
            );
            assert_eq!(got.positions.len(), pairs.len());
            let (cp, ri) = (got.symbolic.col_ptr(), got.symbolic.row_idx());
            for (k, &(r, c)) in pairs.iter().enumerate() {
                let p = got.positions[k];
                assert!(
                    (cp[c]..cp[c + 1]).contains(&p) && ri[p] == r,
                    "entry {k} ({r}, {c}) placed at {p}, symmetric {symmetric}"
                );
            }
        }
    }
}
