//! The points one rank owns in a distributed solve (`LinearSolver::Distributed`,
//! `docs/distributed.md`, 'What runs where'): the Gauss points or particles of the point
//! groups METIS gives it (`newton/partition.rs`), the same groups whose share of `K` it
//! assembles. Within a Newton solve a rank evaluates, linearizes and back-substitutes its
//! own points only. What crosses ranks is velocity-sized (`Bᵀσ`, the Schur right-hand side)
//! or a scalar, each combined in rank order, so that every rank holds the same bits and
//! takes the same decisions. A solve ends with every rank holding every point's σ and z.

/// This rank's points and every rank's, for the reductions and the all-gather.
pub(crate) struct PointShare {
    /// Whether this rank owns each point.
    owned: Vec<bool>,
    /// Every rank's points, ascending: the all-gather's layout.
    by_rank: Vec<Vec<usize>>,
    rank: usize,
}

impl PointShare {
    /// Rank `rank`'s share when group `g` (points `group_ptr[g]..group_ptr[g + 1]`) belongs
    /// to rank `owners[g]`, of `size` ranks.
    pub(crate) fn new(group_ptr: &[usize], owners: &[usize], rank: usize, size: usize) -> Self {
        let n_points = group_ptr.last().copied().unwrap_or(0);
        let mut by_rank = vec![Vec::new(); size];
        for (g, &r) in owners.iter().enumerate() {
            by_rank[r].extend(group_ptr[g]..group_ptr[g + 1]);
        }
        let mut owned = vec![false; n_points];
        for &i in &by_rank[rank] {
            owned[i] = true;
        }
        Self {
            owned,
            by_rank,
            rank,
        }
    }

    /// Whether this rank owns each point.
    pub(crate) fn owned(&self) -> &[bool] {
        &self.owned
    }

    /// This rank's points, ascending.
    pub(crate) fn points(&self) -> &[usize] {
        &self.by_rank[self.rank]
    }

    /// This rank.
    pub(crate) fn rank(&self) -> usize {
        self.rank
    }

    /// The number of ranks.
    fn size(&self) -> usize {
        self.by_rank.len()
    }

    /// The ranks' partial sums `v` (velocity-sized) summed, the same bits on every rank:
    /// rank r sums the r-th slice of every rank's `v` in rank order, then the slices are
    /// gathered. No `MPI_Allreduce`, whose order is the MPI library's.
    pub(crate) fn sum_velocity(&self, v: &mut [f64]) {
        let size = self.size();
        if size == 1 {
            return;
        }
        let slices = slices(v.len(), size);
        let len = slices[self.rank].len();
        let mut received = vec![0.0; size * len];
        {
            let send_counts: Vec<i32> = slices.iter().map(|s| count(s.len())).collect();
            let send_displs: Vec<i32> = slices.iter().map(|s| count(s.start)).collect();
            let recv_counts = vec![count(len); size];
            let recv_displs: Vec<i32> = (0..size).map(|s| count(s * len)).collect();
            exchange(
                v,
                &send_counts,
                &send_displs,
                &mut received,
                &recv_counts,
                &recv_displs,
            );
        }
        let mut summed = vec![0.0; len];
        for (k, out) in summed.iter_mut().enumerate() {
            let mut acc = received[k];
            for s in 1..size {
                acc += received[s * len + k];
            }
            *out = acc;
        }
        let counts: Vec<i32> = slices.iter().map(|s| count(s.len())).collect();
        let displs: Vec<i32> = slices.iter().map(|s| count(s.start)).collect();
        all_gather(&summed, v, &counts, &displs);
    }

    /// The largest of the ranks' `x` (NaN if any is): the same on every rank.
    pub(crate) fn max(&self, x: f64) -> f64 {
        self.each(x).into_iter().fold(0.0f64, |m, y| {
            if m.is_nan() || y.is_nan() {
                f64::NAN
            } else {
                m.max(y)
            }
        })
    }

    /// The ranks' `x` summed in rank order: the same bits on every rank.
    pub(crate) fn sum(&self, x: f64) -> f64 {
        let each = self.each(x);
        each[1..].iter().fold(each[0], |acc, y| acc + y)
    }

    /// Whether `flag` holds on every rank.
    pub(crate) fn all(&self, flag: bool) -> bool {
        self.each(if flag { 1.0 } else { 0.0 })
            .iter()
            .all(|&f| f == 1.0)
    }

    /// The smallest of the ranks' `i` (`None` where a rank has none).
    pub(crate) fn first(&self, i: Option<usize>) -> Option<usize> {
        // Point indices are far below 2⁵³: exact as f64.
        self.each(i.map_or(-1.0, |i| i as f64))
            .into_iter()
            .filter(|&x| x >= 0.0)
            .map(|x| x as usize)
            .min()
    }

    /// Every rank's `x`, in rank order.
    fn each(&self, x: f64) -> Vec<f64> {
        let mut each = vec![x; self.size()];
        if self.size() > 1 {
            let ones = vec![1; self.size()];
            let displs: Vec<i32> = (0..self.size()).map(count).collect();
            all_gather(&[x], &mut each, &ones, &displs);
        }
        each
    }

    /// Every point's block of `v` (`D` entries a point) from the rank that owns it.
    pub(crate) fn gather_points<const D: usize>(&self, v: &mut [f64]) {
        let size = self.size();
        if size == 1 {
            return;
        }
        let mine: Vec<f64> = self
            .points()
            .iter()
            .flat_map(|&i| v[D * i..D * i + D].iter().copied())
            .collect();
        let counts: Vec<i32> = self.by_rank.iter().map(|p| count(D * p.len())).collect();
        let mut displs = Vec::with_capacity(size);
        let mut at = 0;
        for p in &self.by_rank {
            displs.push(count(at));
            at += D * p.len();
        }
        let mut all = vec![0.0; at];
        all_gather(&mine, &mut all, &counts, &displs);
        let mut k = 0;
        for points in &self.by_rank {
            for &i in points {
                v[D * i..D * i + D].copy_from_slice(&all[k..k + D]);
                k += D;
            }
        }
    }
}

/// `n` entries cut into `parts` contiguous slices, sizes within one.
fn slices(n: usize, parts: usize) -> Vec<std::ops::Range<usize>> {
    (0..parts)
        .map(|r| r * n / parts..(r + 1) * n / parts)
        .collect()
}

/// MPI's counts are `int`: a velocity vector of more than 2³¹ entries is far beyond any
/// rank's memory (16 GB a copy).
fn count(n: usize) -> i32 {
    i32::try_from(n).expect("a count below 2^31 (16 GB of f64 a message)")
}

#[cfg(feature = "mpi")]
fn exchange(
    send: &[f64],
    send_counts: &[i32],
    send_displs: &[i32],
    receive: &mut [f64],
    receive_counts: &[i32],
    receive_displs: &[i32],
) {
    use mpi::datatype::{Partition, PartitionMut};
    use mpi::traits::CommunicatorCollectives;
    let world = mpi::topology::SimpleCommunicator::world();
    let send = Partition::new(send, send_counts, send_displs);
    let mut receive = PartitionMut::new(receive, receive_counts, receive_displs);
    world.all_to_all_varcount_into(&send, &mut receive);
}

#[cfg(feature = "mpi")]
fn all_gather(send: &[f64], receive: &mut [f64], counts: &[i32], displs: &[i32]) {
    use mpi::datatype::PartitionMut;
    use mpi::traits::CommunicatorCollectives;
    let world = mpi::topology::SimpleCommunicator::world();
    let mut receive = PartitionMut::new(receive, counts, displs);
    world.all_gather_varcount_into(send, &mut receive);
}

// Without MPI there is one rank: a share of one rank never communicates.
#[cfg(not(feature = "mpi"))]
fn exchange(_: &[f64], _: &[i32], _: &[i32], _: &mut [f64], _: &[i32], _: &[i32]) {
    unreachable!("one rank without the feature `mpi`")
}

#[cfg(not(feature = "mpi"))]
fn all_gather(_: &[f64], _: &mut [f64], _: &[i32], _: &[i32]) {
    unreachable!("one rank without the feature `mpi`")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Five groups of 2, 1, 3, 2 and 1 points on 3 ranks: every point owned by exactly one
    /// rank, each rank's points its groups' in ascending order.
    #[test]
    fn every_point_is_owned_once() {
        let group_ptr = [0, 2, 3, 6, 8, 9];
        let owners = [2, 0, 2, 1, 0];
        let shares: Vec<PointShare> = (0..3)
            .map(|r| PointShare::new(&group_ptr, &owners, r, 3))
            .collect();
        assert_eq!(shares[0].points(), &[2, 8]);
        assert_eq!(shares[1].points(), &[6, 7]);
        assert_eq!(shares[2].points(), &[0, 1, 3, 4, 5]);
        for i in 0..9 {
            let owners: Vec<usize> = (0..3).filter(|&r| shares[r].owned()[i]).collect();
            assert_eq!(owners.len(), 1, "point {i}: owned by {owners:?}");
        }
    }

    /// The velocity slices cover 0..n once, sizes within one.
    #[test]
    fn slices_cover_the_vector_once() {
        for n in [0, 1, 5, 17, 100] {
            for parts in 1..=7 {
                let s = slices(n, parts);
                assert_eq!(s[0].start, 0);
                assert_eq!(s[parts - 1].end, n);
                for w in s.windows(2) {
                    assert_eq!(w[0].end, w[1].start);
                }
                let (lo, hi) = s.iter().fold((usize::MAX, 0), |(lo, hi), r| {
                    (lo.min(r.len()), hi.max(r.len()))
                });
                assert!(hi - lo <= 1, "n {n}, parts {parts}: {s:?}");
            }
        }
    }

    /// One rank: the reductions are the identity, the gather leaves `v` as it is.
    #[test]
    fn one_rank_keeps_its_values() {
        let share = PointShare::new(&[0, 2, 3], &[0, 0], 0, 1);
        let mut v = vec![1.5, -2.0, 3.0];
        share.sum_velocity(&mut v);
        share.gather_points::<1>(&mut v);
        assert_eq!(v, [1.5, -2.0, 3.0]);
        assert!(share.max(f64::NAN).is_nan());
        assert_eq!(share.sum(2.5), 2.5);
        assert!(share.all(true) && !share.all(false));
        assert_eq!(share.first(Some(4)), Some(4));
        assert_eq!(share.first(None), None);
    }
}
