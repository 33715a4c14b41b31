//! Where a field snapshot goes: `vtu/step_NNNNN.vtu` of the run's folder on one rank;
//! under `mpirun -np N` (`docs/distributed.md`, 'Outputs'), rank r writes piece r of its
//! cells or particles (`output::piece_range`) to `vtu/step_NNNNN/piece_r.vtu` of rank 0's
//! folder, and rank 0 the `vtu/step_NNNNN.pvtu` that gathers the pieces.
use std::ops::Range;
use std::path::Path;

use crate::output;
use crate::run::{io_err, RunError};

/// Writes the snapshot of `step` (`n` cells or particles) by `write(path, piece)`: `None`
/// the whole file (returning `None`), `Some(range)` a piece (returning its XML). Returns
/// the file the `.pvd` in `out` lists, relative to `out`.
pub(crate) fn write_snapshot(
    out: &Path,
    step: usize,
    n: usize,
    write: impl FnOnce(&Path, Option<Range<usize>>) -> Result<Option<String>, RunError>,
) -> Result<String, RunError> {
    let ranks = crate::ranks::ranks();
    let stem = format!("step_{step:05}");
    // One process, or ranks without a folder in common (`talus verify`'s cases, a library
    // call): each writes the whole snapshot into its own folder.
    let Some(root) = shared_root() else {
        let dir = out.join("vtu");
        std::fs::create_dir_all(&dir).map_err(io_err(&dir))?;
        write(&dir.join(format!("{stem}.vtu")), None)?;
        return Ok(format!("vtu/{stem}.vtu"));
    };
    let dir = root.join("vtu").join(&stem);
    std::fs::create_dir_all(&dir).map_err(io_err(&dir))?;
    let piece = |r: usize| format!("piece_{r}.vtu");
    let mine = output::piece_range(n, ranks.rank, ranks.size);
    if !mine.is_empty() {
        let xml = write(&dir.join(piece(ranks.rank)), Some(mine))?;
        if let (true, Some(xml)) = (ranks.is_root(), xml) {
            let listed: Vec<String> = (0..ranks.size)
                .filter(|&r| !output::piece_range(n, r, ranks.size).is_empty())
                .map(|r| format!("{stem}/{}", piece(r)))
                .collect();
            output::write_pvtu(
                &root.join("vtu").join(format!("{stem}.pvtu")),
                &xml,
                &listed,
            )?;
        }
    }
    Ok(format!("vtu/{stem}.pvtu"))
}

/// Under `mpirun`, refuses a run whose ranks do not all see rank 0's output folder (its
/// lock file, which rank 0 holds while it runs): each rank writes its pieces of the field
/// snapshots there. Collective: every rank calls it once, rank 0 after it has taken and
/// cleared the folder, so that no rank looks before the lock exists nor writes its piece
/// of step 0 before the clearing.
pub(crate) fn check_shared_folder() -> Result<(), RunError> {
    // Every rank's collective: rank 0 locks and clears its folder before it comes here,
    // so no other rank looks for the lock before it exists.
    crate::ranks::any(false);
    let Some(root) = shared_root() else {
        return Ok(());
    };
    let ranks = crate::ranks::ranks();
    let seen = ranks.is_root() || root.join(crate::run::folder::LOCK_FILE).exists();
    if let Some(blind) = crate::ranks::first(!seen) {
        let who = format!("rank {blind}");
        return Err(RunError::Io {
            path: root.to_path_buf(),
            source: std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!(
                    "{who} of {} does not see rank 0's output folder (its {}): every rank \
                     writes its pieces of the VTU snapshots there; run in a folder all \
                     ranks see (a shared file system)",
                    ranks.size,
                    crate::run::folder::LOCK_FILE
                ),
            ),
        });
    }
    Ok(())
}

/// Rank 0's folder, when this is one of several ranks that all write there.
fn shared_root() -> Option<&'static Path> {
    crate::ranks::root_folder().filter(|_| crate::ranks::ranks().distributed())
}

/// The folder the snapshots of a run into `out` are in: rank 0's under `mpirun`.
pub(crate) fn folder(out: &Path) -> &Path {
    shared_root().unwrap_or(out)
}

/// Removes from `out/vtu` the snapshots `pvd` does not list (a resume's later steps, the
/// one an interruption wrote of its last state): `step_NNNNN.vtu`, or `step_NNNNN.pvtu`
/// and its folder of pieces.
pub(crate) fn drop_unlisted(
    out: &Path,
    pvd: &[(f64, String)],
) -> Result<(), crate::run::checkpoint::CheckpointError> {
    let dir = out.join("vtu");
    let listed = |n: usize, ext: &str| {
        pvd.iter()
            .any(|(_, f)| *f == format!("vtu/step_{n:05}.{ext}"))
    };
    crate::run::checkpoint::drop_numbered_files(&dir, "step_", ".vtu", |n| listed(n, "vtu"))?;
    crate::run::checkpoint::drop_numbered_files(&dir, "step_", ".pvtu", |n| listed(n, "pvtu"))?;
    // The folders of pieces of unlisted steps, their `.pvtu` written or not (a run killed
    // between its ranks' pieces and rank 0's `.pvtu`).
    for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let step = name.strip_prefix("step_").filter(|n| n.len() >= 5);
        if let Some(n) = step.and_then(|n| n.parse::<usize>().ok()) {
            if entry.file_type().is_ok_and(|t| t.is_dir()) && !listed(n, "pvtu") {
                let _ = std::fs::remove_dir_all(entry.path());
            }
        }
    }
    Ok(())
}
