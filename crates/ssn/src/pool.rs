//! The thread a computation calls the solver from: a worker of rayon's global pool.
//!
//! A Newton iteration forks tens of rayon regions over the stress points. From a thread
//! outside the pool each one injects its job and puts the caller to sleep until a worker
//! wakes it; from a worker it is a push onto that worker's own deque, and the caller works
//! too. The paper footing through `talus run` (2026-11-28, `docs/performance.md`): 3.60–3.79 s
//! from the main thread, 2.87–2.94 s from a worker on 2 threads, the same bits.

/// The main thread's stack (Linux' default 8 MiB), not a spawned thread's 2 MiB: a
/// computation moved onto the pool keeps the recursion depth it had on the main thread
/// (`RUST_MIN_STACK` and `ulimit -s` no longer set it; nothing here recurses deeply).
const STACK_BYTES: usize = 8 << 20;

/// Runs `computation` on a worker of rayon's global pool, this thread waiting for it, or
/// here when this thread is a worker already.
///
/// With MPI initialized (feature `mpi`) it stays on this thread: MPI is initialized for one
/// thread (`MPI_THREAD_SINGLE`) and MUMPS' calls must come from it. A global pool not built
/// yet is built with 8 MiB stacks (`RAYON_NUM_THREADS` still sets its size); one built
/// before is kept.
pub fn on_pool<R: Send>(computation: impl FnOnce() -> R + Send) -> R {
    #[cfg(feature = "mpi")]
    if mpi::environment::is_initialized() {
        return computation();
    }
    if rayon::current_thread_index().is_some() {
        return computation();
    }
    let _ = rayon::ThreadPoolBuilder::new()
        .stack_size(STACK_BYTES)
        .build_global();
    rayon::scope(|_| computation())
}

#[cfg(test)]
mod tests {
    use super::on_pool;

    #[test]
    fn the_computation_runs_on_a_worker_and_returns_its_value() {
        assert!(
            rayon::current_thread_index().is_none(),
            "tests run outside the pool"
        );
        let (worker, nested) = on_pool(|| {
            let here = std::thread::current().id();
            // From a worker: in place, on the same thread.
            let nested = on_pool(|| std::thread::current().id() == here);
            (rayon::current_thread_index(), nested)
        });
        assert!(worker.is_some());
        assert!(nested);
    }
}
