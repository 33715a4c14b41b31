//! The output folder brought back to a checkpoint's step: `history.csv` cut after the
//! step's row, the numbered files (VTU, snapshots) of later steps removed.
use std::path::Path;

use super::CheckpointError;

/// Keeps the header of `history.csv` and its rows of steps 0 to `step`, atomically. A
/// file without them (or whose row `step` is not that step's) is an error: the checkpoint
/// is not this folder's.
pub fn truncate_history(path: &Path, step: usize) -> Result<(), CheckpointError> {
    let outputs = |why: String| CheckpointError::Outputs {
        path: path.to_path_buf(),
        step,
        why,
    };
    let text = std::fs::read_to_string(path).map_err(|source| {
        if source.kind() == std::io::ErrorKind::NotFound {
            outputs("not found".into())
        } else {
            CheckpointError::Io {
                path: path.to_path_buf(),
                source,
            }
        }
    })?;
    // Complete lines only: a kill may have cut the last one.
    let lines: Vec<&str> = text.split_inclusive('\n').collect();
    let keep = step + 2;
    let complete = lines.iter().filter(|l| l.ends_with('\n')).count();
    if complete < keep {
        return Err(outputs(format!(
            "{} complete rows after the header, the checkpoint needs {}",
            complete.saturating_sub(1),
            step + 1
        )));
    }
    let last = lines[keep - 1];
    if last.split(',').next() != Some(&step.to_string()) {
        return Err(outputs(format!(
            "row {} is not step {step}'s: {}",
            keep - 1,
            last.trim_end()
        )));
    }
    crate::output::write_atomically(path, lines[..keep].concat()).map_err(|e| CheckpointError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e.to_string()),
    })
}

/// Removes `dir/PREFIXNNNNN.EXT` for every `NNNNN` not to `keep` (the files of steps a
/// resumed run writes again, or of the state an interruption wrote). A missing folder has
/// nothing to remove.
pub fn drop_numbered_files(
    dir: &Path,
    prefix: &str,
    ext: &str,
    keep: impl Fn(usize) -> bool,
) -> Result<(), CheckpointError> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let number = name
            .strip_prefix(prefix)
            .and_then(|n| n.strip_suffix(ext))
            .and_then(|n| n.parse::<usize>().ok());
        if number.is_some_and(|n| !keep(n)) {
            std::fs::remove_file(entry.path()).map_err(|source| CheckpointError::Io {
                path: entry.path(),
                source,
            })?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn history_is_cut_after_the_step_and_a_short_one_refused() {
        let dir = std::env::temp_dir().join(format!("talus_truncate_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("history.csv");
        std::fs::write(&path, "step,x\n0,a\n1,b\n2,c\n3,d\n4,e").unwrap();
        truncate_history(&path, 2).unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "step,x\n0,a\n1,b\n2,c\n"
        );
        // Step 3 needs a complete row 3.
        std::fs::write(&path, "step,x\n0,a\n1,b\n2,c\n3,d").unwrap();
        let err = truncate_history(&path, 3).unwrap_err();
        assert!(err.to_string().contains("3 complete rows"), "{err}");
        std::fs::write(&path, "step,x\n0,a\n5,b\n").unwrap();
        let err = truncate_history(&path, 1).unwrap_err();
        assert!(err.to_string().contains("not step 1's"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn only_later_numbered_files_are_removed() {
        let dir = std::env::temp_dir().join(format!("talus_drop_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for name in [
            "step_00010.vtu",
            "step_00020.vtu",
            "step_00021.vtu",
            "other.vtu",
        ] {
            std::fs::write(dir.join(name), "").unwrap();
        }
        drop_numbered_files(&dir, "step_", ".vtu", |n| n <= 20).unwrap();
        let mut names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["other.vtu", "step_00010.vtu", "step_00020.vtu"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
