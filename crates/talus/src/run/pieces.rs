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
    if !ranks.distributed() {
        let dir = out.join("vtu");
        std::fs::create_dir_all(&dir).map_err(io_err(&dir))?;
        write(&dir.join(format!("{stem}.vtu")), None)?;
        return Ok(format!("vtu/{stem}.vtu"));
    }
    let root = crate::ranks::root_folder().unwrap_or(out);
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
    crate::run::checkpoint::drop_numbered_files(&dir, "step_", ".pvtu", |n| {
        let keep = listed(n, "pvtu");
        if !keep {
            let _ = std::fs::remove_dir_all(dir.join(format!("step_{n:05}")));
        }
        keep
    })
}
