//! This rank's share of `K`'s assembly when MUMPS factorizes it over the MPI ranks
//! (`docs/distributed.md`, 'What runs where'): the point groups METIS' partition gives it
//! (`partition.rs`) and, on rank 0, the masses. The rank hands MUMPS only the entries
//! these touch (distributed assembled input); MUMPS sums the ones two ranks share.

/// The entries of `K` one rank assembles, each summed from its own contributions in
/// `SchurSystem::new`'s enumeration order.
pub(crate) struct OwnedAssembly {
    /// Point groups whose contributions this rank computes, ascending.
    pub(crate) groups: Vec<usize>,
    /// Every group's rank: the points each rank owns (`PointShare`).
    pub(crate) owners: Vec<usize>,
    /// Row and column of each entry (0-based), ascending CSC positions.
    pub(crate) rows: Vec<usize>,
    pub(crate) cols: Vec<usize>,
    /// For entry `e`, its contributions `gather[gather_ptr[e]..gather_ptr[e + 1]]`.
    gather_ptr: Vec<usize>,
    gather: Vec<u32>,
    pub(crate) values: Vec<f64>,
}

impl OwnedAssembly {
    /// Rank `rank`'s share: the groups `g` with `owners[g] == rank` (`group_entries[g]`:
    /// the first contribution of group g, masses before it), the masses on rank 0.
    /// `positions[k]`: the CSC position of contribution k; `col_ptr`, `row_idx`: K's
    /// pattern.
    pub(crate) fn new(
        rank: usize,
        owners: &[usize],
        group_entries: &[usize],
        positions: &[usize],
        col_ptr: &[usize],
        row_idx: &[usize],
    ) -> Self {
        let groups: Vec<usize> = (0..owners.len()).filter(|&g| owners[g] == rank).collect();
        let masses = if rank == 0 { 0..group_entries[0] } else { 0..0 };
        let contributions = masses.chain(
            groups
                .iter()
                .flat_map(|&g| group_entries[g]..group_entries[g + 1]),
        );
        // Entries in ascending CSC position; each one's contributions in order.
        let mut by_position: Vec<(usize, u32)> =
            contributions.map(|k| (positions[k], k as u32)).collect();
        by_position.sort_unstable();
        let mut gather_ptr = vec![0];
        let mut gather = Vec::with_capacity(by_position.len());
        let (mut rows, mut cols) = (Vec::new(), Vec::new());
        for (i, &(p, k)) in by_position.iter().enumerate() {
            if i > 0 && by_position[i - 1].0 != p {
                gather_ptr.push(gather.len());
            }
            if i == 0 || by_position[i - 1].0 != p {
                rows.push(row_idx[p]);
                cols.push(col_ptr.partition_point(|&c| c <= p) - 1);
            }
            gather.push(k);
        }
        gather_ptr.push(gather.len());
        let values = vec![0.0; rows.len()];
        Self {
            groups,
            owners: owners.to_vec(),
            rows,
            cols,
            gather_ptr,
            gather,
            values,
        }
    }

    /// This rank's entries from `contributions` (indexed as in `SchurSystem::new`).
    pub(crate) fn sum(&mut self, contributions: &[f64]) {
        for (e, out) in self.values.iter_mut().enumerate() {
            let mut acc = 0.0;
            for &k in &self.gather[self.gather_ptr[e]..self.gather_ptr[e + 1]] {
                acc += contributions[k as usize];
            }
            *out = acc;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three groups over a 3 × 3 pattern, split over 1, 2 and 3 ranks (every assignment of
    /// the groups to them): the ranks' entries summed together are the whole matrix, every
    /// contribution some rank's once.
    #[test]
    fn the_ranks_shares_add_up_to_the_whole_matrix() {
        // Dense 3 × 3 CSC pattern; 3 masses on the diagonal, then groups of 4, 2 and 3
        // contributions.
        let col_ptr = [0, 3, 6, 9];
        let row_idx = [0, 1, 2, 0, 1, 2, 0, 1, 2];
        let group_entries = [3, 7, 9, 12];
        let positions = [0, 4, 8, 0, 1, 3, 4, 8, 5, 4, 7, 8];
        let contributions: Vec<f64> = (0..12).map(|k| 1.0 + k as f64).collect();
        let mut whole = [0.0; 9];
        for (k, &p) in positions.iter().enumerate() {
            whole[p] += contributions[k];
        }
        for size in 1..=3usize {
            for code in 0..size.pow(3) {
                let owners: Vec<usize> = (0..3).map(|g| code / size.pow(g) % size).collect();
                let mut summed = [0.0; 9];
                let mut seen = vec![0; 12];
                for rank in 0..size {
                    let mut own = OwnedAssembly::new(
                        rank,
                        &owners,
                        &group_entries,
                        &positions,
                        &col_ptr,
                        &row_idx,
                    );
                    for k in own.gather.iter() {
                        seen[*k as usize] += 1;
                    }
                    own.sum(&contributions);
                    for (e, v) in own.values.iter().enumerate() {
                        summed[3 * own.cols[e] + own.rows[e]] += v;
                    }
                }
                assert_eq!(seen, vec![1; 12], "{size} ranks, owners {owners:?}");
                assert_eq!(summed, whole, "{size} ranks, owners {owners:?}");
            }
        }
    }
}
