//! `talus` under `mpirun` (`docs/distributed.md`): rank 0 writes the output folder and
//! reports; the other ranks run the same scene into a scratch folder removed at the end
//! (their pieces of the VTUs go to rank 0's folder, `run/pieces.rs`), and keep their
//! errors unless rank 0 did not fail too.
use std::fmt::Display;
use std::path::PathBuf;
#[cfg(feature = "mpi")]
use std::process::ExitCode;
use std::sync::Mutex;

use talus::ranks::ranks;

#[cfg(feature = "mpi")]
use super::exit::Exit;

/// A non-root rank's last error, printed only if that rank fails alone.
static DEFERRED: Mutex<Option<String>> = Mutex::new(None);

/// Prints an error on rank 0; on another rank keeps it for [`finish`].
pub fn error(e: impl Display) {
    if ranks().is_root() {
        eprintln!("error: {e}");
    } else if let Ok(mut last) = DEFERRED.lock() {
        *last = Some(e.to_string());
    }
}

/// Whether this rank reports (prints summaries and notices): rank 0.
pub fn reports() -> bool {
    ranks().is_root()
}

/// The folder this rank writes: `out` on rank 0, a scratch folder elsewhere.
pub fn output_folder(out: PathBuf) -> PathBuf {
    let r = ranks();
    if r.is_root() {
        out
    } else {
        std::env::temp_dir().join(format!("talus-rank{}-{}", r.rank, std::process::id()))
    }
}

/// The folder a resume of `out` continues on this rank: `out` on rank 0; elsewhere the
/// scratch folder, given copies of `out`'s checkpoint and `history.csv` (the state is the
/// same on every rank, `talus::ranks`), which rank 0 alone writes.
pub fn resume_folder(out: PathBuf) -> std::io::Result<PathBuf> {
    if ranks().is_root() {
        return Ok(out);
    }
    let scratch = output_folder(PathBuf::new());
    let checkpoint = talus::run::checkpoint::path(&out);
    let copy = talus::run::checkpoint::path(&scratch);
    if let Some(dir) = copy.parent() {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::copy(&checkpoint, &copy)?;
    std::fs::copy(out.join("history.csv"), scratch.join("history.csv"))?;
    Ok(scratch)
}

/// The process' exit: with more than one rank, an input or output failure (the ones a
/// rank can meet alone: a file, a lock, a disk) stops every rank by `MPI_Abort`, so that
/// none is left waiting in MUMPS; a non-root rank first gives rank 0 two seconds to report
/// the same error and abort. Outcomes every rank reaches together (converged, collapsed,
/// not converged) exit normally.
#[cfg(feature = "mpi")]
pub fn finish(mpi: &talus::ranks::Mpi, code: ExitCode) -> ExitCode {
    let r = ranks();
    if talus::ranks::launched_by_mpi() {
        if let Some(kib) = peak_kib() {
            tracing::info!(rank = r.rank, peak_mib = kib / 1024, "peak resident memory");
        }
    }
    if !r.is_root() {
        let _ = std::fs::remove_dir_all(output_folder(PathBuf::new()));
    }
    let alone = [Exit::InvalidInput, Exit::Io]
        .into_iter()
        .find(|&e| ExitCode::from(e) == code);
    match alone {
        Some(e) if r.distributed() => {
            if !r.is_root() {
                std::thread::sleep(std::time::Duration::from_secs(2));
                if let Some(message) = DEFERRED.lock().ok().and_then(|m| m.clone()) {
                    eprintln!("rank {}: error: {message}", r.rank);
                }
            }
            mpi.abort(i32::from(e.code()))
        }
        _ => code,
    }
}

/// This process' peak resident memory (`VmHWM`, KiB), where Linux gives it.
#[cfg(feature = "mpi")]
fn peak_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find_map(|l| l.strip_prefix("VmHWM:"))?;
    line.trim().trim_end_matches("kB").trim().parse().ok()
}
