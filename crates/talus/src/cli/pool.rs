//! The thread a command runs on: a worker of rayon's global pool.
//!
//! A Newton iteration forks tens of rayon regions over the stress points (`talus_ssn`).
//! From a thread outside the pool each one injects its job and puts the caller to sleep
//! until a worker wakes it; from a worker it is a push onto that worker's own deque, and
//! the caller works too. The paper footing on 2 threads: 3.4–3.7 s from the main thread,
//! 2.75–3.0 s from a worker (2026-11-28).

/// The main thread's stack (Linux' default 8 MiB), not a spawned thread's 2 MiB: the
/// command's recursion depth stays what it was on the main thread.
const STACK_BYTES: usize = 8 << 20;

/// Runs `command` on a worker of rayon's global pool, this thread waiting for it.
///
/// Under an MPI launcher the command stays on this thread: MPI is initialized for it alone
/// (`MPI_THREAD_SINGLE`, `talus_mumps`), and `ranks::init` has sized the pool already.
pub fn on_pool<R: Send>(command: impl FnOnce() -> R + Send) -> R {
    if talus::ranks::launched_by_mpi() {
        return command();
    }
    // RAYON_NUM_THREADS still sets the size; a pool built before (a second call) is kept.
    let _ = rayon::ThreadPoolBuilder::new()
        .stack_size(STACK_BYTES)
        .build_global();
    rayon::scope(|_| command())
}
