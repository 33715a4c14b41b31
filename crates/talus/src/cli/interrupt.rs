//! SIGINT / SIGTERM (Ctrl-C, `kill`): the run loop finishes the step it is in, writes the
//! end-of-run files and `summary.json` (status `interrupted`), and `talus` exits 130. A
//! second signal exits at once. Only the `talus` binary installs the handler: a library
//! user's runs are never interrupted by it.
use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Installs the handler (once per process; later calls do nothing).
pub fn install() -> Result<(), ctrlc::Error> {
    ctrlc::set_handler(|| {
        if REQUESTED.swap(true, Ordering::SeqCst) {
            std::process::exit(super::exit::Exit::Interrupted.code().into());
        }
        eprintln!(
            "interrupted: finishing the step, then writing the outputs (again to quit at once)"
        );
    })
}

/// Whether a signal asked the run to stop.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}
