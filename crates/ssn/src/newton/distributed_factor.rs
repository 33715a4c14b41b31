//! `K` factorized by MUMPS over `MPI_COMM_WORLD` (`docs/distributed.md`): every rank
//! runs the same Newton iteration on its own points (`PointShare`) and hands MUMPS the
//! entries of `K` its own point groups give (`OwnedAssembly`, distributed assembled input); MUMPS splits its fronts between the
//! ranks, or on rank 0 alone for runs that repeat bit for bit (`FactorRanks::Host`). The
//! solution comes back on every rank, bit for bit the host's.
use talus_mumps::{Mumps, Placement, Statistics, Symmetry};

use crate::FactorRanks;

/// This rank and the number of ranks, once MPI is initialized.
pub(crate) fn world() -> Result<(usize, usize), String> {
    talus_mumps::world().ok_or_else(|| {
        "MPI is not initialized: run under mpirun (`mpirun -np 1 talus run …` for one rank)"
            .to_string()
    })
}

pub(crate) struct DistributedFactor {
    mumps: Mumps,
    /// The last factorization succeeded.
    pub(crate) ready: bool,
    /// MUMPS' figures were logged (once per analysis).
    logged: bool,
}

impl DistributedFactor {
    /// MUMPS' analysis of this rank's entries `(rows[k], cols[k])` of the `n × n` `K` (its
    /// lower triangle when `symmetric`: LDLᵀ; else LU with the determinant's sign, the
    /// fold signature of `docs/solver.md`), to be factorized by `ranks`.
    pub(crate) fn analyse(
        n: usize,
        rows: &[usize],
        cols: &[usize],
        symmetric: bool,
        ranks: FactorRanks,
    ) -> Result<Self, String> {
        let symmetry = if symmetric {
            Symmetry::PositiveDefinite
        } else {
            Symmetry::Unsymmetric
        };
        let placement = match ranks {
            FactorRanks::All => Placement::AllRanks,
            FactorRanks::Host => Placement::Host,
        };
        let mut mumps =
            Mumps::with_placement(symmetry, !symmetric, placement).map_err(|e| e.to_string())?;
        mumps.analyse(n, rows, cols).map_err(|e| e.to_string())?;
        Ok(Self {
            mumps,
            ready: false,
            logged: false,
        })
    }

    /// Factorizes with this rank's `values` (collective) and returns the negative pivots:
    /// LDLᵀ's count, or for the LU 1 when the determinant is negative (an odd count of
    /// negative pivots), else 0.
    pub(crate) fn factorize(&mut self, values: &[f64]) -> Result<usize, String> {
        self.ready = false;
        let start = std::time::Instant::now();
        self.mumps.factorize(values).map_err(|e| e.to_string())?;
        let seconds = start.elapsed().as_secs_f64();
        self.ready = true;
        let stats = self.mumps.statistics();
        if !self.logged {
            self.logged = true;
            tracing::info!(
                ranks = self.ranks(),
                placement = ?self.mumps.placement(),
                ordering = stats.ordering,
                factor_entries = stats.factor_entries,
                flops = stats.flops,
                peak_megabytes_per_rank = stats.peak_megabytes_per_rank,
                megabytes = stats.megabytes,
                seconds,
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
        self.mumps.factor_ranks()
    }
}
