//! `K` factorized by MUMPS over `MPI_COMM_WORLD` (`docs/distributed.md`): every rank holds
//! the same `K` (the Newton iteration runs replicated) and hands MUMPS one block of its
//! columns (distributed assembled input), so that MUMPS' fronts, not `K`, are what the ranks
//! split. The solution comes back on every rank, bit for bit the host's.
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use talus_mumps::{Mumps, Statistics, Symmetry};

pub(crate) struct DistributedFactor {
    mumps: Mumps,
    /// This rank's CSC values: `values[first..last]`, whole columns.
    first: usize,
    last: usize,
    /// The last factorization succeeded.
    pub(crate) ready: bool,
    /// MUMPS' figures were logged (once per analysis).
    logged: bool,
}

impl DistributedFactor {
    /// MUMPS' analysis of `pattern` (its lower triangle when `symmetric`: LDLᵀ; else LU
    /// with the determinant's sign, the fold signature of `docs/solver.md`).
    pub(crate) fn analyse(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        symmetric: bool,
    ) -> Result<Self, String> {
        let symmetry = if symmetric {
            Symmetry::PositiveDefinite
        } else {
            Symmetry::Unsymmetric
        };
        let mut mumps = Mumps::new(symmetry, !symmetric).map_err(|e| e.to_string())?;
        let (rank, size) = mumps.rank();
        let col_ptr = pattern.col_ptr();
        let row_idx = pattern.row_idx();
        let n = pattern.ncols();
        // Whole columns, about nnz/size entries per rank.
        let nnz = col_ptr[n];
        let boundary = |r: usize| col_ptr.partition_point(|&p| p < nnz * r / size);
        let (c0, c1) = (boundary(rank).min(n), boundary(rank + 1).min(n));
        let (first, last) = (col_ptr[c0], col_ptr[c1]);
        let rows = &row_idx[first..last];
        let cols: Vec<usize> = (c0..c1)
            .flat_map(|c| std::iter::repeat_n(c, col_ptr[c + 1] - col_ptr[c]))
            .collect();
        mumps.analyse(n, rows, &cols).map_err(|e| e.to_string())?;
        Ok(Self {
            mumps,
            first,
            last,
            ready: false,
            logged: false,
        })
    }

    /// Factorizes `k` (collective) and returns its negative pivots: LDLᵀ's count, or for
    /// the LU 1 when the determinant is negative (an odd count of negative pivots), else 0.
    pub(crate) fn factorize(
        &mut self,
        k: SparseColMatRef<'_, usize, f64>,
    ) -> Result<usize, String> {
        self.ready = false;
        self.mumps
            .factorize(&k.val()[self.first..self.last])
            .map_err(|e| e.to_string())?;
        self.ready = true;
        let stats = self.mumps.statistics();
        if !self.logged {
            self.logged = true;
            tracing::info!(
                ranks = self.ranks(),
                ordering = stats.ordering,
                factor_entries = stats.factor_entries,
                flops = stats.flops,
                peak_megabytes_per_rank = stats.peak_megabytes_per_rank,
                megabytes = stats.megabytes,
                "MUMPS factorization"
            );
        }
        Ok(match stats.determinant_sign {
            Some(sign) => usize::from(sign < 0.0),
            None => stats.negative_pivots.max(0) as usize,
        })
    }

    /// `x ← K⁻¹ x` with the last factorization (collective).
    pub(crate) fn solve_in_place(&mut self, x: &mut [f64]) -> Result<(), String> {
        self.mumps.solve(x).map_err(|e| e.to_string())
    }

    pub(crate) fn statistics(&self) -> Statistics {
        self.mumps.statistics()
    }

    /// Ranks sharing the factors.
    pub(crate) fn ranks(&self) -> usize {
        self.mumps.rank().1
    }
}
