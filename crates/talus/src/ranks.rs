//! The MPI ranks of a `mpirun -np N talus run` (cargo feature `mpi`, `docs/distributed.md`).
//! Every rank runs the same scene on the same model; only the Newton matrix's
//! factorization is split between them (MUMPS). Rank 0 writes the outputs.
//!
//! Without the feature, or outside `mpirun`, there is one rank.
use std::sync::OnceLock;

/// This process' rank and the number of ranks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ranks {
    pub rank: usize,
    pub size: usize,
}

impl Ranks {
    pub const ONE: Self = Self { rank: 0, size: 1 };

    /// Rank 0: the one that writes outputs and reports.
    pub fn is_root(&self) -> bool {
        self.rank == 0
    }

    /// More than one rank: the Newton matrices are factorized by MUMPS.
    pub fn distributed(&self) -> bool {
        self.size > 1
    }
}

static RANKS: OnceLock<Ranks> = OnceLock::new();

/// The ranks [`init`] found, else one.
pub fn ranks() -> Ranks {
    RANKS.get().copied().unwrap_or(Ranks::ONE)
}

/// Whether this process was started by an MPI launcher (OpenMPI's `mpirun`, or a PMI one
/// such as Slurm's `srun`).
pub fn launched_by_mpi() -> bool {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"]
        .iter()
        .any(|v| std::env::var_os(v).is_some())
}

/// MPI, initialized when this process was started by an MPI launcher; finalized on drop,
/// after every MUMPS instance is gone.
#[cfg(feature = "mpi")]
pub struct Mpi(#[allow(dead_code)] Option<mpi::environment::Universe>);

#[cfg(feature = "mpi")]
impl Mpi {
    /// Stops every rank with `code` (`MPI_Abort`): a rank that fails alone must not leave
    /// the others waiting in a collective call.
    pub fn abort(&self, code: i32) -> ! {
        use mpi::traits::Communicator;
        match &self.0 {
            Some(universe) => universe.world().abort(code),
            None => std::process::exit(code),
        }
    }
}

/// Initializes MPI if this process was started by an MPI launcher; records the ranks.
#[cfg(feature = "mpi")]
pub fn init() -> Result<Mpi, String> {
    use mpi::traits::Communicator;
    if !launched_by_mpi() {
        let _ = RANKS.set(Ranks::ONE);
        return Ok(Mpi(None));
    }
    let universe = mpi::initialize().ok_or("MPI was initialized twice")?;
    let world = universe.world();
    let ranks = Ranks {
        rank: world.rank() as usize,
        size: world.size() as usize,
    };
    let _ = RANKS.set(ranks);
    share_cores(ranks);
    Ok(Mpi(Some(universe)))
}

/// The ranks on one machine share its cores: each rank's thread pool gets its share
/// (`RAYON_NUM_THREADS` overrides), so that N ranks do not run N × cores threads.
#[cfg(feature = "mpi")]
fn share_cores(ranks: Ranks) {
    if std::env::var_os("RAYON_NUM_THREADS").is_some() || !ranks.distributed() {
        return;
    }
    let local = [
        "OMPI_COMM_WORLD_LOCAL_SIZE",
        "SLURM_NTASKS_PER_NODE",
        "MPI_LOCALNRANKS",
    ]
    .iter()
    .find_map(|v| std::env::var(v).ok()?.parse::<usize>().ok())
    .unwrap_or(ranks.size)
    .max(1);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let threads = (cores / local).max(1);
    if let Err(e) = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
    {
        tracing::warn!("{threads} threads per rank not set: {e}");
    }
}
