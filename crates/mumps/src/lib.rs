//! A thin handle on MUMPS' MPI solver (`dmumps`, Debian's `libmumps-dev`), as Talus'
//! distributed factorization of the Newton matrix uses it (`docs/distributed.md`):
//!
//! - distributed assembled input (ICNTL(18) = 3): every rank passes its own entries,
//!   duplicates summed by MUMPS;
//! - the analysis once per pattern ([`Mumps::analyse`]), the numeric factorization per
//!   call ([`Mumps::factorize`]), solves on it ([`Mumps::solve`]);
//! - LU for unsymmetric matrices, LDLᵀ for symmetric positive definite or indefinite ones;
//! - a centralized right-hand side and solution (ICNTL(20) = ICNTL(21) = 0), broadcast to
//!   every rank: Talus keeps velocity-sized vectors on every rank;
//! - the factorization over every rank ([`Placement::AllRanks`]) or, for the same bits on
//!   every run, on rank 0 alone from the entries every rank sends it ([`Placement::Host`]).
//!
//! Every method is collective over `MPI_COMM_WORLD`: all ranks call it, in the same order.
//! MPI must be initialized first (`mpi::initialize`), and finalized only after the last
//! [`Mumps`] is dropped.
//!
//! No Rust crate wraps MUMPS' MPI version (`docs/distributed.md`, 'What was checked'); the
//! C handle in `csrc/shim.c` keeps `DMUMPS_STRUC_C`'s layout in MUMPS' own header.
mod ffi;

use std::os::raw::c_int;
use std::ptr::NonNull;

use mpi::datatype::PartitionMut;
use mpi::topology::SimpleCommunicator;
use mpi::traits::{Communicator, Equivalence, Root};

/// Which factorization MUMPS computes (its `SYM`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Symmetry {
    /// LU with threshold pivoting (`SYM = 0`).
    Unsymmetric,
    /// LDLᵀ without pivoting (`SYM = 1`); pass one triangle.
    PositiveDefinite,
    /// LDLᵀ with pivoting (`SYM = 2`); pass one triangle.
    Symmetric,
}

/// Which ranks factorize.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Placement {
    /// MUMPS over every rank of `MPI_COMM_WORLD`: the factors' memory and flops are split
    /// between them. A front adds the contributions other ranks send it in the order they
    /// arrive, so two runs differ in the last bits.
    #[default]
    AllRanks,
    /// MUMPS on rank 0 alone (`MPI_COMM_SELF`), on the entries every rank sends it, gathered
    /// in rank order: the same ranks and entries give the same bits on every run. The
    /// factorization's memory and time are rank 0's; the other ranks wait for it.
    Host,
}

/// MUMPS' code for `MPI_COMM_WORLD` in `comm_fortran` (its C examples' `USE_COMM_WORLD`).
const COMM_WORLD: c_int = -987_654;

/// INFOG and RINFOG entries a host placement shares with the other ranks after each call
/// (those [`Statistics`] and the errors read: INFOG(1..=29), RINFOG(1..=12)).
const SHARED_INFOG: usize = 40;
const SHARED_RINFOG: usize = 20;

/// A step of MUMPS that failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    Initialize,
    Analysis,
    Factorization,
    Solve,
}

impl std::fmt::Display for Phase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Phase::Initialize => "initialization",
            Phase::Analysis => "analysis",
            Phase::Factorization => "factorization",
            Phase::Solve => "solve",
        })
    }
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MumpsError {
    #[error("MPI is not initialized: call mpi::initialize before building a MUMPS solver")]
    NoMpi,
    #[error("MUMPS {phase} failed: INFOG(1) = {infog1}, INFOG(2) = {infog2} ({meaning})")]
    Failed {
        phase: Phase,
        infog1: i32,
        infog2: i32,
        meaning: &'static str,
    },
    #[error("{field} = {value}: {reason}")]
    Invalid {
        field: &'static str,
        value: String,
        reason: &'static str,
    },
}

/// MUMPS' figures for the last analysis and factorization, the same on every rank
/// (MUMPS' user guide, §6.1: INFOG, RINFOG).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Statistics {
    /// Entries in the factors as the analysis estimated them, summed over ranks (INFOG(20)).
    pub estimated_factor_entries: i64,
    /// Entries in the factors, summed over ranks (INFOG(29), after a factorization).
    pub factor_entries: i64,
    /// Floating-point operations of the elimination (RINFOG(3)).
    pub flops: f64,
    /// The ordering the analysis used (INFOG(7): 0 AMD, 2 AMF, 3 SCOTCH, 4 PORD, 5 METIS,
    /// 6 QAMD, 7 automatic choice).
    pub ordering: i32,
    /// Negative pivots (INFOG(12); `Symmetry::Symmetric` and `PositiveDefinite` only, the
    /// off-diagonal pivots for `Unsymmetric`). Without those of a root node factorized by
    /// ScaLAPACK (ICNTL(13) = 0, the default, on large matrices): then a lower bound.
    pub negative_pivots: i32,
    /// Largest memory a rank used in the factorization, in MB (INFOG(21)).
    pub peak_megabytes_per_rank: i32,
    /// Memory of all ranks in the factorization, in MB (INFOG(22)).
    pub megabytes: i32,
    /// The determinant's sign, when asked for (`Mumps::new`'s `determinant`): `-1`, `0` or
    /// `1` (RINFOG(12)'s sign).
    pub determinant_sign: Option<f64>,
}

/// MUMPS' counters of entries: a negative value counts millions (user guide, INFOG(20)).
fn entries(v: c_int) -> i64 {
    if v < 0 {
        -(v as i64) * 1_000_000
    } else {
        v as i64
    }
}

/// What MUMPS' most frequent INFOG(1) codes mean (user guide, §8).
fn meaning(infog1: i32) -> &'static str {
    match infog1 {
        -5 | -7 | -13 => "an allocation failed: too little memory on some rank",
        -6 => "the matrix is structurally singular",
        -8 | -9 | -14 | -15 | -17 | -20 => {
            "the workspace estimated by the analysis was too small (ICNTL(14))"
        }
        -10 => "the matrix is numerically singular",
        -16 => "N is out of range",
        -22 => "an array MUMPS needs was not given",
        -38 => "the parallel analysis needs PT-SCOTCH or ParMETIS, which this MUMPS lacks",
        -40 => "a matrix declared positive definite has a non-positive pivot",
        _ => "see MUMPS' user guide, section 8",
    }
}

/// The distributed factorization of one sparse `n × n` matrix. Neither `Send` nor `Sync`:
/// MPI is initialized for one thread (`MPI_THREAD_SINGLE`), so every call, collective,
/// stays on the thread that initialized MPI. The checks of a call's arguments are this
/// rank's: give every rank valid ones, or the others wait in the call.
pub struct Mumps {
    /// MUMPS' instance: on every rank, or on rank 0 alone ([`Placement::Host`]).
    id: Option<NonNull<ffi::Struc>>,
    world: SimpleCommunicator,
    placement: Placement,
    symmetry: Symmetry,
    n: usize,
    /// The 1-based entries MUMPS reads (it keeps pointers to them between calls): this
    /// rank's, or on a host all ranks' in rank order.
    rows: Vec<c_int>,
    cols: Vec<c_int>,
    values: Vec<f64>,
    /// Entries this rank gives ([`Mumps::factorize`]'s `values`).
    local_entries: usize,
    /// On a host: each rank's count of entries and its offset in `rows`, `cols`, `values`.
    counts: Vec<c_int>,
    displs: Vec<c_int>,
    /// On a host placement: INFOG and RINFOG as rank 0's instance left them, on every rank.
    infog: [c_int; SHARED_INFOG],
    rinfog: [f64; SHARED_RINFOG],
    analysed: bool,
    factorized: bool,
    determinant: bool,
}

/// ICNTL(14): the analysis' workspace estimate is raised by this percentage, then doubled
/// on each factorization refused for a too small workspace.
const WORKSPACE_PERCENT: c_int = 30;
const WORKSPACE_RETRIES: usize = 4;

impl Mumps {
    /// A MUMPS instance over every rank of `MPI_COMM_WORLD` (collective). `determinant`:
    /// compute the determinant's sign with each factorization (ICNTL(33)).
    pub fn new(symmetry: Symmetry, determinant: bool) -> Result<Self, MumpsError> {
        Self::with_placement(symmetry, determinant, Placement::AllRanks)
    }

    /// A MUMPS instance factorizing where `placement` says (collective).
    pub fn with_placement(
        symmetry: Symmetry,
        determinant: bool,
        placement: Placement,
    ) -> Result<Self, MumpsError> {
        if !mpi::environment::is_initialized() {
            return Err(MumpsError::NoMpi);
        }
        let sym = match symmetry {
            Symmetry::Unsymmetric => 0,
            Symmetry::PositiveDefinite => 1,
            Symmetry::Symmetric => 2,
        };
        let world = SimpleCommunicator::world();
        let comm = match placement {
            Placement::AllRanks => Some(COMM_WORLD),
            // SAFETY: MPI is initialized; MPI_COMM_SELF's Fortran handle is a plain integer.
            Placement::Host if world.rank() == 0 => {
                Some(unsafe { mpi::ffi::RSMPI_Comm_c2f(mpi::ffi::RSMPI_COMM_SELF) })
            }
            Placement::Host => None,
        };
        let mut id = None;
        let mut created = true;
        if let Some(comm) = comm {
            id = NonNull::new(unsafe { ffi::talus_dmumps_init(sym, comm) });
            created = id.is_some();
        }
        let mut mumps = Self {
            id,
            world,
            placement,
            symmetry,
            n: 0,
            rows: Vec::new(),
            cols: Vec::new(),
            values: Vec::new(),
            local_entries: 0,
            counts: Vec::new(),
            displs: Vec::new(),
            infog: [0; SHARED_INFOG],
            rinfog: [0.0; SHARED_RINFOG],
            analysed: false,
            factorized: false,
            determinant,
        };
        // An instance that could not be allocated reads as MUMPS' own allocation failure;
        // a host's is shared with the other ranks.
        if !created {
            mumps.infog[0] = -13;
        }
        mumps.share_info();
        mumps.check(Phase::Initialize)?;
        // Silent: errors come back as `MumpsError`, figures as `Statistics`.
        for i in 1..=3 {
            mumps.set_icntl(i, 0);
        }
        mumps.set_icntl(4, 0);
        mumps.set_icntl(5, 0); // assembled input
        mumps.set_icntl(14, WORKSPACE_PERCENT);
        mumps.set_icntl(18, 3); // distributed: each rank its own entries
        mumps.set_icntl(20, 0); // dense right-hand side on the host
        mumps.set_icntl(21, 0); // solution on the host, then broadcast
        if determinant {
            mumps.set_icntl(33, 1);
        }
        Ok(mumps)
    }

    /// This rank's number and the number of ranks.
    pub fn rank(&self) -> (usize, usize) {
        (self.world.rank() as usize, self.world.size() as usize)
    }

    pub fn placement(&self) -> Placement {
        self.placement
    }

    /// Ranks that hold factors: all of them, or 1 on a host placement.
    pub fn factor_ranks(&self) -> usize {
        match self.placement {
            Placement::AllRanks => self.world.size() as usize,
            Placement::Host => 1,
        }
    }

    pub fn symmetry(&self) -> Symmetry {
        self.symmetry
    }

    /// On a rank with an instance; a host's other ranks have no controls to set.
    fn set_icntl(&mut self, i: c_int, value: c_int) {
        if let Some(id) = self.id {
            unsafe { ffi::talus_dmumps_set_icntl(id.as_ptr(), i, value) }
        }
    }

    /// Runs MUMPS' `job` on this rank's instance, if it has one (a host's other ranks do
    /// not take part).
    fn job(&mut self, job: c_int) {
        if let Some(id) = self.id {
            unsafe { ffi::talus_dmumps_job(id.as_ptr(), job) };
        }
    }

    /// INFOG(i) as this rank's instance left it (0 without one).
    fn raw_infog(&self, i: c_int) -> c_int {
        self.id
            .map_or(0, |id| unsafe { ffi::talus_dmumps_infog(id.as_ptr(), i) })
    }

    /// On a host placement, rank 0's INFOG and RINFOG to every rank (collective), so that
    /// all return the same errors and figures; over all ranks MUMPS shares them itself.
    fn share_info(&mut self) {
        if self.placement != Placement::Host {
            return;
        }
        if let Some(id) = self.id {
            for i in 0..SHARED_INFOG {
                self.infog[i] = unsafe { ffi::talus_dmumps_infog(id.as_ptr(), i as c_int + 1) };
            }
            for i in 0..SHARED_RINFOG {
                self.rinfog[i] = unsafe { ffi::talus_dmumps_rinfog(id.as_ptr(), i as c_int + 1) };
            }
        }
        let host = self.world.process_at_rank(0);
        host.broadcast_into(&mut self.infog[..]);
        host.broadcast_into(&mut self.rinfog[..]);
    }

    /// Sets ICNTL(i) (MUMPS' user guide, §6.1) before [`analyse`](Self::analyse); the
    /// entries this handle relies on (5, 18, 20, 21) are refused.
    pub fn set_control(&mut self, i: usize, value: i32) -> Result<(), MumpsError> {
        if !(1..=60).contains(&i) || [5, 18, 20, 21].contains(&i) {
            return Err(MumpsError::Invalid {
                field: "icntl",
                value: i.to_string(),
                reason: "not in 1..=60, or fixed by this handle (5, 18, 20, 21)",
            });
        }
        self.set_icntl(i as c_int, value);
        Ok(())
    }

    fn infog(&self, i: c_int) -> c_int {
        match (self.placement, self.id) {
            (Placement::AllRanks, Some(id)) => unsafe { ffi::talus_dmumps_infog(id.as_ptr(), i) },
            _ => self.infog[i as usize - 1],
        }
    }

    fn rinfog(&self, i: c_int) -> f64 {
        match (self.placement, self.id) {
            (Placement::AllRanks, Some(id)) => unsafe { ffi::talus_dmumps_rinfog(id.as_ptr(), i) },
            _ => self.rinfog[i as usize - 1],
        }
    }

    fn check(&self, phase: Phase) -> Result<(), MumpsError> {
        let infog1 = self.infog(1);
        if infog1 < 0 {
            return Err(MumpsError::Failed {
                phase,
                infog1,
                infog2: self.infog(2),
                meaning: meaning(infog1),
            });
        }
        Ok(())
    }

    /// The analysis of this rank's entries `(rows[k], cols[k])`, 0-based, of an `n × n`
    /// matrix (one triangle when symmetric). Collective; call again for a new pattern.
    pub fn analyse(&mut self, n: usize, rows: &[usize], cols: &[usize]) -> Result<(), MumpsError> {
        let too_large = |field, value: usize| MumpsError::Invalid {
            field,
            value: value.to_string(),
            reason: "exceeds MUMPS' 32-bit indices",
        };
        if n == 0 || n > c_int::MAX as usize {
            return Err(too_large("n", n));
        }
        if rows.len() != cols.len() {
            return Err(MumpsError::Invalid {
                field: "cols",
                value: cols.len().to_string(),
                reason: "not as many column indices as row indices",
            });
        }
        if let Some(k) = rows.iter().zip(cols).position(|(&i, &j)| i >= n || j >= n) {
            return Err(MumpsError::Invalid {
                field: "rows/cols",
                value: format!("({}, {}) at entry {k}", rows[k], cols[k]),
                reason: "an index outside the matrix",
            });
        }
        self.n = n;
        self.analysed = false;
        self.factorized = false;
        self.local_entries = rows.len();
        let local_rows: Vec<c_int> = rows.iter().map(|&i| i as c_int + 1).collect();
        let local_cols: Vec<c_int> = cols.iter().map(|&j| j as c_int + 1).collect();
        match self.placement {
            Placement::AllRanks => {
                self.rows = local_rows;
                self.cols = local_cols;
                self.values = vec![0.0; rows.len()];
            }
            Placement::Host => {
                let total = self.gather_counts()?;
                let host_len = if self.world.rank() == 0 { total } else { 0 };
                self.rows = vec![0; host_len];
                self.cols = vec![0; host_len];
                self.values = vec![0.0; host_len];
                let (counts, displs) = (&self.counts[..], &self.displs[..]);
                gather_to_host(&self.world, counts, displs, &local_rows, &mut self.rows);
                gather_to_host(&self.world, counts, displs, &local_cols, &mut self.cols);
            }
        }
        if let Some(id) = self.id {
            unsafe {
                ffi::talus_dmumps_set_local_matrix(
                    id.as_ptr(),
                    n as c_int,
                    self.rows.len() as i64,
                    self.rows.as_mut_ptr(),
                    self.cols.as_mut_ptr(),
                    self.values.as_mut_ptr(),
                );
            }
        }
        self.job(1);
        self.share_info();
        self.check(Phase::Analysis)?;
        self.analysed = true;
        Ok(())
    }

    /// The numeric factorization with this rank's `values`, in the order of
    /// [`analyse`](Self::analyse)'s entries. Collective.
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), MumpsError> {
        if !self.analysed {
            return Err(MumpsError::Invalid {
                field: "analyse",
                value: "not called".into(),
                reason: "factorize needs the analysis of the pattern first",
            });
        }
        if values.len() != self.local_entries {
            return Err(MumpsError::Invalid {
                field: "values",
                value: values.len().to_string(),
                reason: "not one value per entry given to analyse",
            });
        }
        self.factorized = false;
        match self.placement {
            Placement::AllRanks => self.values.copy_from_slice(values),
            Placement::Host => {
                let (counts, displs) = (&self.counts[..], &self.displs[..]);
                gather_to_host(&self.world, counts, displs, values, &mut self.values);
            }
        }
        if let Some(id) = self.id {
            unsafe { ffi::talus_dmumps_set_local_values(id.as_ptr(), self.values.as_mut_ptr()) };
        }
        // Every rank with an instance retries alike: MUMPS gives INFOG(1) to all of them.
        let mut percent = WORKSPACE_PERCENT;
        for attempt in 0..=WORKSPACE_RETRIES {
            self.job(2);
            let infog1 = self.raw_infog(1);
            // -8, -9, -14, -15, -17, -20: the analysis' workspace estimate was exceeded
            // (pivoting grew the fronts); the user guide's remedy is a larger ICNTL(14).
            let workspace = matches!(infog1, -8 | -9 | -14 | -15 | -17 | -20);
            if !workspace || attempt == WORKSPACE_RETRIES {
                break;
            }
            percent *= 2;
            self.set_icntl(14, percent);
        }
        self.share_info();
        self.check(Phase::Factorization)?;
        self.factorized = true;
        Ok(())
    }

    /// `x ← A⁻¹ x` with the last factorization. Collective; the host's `x` is the
    /// right-hand side, and every rank receives the solution.
    pub fn solve(&mut self, x: &mut [f64]) -> Result<(), MumpsError> {
        if !self.factorized {
            return Err(MumpsError::Invalid {
                field: "factorize",
                value: "no successful factorization".into(),
                reason: "solve needs a factorization",
            });
        }
        if x.len() != self.n {
            return Err(MumpsError::Invalid {
                field: "x",
                value: x.len().to_string(),
                reason: "not the matrix's size",
            });
        }
        if let Some(id) = self.id {
            unsafe {
                ffi::talus_dmumps_set_rhs(id.as_ptr(), x.as_mut_ptr());
                ffi::talus_dmumps_job(id.as_ptr(), 3);
                // MUMPS must not keep a pointer into the caller's slice.
                ffi::talus_dmumps_set_rhs(id.as_ptr(), std::ptr::null_mut());
            }
        }
        self.share_info();
        self.check(Phase::Solve)?;
        self.world.process_at_rank(0).broadcast_into(x);
        Ok(())
    }

    /// The last analysis' and factorization's figures.
    pub fn statistics(&self) -> Statistics {
        let determinant_sign = self.determinant.then(|| {
            let m = self.rinfog(12);
            if m > 0.0 {
                1.0
            } else if m < 0.0 {
                -1.0
            } else {
                0.0
            }
        });
        Statistics {
            estimated_factor_entries: entries(self.infog(20)),
            factor_entries: entries(self.infog(29)),
            flops: self.rinfog(3),
            ordering: self.infog(7),
            negative_pivots: self.infog(12),
            peak_megabytes_per_rank: self.infog(21),
            megabytes: self.infog(22),
            determinant_sign,
        }
    }
}

impl Mumps {
    /// On a host placement: every rank's count of entries to rank 0, as the gathers'
    /// counts and offsets (collective). Refused on every rank when their sum exceeds MPI's
    /// 32-bit offsets.
    fn gather_counts(&mut self) -> Result<usize, MumpsError> {
        let host = self.world.process_at_rank(0);
        let mine = self.local_entries as i64;
        let root = self.world.rank() == 0;
        let mut counts = vec![0i64; if root { self.world.size() as usize } else { 0 }];
        if root {
            host.gather_into_root(&mine, &mut counts[..]);
        } else {
            host.gather_into(&mine);
        }
        let mut total: i64 = counts.iter().sum();
        host.broadcast_into(&mut total);
        if total > c_int::MAX as i64 {
            return Err(MumpsError::Invalid {
                field: "rows",
                value: format!("{total} entries over all ranks"),
                reason:
                    "more than a gather to rank 0 addresses (2^31 - 1): use Placement::AllRanks",
            });
        }
        self.counts = counts.iter().map(|&c| c as c_int).collect();
        self.displs = self
            .counts
            .iter()
            .scan(0, |offset, &c| {
                let at = *offset;
                *offset += c;
                Some(at)
            })
            .collect();
        Ok(total as usize)
    }
}

/// This rank's `local` entries into rank 0's `all`, at the offsets `displs` (collective;
/// `counts` and `displs` are read on rank 0 only). MPI places each rank's part at its
/// offset, whatever the order messages arrive in.
fn gather_to_host<T: Equivalence>(
    world: &SimpleCommunicator,
    counts: &[c_int],
    displs: &[c_int],
    local: &[T],
    all: &mut [T],
) {
    let host = world.process_at_rank(0);
    if world.rank() == 0 {
        let mut partition = PartitionMut::new(all, counts, displs);
        host.gather_varcount_into_root(local, &mut partition);
    } else {
        host.gather_varcount_into(local);
    }
}

impl Drop for Mumps {
    fn drop(&mut self) {
        // Collective too: every rank with an instance drops it at the same point.
        if let Some(id) = self.id {
            unsafe { ffi::talus_dmumps_end(id.as_ptr()) }
        }
    }
}

/// This rank and the number of ranks of `MPI_COMM_WORLD`, once MPI is initialized.
pub fn world() -> Option<(usize, usize)> {
    if !mpi::environment::is_initialized() {
        return None;
    }
    let world = SimpleCommunicator::world();
    Some((world.rank() as usize, world.size() as usize))
}

/// `mpirun` flags the tests and benchmarks launch with: OpenMPI refuses root without
/// `--allow-run-as-root` (CI containers run as root) and more ranks than cores without
/// `--oversubscribe`.
pub const MPIRUN_FLAGS: &[&str] = &["--allow-run-as-root", "--oversubscribe"];

/// For a test program that checks itself on several ranks: `Some(code)` when this process
/// was not started by `mpirun` (then it has run itself under `mpirun -np n` for each of
/// `ranks`, and `code` says whether all succeeded), `None` under `mpirun` (run the checks).
pub fn relaunch_under_mpirun(name: &str, ranks: &[usize]) -> Option<std::process::ExitCode> {
    if std::env::var_os("OMPI_COMM_WORLD_SIZE").is_some() || std::env::var_os("PMI_SIZE").is_some()
    {
        return None;
    }
    let exe = std::env::current_exe().expect("the test's own path");
    let mut ok = true;
    for n in ranks {
        let status = std::process::Command::new("mpirun")
            .args(MPIRUN_FLAGS)
            .args(["-np", &n.to_string()])
            .arg(&exe)
            .status()
            .expect("mpirun runs (Debian's openmpi-bin)");
        eprintln!("{name} on {n} rank(s): {status}");
        ok &= status.success();
    }
    Some(if ok {
        std::process::ExitCode::SUCCESS
    } else {
        std::process::ExitCode::FAILURE
    })
}
