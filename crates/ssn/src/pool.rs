//! The thread a computation calls the solver from: a worker of rayon's global pool.
//!
//! A Newton iteration forks tens of rayon regions over the stress points. From a thread
//! outside the pool each one injects its job and puts the caller to sleep until a worker
//! wakes it; from a worker it is a push onto that worker's own deque, and the caller works
//! too. The paper footing through `talus run` (2026-11-28, `docs/performance.md`): 3.60–3.79 s
//! from the main thread, 2.87–2.94 s from a worker on 2 threads, the same bits.
use std::sync::mpsc::{channel, RecvTimeoutError};
use std::time::Duration;

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
    if stays_here() {
        return computation();
    }
    build_pool();
    rayon::scope(|_| computation())
}

/// [`on_pool`], this thread calling `meanwhile` every `period` until the computation ends:
/// where this thread has work of its own while it waits (a Python caller checks for Ctrl-C,
/// whose handler CPython runs on its main thread only). Where the computation stays on
/// this thread, `meanwhile` is not called.
pub fn on_pool_polling<R: Send>(
    computation: impl FnOnce() -> R + Send,
    period: Duration,
    mut meanwhile: impl FnMut(),
) -> R {
    if stays_here() {
        return computation();
    }
    build_pool();
    let (sender, receiver) = channel();
    let finished = rayon::in_place_scope(|scope| {
        scope.spawn(move |_| {
            let _ = sender.send(computation());
        });
        loop {
            match receiver.recv_timeout(period) {
                Ok(r) => return Some(r),
                Err(RecvTimeoutError::Timeout) => meanwhile(),
                // It panicked: the scope's end raises that panic here.
                Err(RecvTimeoutError::Disconnected) => return None,
            }
        }
    });
    finished.expect("a computation that sent nothing panicked, and the scope re-raised it")
}

fn stays_here() -> bool {
    #[cfg(feature = "mpi")]
    if mpi::environment::is_initialized() {
        return true;
    }
    rayon::current_thread_index().is_some()
}

fn build_pool() {
    // An error means a pool exists already: it is kept.
    let _ = rayon::ThreadPoolBuilder::new()
        .stack_size(STACK_BYTES)
        .build_global();
}

#[cfg(test)]
mod tests {
    use super::{on_pool, on_pool_polling};

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

    #[test]
    fn the_caller_polls_until_the_computation_ends() {
        let mut polls = 0;
        let (worker, value) = on_pool_polling(
            || {
                std::thread::sleep(std::time::Duration::from_millis(60));
                (rayon::current_thread_index(), 7)
            },
            std::time::Duration::from_millis(5),
            || polls += 1,
        );
        assert!(worker.is_some());
        assert_eq!(value, 7);
        assert!(polls >= 2, "{polls} polls in 60 ms at 5 ms");
    }
}
