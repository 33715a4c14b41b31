//! The MPI ranks of a `mpirun -np N talus run` (cargo feature `mpi`, `docs/distributed.md`).
//! Every rank runs the same scene on the same model; the Newton solve's work on the
//! points, the Newton matrix's assembly and its factorization are split between them
//! (METIS, MUMPS). Rank 0 writes the outputs, every
//! rank its piece of each VTU.
//!
//! Without the feature, or outside `mpirun`, there is one rank.
use std::fmt::Display;
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

static ROOT_FOLDER: OnceLock<std::path::PathBuf> = OnceLock::new();

/// Records rank 0's output folder on every rank (the `talus` binary, before a run): each
/// rank writes its piece of the field snapshots there (`docs/distributed.md`, 'Outputs').
pub fn set_root_folder(out: std::path::PathBuf) {
    let _ = ROOT_FOLDER.set(out);
}

/// Rank 0's output folder, once [`set_root_folder`] recorded it.
pub fn root_folder() -> Option<&'static std::path::Path> {
    ROOT_FOLDER.get().map(|p| p.as_path())
}

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

/// A failure this rank may meet alone (a file it writes, a lock, a full disk): with more
/// than one rank, prints it and stops every rank (`MPI_Abort`, exit code 5) at once,
/// before this rank drops a MUMPS instance (whose end the others would never join).
pub fn local_failure(e: &dyn Display) {
    let r = ranks();
    if !r.distributed() {
        return;
    }
    eprintln!("rank {}: error: {e}", r.rank);
    #[cfg(feature = "mpi")]
    {
        use mpi::traits::Communicator;
        mpi::topology::SimpleCommunicator::world().abort(5);
    }
}

/// Whether `flag` is set on any rank (collective with more than one rank: every rank
/// must call it at the same point, e.g. after each step, which they all take).
pub fn any(flag: bool) -> bool {
    #[cfg(feature = "mpi")]
    if ranks().distributed() {
        use mpi::collective::SystemOperation;
        use mpi::traits::CommunicatorCollectives;
        let mut any = 0u8;
        mpi::topology::SimpleCommunicator::world().all_reduce_into(
            &u8::from(flag),
            &mut any,
            SystemOperation::max(),
        );
        return any != 0;
    }
    flag
}

/// The smallest rank on which `flag` is set, if any (collective as [`any`]).
pub fn first(flag: bool) -> Option<usize> {
    #[cfg(feature = "mpi")]
    if ranks().distributed() {
        use mpi::collective::SystemOperation;
        use mpi::traits::CommunicatorCollectives;
        let mine = if flag { ranks().rank as u64 } else { u64::MAX };
        let mut first = u64::MAX;
        mpi::topology::SimpleCommunicator::world().all_reduce_into(
            &mine,
            &mut first,
            SystemOperation::min(),
        );
        return (first != u64::MAX).then_some(first as usize);
    }
    flag.then_some(ranks().rank)
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
    if ranks.distributed() {
        // A panic (a bug) on one rank stops every rank instead of leaving them in MUMPS.
        let report = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            report(info);
            mpi::topology::SimpleCommunicator::world().abort(101);
        }));
    }
    Ok(Mpi(Some(universe)))
}

/// The ranks on one machine share its cores: each rank's thread pool gets its share
/// (`RAYON_NUM_THREADS` overrides), so that N ranks do not run N × cores threads.
#[cfg(feature = "mpi")]
fn share_cores(ranks: Ranks) {
    if std::env::var_os("RAYON_NUM_THREADS").is_some() || !ranks.distributed() {
        return;
    }
    // Slurm writes `8(x2)`: the leading count.
    let leading = |v: String| -> Option<usize> {
        let digits: String = v.chars().take_while(char::is_ascii_digit).collect();
        digits.parse().ok()
    };
    let local = [
        "OMPI_COMM_WORLD_LOCAL_SIZE",
        "SLURM_NTASKS_PER_NODE",
        "MPI_LOCALNRANKS",
    ]
    .iter()
    .find_map(|v| leading(std::env::var(v).ok()?))
    .unwrap_or(ranks.size)
    .max(1);
    // A rank bound to some cores (mpirun's default for 2 ranks, `srun --cpus-per-task`)
    // sees only those: they are its own. Unbound, it sees the machine's, shared.
    let visible = std::thread::available_parallelism().map_or(1, |n| n.get());
    let machine = std::fs::read_to_string("/proc/cpuinfo")
        .map(|s| s.lines().filter(|l| l.starts_with("processor")).count())
        .unwrap_or(visible);
    let threads = if visible < machine {
        visible
    } else {
        (visible / local).max(1)
    };
    if let Err(e) = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
    {
        tracing::warn!("{threads} threads per rank not set: {e}");
    }
}
