//! The pattern of the Schur matrix `K = M + h² Σ Bᵢᵀ Cᵢ Bᵢ` and where each point's
//! entries land in it, built column by column with a marker (the symbolic product `Bᵀ B`).
//! Sorting every `(row, column)` pair instead costs `Σ nᵢ²` pairs (3 M on a 10k-particle
//! MPM grid) and was most of an MPM step's set-up (`docs/mpm-performance.md`).
//!
//! Consecutive points with the same dofs (the Gauss points of one element) form one
//! *group* whose blocks are summed before the scatter: a P2 triangle's three points then
//! write 144 entries instead of 432, and the gather reads a third as much.
use faer::sparse::SymbolicSparseColMat;

use crate::operator::PointBlocks;

pub(crate) struct SchurPattern {
    pub symbolic: SymbolicSparseColMat<usize>,
    /// Where each entry of the assembly order lands in the CSC values: the `n_v`
    /// diagonal entries, then per group `(dofs[a], dofs[b])` for `a`, then `b`, in
    /// `0..nᵢ` (only `dofs[a] ≥ dofs[b]` when `symmetric`: the lower triangle).
    pub positions: Vec<usize>,
}

/// `group_ptr`: group `g` holds points `group_ptr[g]..group_ptr[g + 1]`, the maximal runs
/// of consecutive points with identical dof lists.
pub(crate) fn point_groups<const D: usize>(blocks: &PointBlocks<D>) -> Vec<usize> {
    let n_points = blocks.dof_ptr.len() - 1;
    let mut group_ptr = vec![0];
    for i in 1..n_points {
        if blocks.point(i).0 != blocks.point(i - 1).0 {
            group_ptr.push(i);
        }
    }
    if n_points > 0 {
        group_ptr.push(n_points);
    }
    group_ptr
}

/// Entries of point `i`'s block in the assembly order, and the index of `(a, b)` in it.
pub(crate) fn block_len(m: usize, symmetric: bool) -> usize {
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
    group_ptr: &[usize],
    symmetric: bool,
) -> Result<SchurPattern, String> {
    let n_groups = group_ptr.len().saturating_sub(1);
    // A group's dofs are those of its first point.
    let group_dofs = |g: usize| blocks.point(group_ptr[g]).0;
    let n_dofs: usize = (0..n_groups).map(|g| group_dofs(g).len()).sum();
    // Groups touching each velocity column, ascending (a counting sort of the dofs).
    let mut group_ptr_of_column = vec![0usize; n_v + 1];
    for g in 0..n_groups {
        for &j in group_dofs(g) {
            if j >= n_v {
                return Err(format!("velocity column {j} out of {n_v}"));
            }
            group_ptr_of_column[j + 1] += 1;
        }
    }
    for j in 0..n_v {
        group_ptr_of_column[j + 1] += group_ptr_of_column[j];
    }
    let mut fill = group_ptr_of_column.clone();
    let mut groups = vec![0usize; n_dofs];
    for g in 0..n_groups {
        for &j in group_dofs(g) {
            groups[fill[j]] = g;
            fill[j] += 1;
        }
    }

    // Rows of each column: the diagonal and every dof of every group in the column.
    let mut mark = vec![usize::MAX; n_v];
    let mut col_ptr = Vec::with_capacity(n_v + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::new();
    for j in 0..n_v {
        let start = row_idx.len();
        mark[j] = j;
        row_idx.push(j);
        for &i in &groups[group_ptr_of_column[j]..group_ptr_of_column[j + 1]] {
            for &r in group_dofs(i) {
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
    let mut offset = Vec::with_capacity(n_groups + 1);
    offset.push(n_v);
    for g in 0..n_groups {
        offset.push(offset[g] + block_len(group_dofs(g).len(), symmetric));
    }
    let mut positions = vec![usize::MAX; offset[n_groups]];
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
        for &i in &groups[group_ptr_of_column[j]..group_ptr_of_column[j + 1]] {
            let dofs = group_dofs(i);
            let m = dofs.len();
            let b = dofs
                .binary_search(&j)
                .map_err(|_| format!("group {i} lost column {j}"))?;
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

    /// The reference: every `(row, column)` pair of the assembly order (one block per
    /// group), sorted by faer.
    fn by_sorting<const D: usize>(
        n_v: usize,
        blocks: &PointBlocks<D>,
        group_ptr: &[usize],
        symmetric: bool,
    ) -> (SymbolicSparseColMat<usize>, Vec<(usize, usize)>) {
        let mut pairs: Vec<Pair<usize, usize>> = (0..n_v).map(|j| Pair::new(j, j)).collect();
        for g in 0..group_ptr.len() - 1 {
            let dofs = blocks.point(group_ptr[g]).0;
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
        // Points touching 1–9 scattered columns (a linear congruential generator); about
        // one in three repeats the previous point's columns, as Gauss points of one
        // element do.
        let mut state = 12345u64;
        let mut next = |n: usize| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) as usize) % n
        };
        let (n_v, n_points) = (60, 40);
        let mut triplets = Vec::new();
        let mut previous: Vec<usize> = Vec::new();
        let mut repeats = 0;
        for p in 0..n_points {
            let columns: Vec<usize> = if p > 0 && next(3) == 0 {
                repeats += 1;
                previous.clone()
            } else {
                (0..1 + next(9)).map(|_| next(n_v)).collect()
            };
            for &j in &columns {
                triplets.push(Triplet::new(4 * p + next(4), j, 1.0 + next(7) as f64));
            }
            previous = columns;
        }
        let b = SparseColMat::try_new_from_triplets(4 * n_points, n_v, &triplets).unwrap();
        let blocks = PointBlocks::<4>::new(&b, n_points);
        let group_ptr = point_groups(&blocks);
        assert!(repeats > 5 && group_ptr.len() - 1 < n_points);
        for g in 0..group_ptr.len() - 1 {
            for i in group_ptr[g]..group_ptr[g + 1] {
                assert_eq!(blocks.point(i).0, blocks.point(group_ptr[g]).0);
            }
        }
        for symmetric in [false, true] {
            let got = schur_pattern(n_v, &blocks, &group_ptr, symmetric).unwrap();
            let (want, pairs) = by_sorting(n_v, &blocks, &group_ptr, symmetric);
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
