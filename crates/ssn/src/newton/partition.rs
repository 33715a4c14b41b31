//! Which rank assembles which point groups when MUMPS factorizes `K` over the MPI ranks
//! (`docs/distributed.md`, 'What runs where'): METIS' k-way partition of `K`'s graph, each
//! velocity dof weighted by the groups anchored at it (a group's anchor: its smallest dof),
//! so that the ranks get about equal numbers of groups (of contributions, where the groups'
//! blocks are of one size) and share few entries. A
//! group goes to its anchor's part. METIS runs with its fixed seed: every rank computes the
//! same parts from the same pattern.
use faer::sparse::SymbolicSparseColMatRef;

use crate::operator::PointBlocks;

/// The rank of each group (`group_ptr`: the groups' first points) among `ranks`.
#[cfg(feature = "metis")]
pub(crate) fn group_owners<const D: usize>(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    blocks: &PointBlocks<D>,
    group_ptr: &[usize],
    ranks: usize,
) -> Result<Vec<usize>, String> {
    let n_groups = group_ptr.len().saturating_sub(1);
    let anchors: Vec<usize> = (0..n_groups)
        .map(|g| {
            blocks
                .point(group_ptr[g])
                .0
                .iter()
                .copied()
                .min()
                .unwrap_or(0)
        })
        .collect();
    let mut weights = vec![0usize; pattern.nrows()];
    for &a in &anchors {
        weights[a] += 1;
    }
    let parts = crate::factorization::metis_graph::MetisGraph::of_pattern(pattern)
        .and_then(|mut graph| graph.partition(&weights, ranks))
        .map_err(|e| format!("partitioning K between {ranks} ranks: {e}"))?;
    Ok(anchors.into_iter().map(|a| parts[a]).collect())
}

/// Without METIS there is no distributed factorization to share out (feature `mpi`).
#[cfg(not(feature = "metis"))]
pub(crate) fn group_owners<const D: usize>(
    _pattern: SymbolicSparseColMatRef<'_, usize>,
    _blocks: &PointBlocks<D>,
    _group_ptr: &[usize],
    ranks: usize,
) -> Result<Vec<usize>, String> {
    Err(format!(
        "partitioning K between {ranks} ranks needs METIS: build with the feature `mpi`"
    ))
}

#[cfg(all(test, feature = "metis"))]
mod tests {
    use faer::sparse::{SparseColMat, Triplet};

    use super::*;
    use crate::newton::schur_pattern::{point_groups, schur_pattern};

    /// Entries of `K`'s lower triangle that groups of two or more ranks touch: what MUMPS
    /// receives twice.
    fn shared_entries(
        n: usize,
        blocks: &PointBlocks<1>,
        group_ptr: &[usize],
        owners: &[usize],
    ) -> usize {
        let mut first = std::collections::HashMap::new();
        let mut shared = std::collections::HashSet::new();
        for (g, &rank) in owners.iter().enumerate() {
            let dofs = blocks.point(group_ptr[g]).0;
            for &a in dofs {
                for &b in dofs {
                    if a >= b && *first.entry((a, b)).or_insert(rank) != rank {
                        shared.insert((a, b));
                    }
                }
            }
        }
        assert!(first.len() <= n * n);
        shared.len()
    }

    /// A 40 × 40 grid of bilinear elements, one point each touching its 4 nodes (one dof
    /// a node): METIS' halves and quarters balance the elements within METIS' 3% (plus a
    /// grid line's granularity), share at most twice the entries of the straight cut
    /// through the middle (41 nodes and the 40 edges between them), and are the same when
    /// computed again (every rank computes them).
    #[test]
    fn a_grid_is_cut_in_balanced_compact_parts() {
        let (nx, ny) = (40, 40);
        let node = |i: usize, j: usize| j * (nx + 1) + i;
        let n_v = (nx + 1) * (ny + 1);
        let mut triplets = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let e = j * nx + i;
                for n in [
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1),
                ] {
                    triplets.push(Triplet::new(e, n, 0.25));
                }
            }
        }
        let b = SparseColMat::try_new_from_triplets(nx * ny, n_v, &triplets).unwrap();
        let blocks = PointBlocks::<1>::new(&b, nx * ny);
        let group_ptr = point_groups(&blocks);
        let pattern = schur_pattern(n_v, &blocks, &group_ptr, true)
            .unwrap()
            .symbolic;
        let straight: Vec<usize> = (0..nx * ny)
            .map(|e| usize::from(e % nx >= nx / 2))
            .collect();
        let straight_shared = shared_entries(n_v, &blocks, &group_ptr, &straight);
        assert_eq!(straight_shared, 41 + 40);
        for ranks in [2, 4] {
            let owners = group_owners(pattern.as_ref(), &blocks, &group_ptr, ranks).unwrap();
            let again = group_owners(pattern.as_ref(), &blocks, &group_ptr, ranks).unwrap();
            assert_eq!(owners, again, "{ranks} ranks");
            let mut counts = vec![0usize; ranks];
            for &r in &owners {
                counts[r] += 1;
            }
            let ideal = (nx * ny) as f64 / ranks as f64;
            for &c in &counts {
                assert!(
                    (c as f64) <= 1.03 * ideal + nx as f64 && c > 0,
                    "{ranks} ranks: {counts:?}"
                );
            }
            let shared = shared_entries(n_v, &blocks, &group_ptr, &owners);
            // Quarters: two straight cuts crossing, 2 × 81 − 1 entries.
            let bound = if ranks == 2 {
                2 * straight_shared
            } else {
                2 * (2 * straight_shared - 1)
            };
            assert!(
                shared <= bound,
                "{ranks} ranks: {shared} shared entries > {bound}"
            );
        }
    }
}
