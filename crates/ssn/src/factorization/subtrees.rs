//! Independent subtrees of a supernodal elimination tree, for a left-looking factorization
//! on several threads. A supernode is updated only by its descendants, so disjoint
//! subtrees factorize in parallel and their common ancestors (the top) after them. Each
//! supernode applies its updates in one fixed order whatever the schedule: the factors do
//! not depend on the thread count.
use std::ops::Range;

/// Subtrees are split (largest first, from the roots down) until the largest holds at
/// most this fraction of the work: enough tasks to keep two to four threads busy
/// (`docs/performance.md`, 'The LU on two threads': 1/16 was no faster, 1/32 slower).
const SPLIT: f64 = 1.0 / 8.0;
/// Below this many estimated flops the factorization stays on one thread. From a worker
/// of the pool (`talus_ssn::on_pool`) a task costs microseconds: the paper footing's
/// 7.7e6 (3 550 unknowns) gains on two threads (`docs/performance.md`, 'The paper
/// footing's iteration on two threads'); 1e7 was chosen when the solves forked from the
/// main thread, as they still do under an MPI launcher.
const PARALLEL_WORK: f64 = 2e6;

/// Which supernodes a parallel factorization takes as tasks, and which after them.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Schedule {
    /// Whole subtrees, each a contiguous, ascending range of supernodes.
    pub tasks: Vec<Range<usize>>,
    /// The supernodes in no task, ascending: each an ancestor of some task.
    pub top: Vec<usize>,
}

impl Schedule {
    /// From `parent[s]` (`None` for a root) and an estimate of each supernode's flops.
    /// Without parents above their children, subtrees numbered contiguously (a postorder)
    /// or enough work, everything is in the top: one thread.
    pub(crate) fn new(parent: &[Option<usize>], work: &[f64]) -> Self {
        let n = parent.len();
        let sequential = Self {
            tasks: Vec::new(),
            top: (0..n).collect(),
        };
        let mut subtree = work.to_vec();
        let mut first: Vec<usize> = (0..n).collect();
        let mut size = vec![1usize; n];
        let mut children = vec![Vec::new(); n];
        let mut roots = Vec::new();
        // Children come before their parent: each subtree is complete when added up.
        for s in 0..n {
            match parent[s] {
                Some(p) if p > s && p < n => {
                    subtree[p] += subtree[s];
                    first[p] = first[p].min(first[s]);
                    size[p] += size[s];
                    children[p].push(s);
                }
                Some(_) => return sequential,
                None => roots.push(s),
            }
        }
        if (0..n).any(|s| first[s] + size[s] != s + 1) {
            return sequential;
        }
        let total: f64 = roots.iter().map(|&r| subtree[r]).sum();
        if !(total >= PARALLEL_WORK) {
            return sequential;
        }
        let mut pool = roots;
        let mut top = Vec::new();
        while let Some((k, s)) = pool
            .iter()
            .copied()
            .enumerate()
            .max_by(|a, b| subtree[a.1].total_cmp(&subtree[b.1]))
        {
            // A chain is walked down only to its first branching: splitting a root of
            // one child gains no task, and its root then runs after every task.
            let chain = children[s].len() == 1 && pool.len() >= 2;
            if subtree[s] <= SPLIT * total || children[s].is_empty() || chain {
                break;
            }
            pool.swap_remove(k);
            top.push(s);
            pool.extend_from_slice(&children[s]);
        }
        if pool.len() < 2 {
            return sequential;
        }
        top.sort_unstable();
        let mut tasks: Vec<Range<usize>> = pool.iter().map(|&s| first[s]..s + 1).collect();
        tasks.sort_unstable_by_key(|r| r.start);
        Self { tasks, top }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two chains of 3 under one root (postorder 0 1 2 | 3 4 5 | 6): the root splits, the
    /// two chains are the tasks, and every supernode is in exactly one place.
    #[test]
    fn a_root_with_two_subtrees_gives_two_tasks() {
        let parent = [Some(1), Some(2), Some(6), Some(4), Some(5), Some(6), None];
        let s = Schedule::new(&parent, &[1e7; 7]);
        assert_eq!(s.tasks, vec![0..3, 3..6]);
        assert_eq!(s.top, vec![6]);
    }

    /// Little work, a chain, or a tree not in postorder: one thread, in order.
    #[test]
    fn small_chained_or_unordered_trees_stay_sequential() {
        let parent = [Some(1), Some(2), Some(6), Some(4), Some(5), Some(6), None];
        let sequential = Schedule {
            tasks: Vec::new(),
            top: (0..7).collect(),
        };
        assert_eq!(Schedule::new(&parent, &[1.0; 7]), sequential);
        let chain = [Some(1), Some(2), None];
        assert_eq!(
            Schedule::new(&chain, &[1e8; 3]).tasks,
            Vec::<Range<usize>>::new()
        );
        // 0 and 2 under 3, 1 under 4: subtree 3 = {0, 2, 3} is not contiguous.
        let unordered = [Some(3), Some(4), Some(3), Some(5), Some(5), None];
        assert_eq!(
            Schedule::new(&unordered, &[1e8; 6]).tasks,
            Vec::<Range<usize>>::new()
        );
    }
}
