//! The output folder brought back to a checkpoint's step: `history.csv` cut after the
//! step's row, the numbered files (VTU, snapshots) of later steps removed. What ties a
//! checkpoint to its folder's `history.csv` ([`history_key`]) is here too.
use std::io::{BufRead, Read, Seek, SeekFrom};
use std::path::Path;

use super::{fnv1a64, CheckpointError};

/// The header of `history.csv` and its rows of steps 0 to `step`: the text a resume keeps.
/// Reads only. A file without them (or whose row `step` is not that step's) is an error:
/// the checkpoint is not this folder's.
pub fn history_prefix(path: &Path, step: usize) -> Result<String, CheckpointError> {
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
    Ok(lines[..keep].concat())
}

/// `history.csv` replaced by `kept` ([`history_prefix`]), atomically.
pub fn write_history(path: &Path, kept: &str) -> Result<(), CheckpointError> {
    crate::output::write_atomically(path, kept).map_err(|e| CheckpointError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e.to_string()),
    })
}

/// What ties the checkpoint of a step to its folder: the FNV-1a hash (16 hex digits) of
/// `history.csv`'s header line and its row of that step, as they were when the checkpoint
/// was written (both without their line end), the row's wall time (`seconds`) left out so
/// that a resumed run's checkpoints are byte for byte those of the run never stopped. The
/// row holds the step's time, reaction, settlement and monitors: another scene's run gives
/// another row, unless its steps up to this one were the same computation.
pub fn history_key(header: &str, row: &str) -> String {
    let seconds = header.split(',').position(|c| c == "seconds");
    let row: Vec<&str> = row
        .split(',')
        .enumerate()
        .filter(|(k, _)| Some(*k) != seconds)
        .map(|(_, v)| v)
        .collect();
    let text = format!("{header}\n{}\n", row.join(","));
    format!("{:016x}", fnv1a64(text.as_bytes()))
}

/// [`history_key`] of the text [`history_prefix`] kept: its first and last lines.
pub(super) fn key_of_prefix(kept: &str) -> Option<String> {
    let mut lines = kept.lines();
    let header = lines.next()?;
    let row = lines.next_back()?;
    Some(history_key(header, row))
}

/// [`history_key`] of the history file at `path` when its last row is step `step`'s (the
/// run loop writes a checkpoint after that row): its header and its last row, read from
/// the end, not the whole file.
pub(super) fn key_of_file(path: &Path, step: usize) -> Option<String> {
    let mut file = std::fs::File::open(path).ok()?;
    let mut header = String::new();
    std::io::BufReader::new(&file).read_line(&mut header).ok()?;
    let header = header.strip_suffix('\n')?;
    let len = file.metadata().ok()?.len();
    let mut chunk = 4096u64;
    let row = loop {
        let start = len.saturating_sub(chunk);
        file.seek(SeekFrom::Start(start)).ok()?;
        let mut tail = Vec::new();
        file.read_to_end(&mut tail).ok()?;
        // The last row is complete: the run loop flushed it whole.
        let body = tail.strip_suffix(b"\n")?;
        if let Some(i) = body.iter().rposition(|&b| b == b'\n') {
            break String::from_utf8(body[i + 1..].to_vec()).ok()?;
        }
        if start == 0 {
            // The header alone.
            return None;
        }
        chunk *= 4;
    };
    row.starts_with(&format!("{step},"))
        .then(|| history_key(header, &row))
}

/// Drops from the collection a checkpoint's outputs list (`pvd`: `[time, file]` pairs,
/// the file relative to `out`, as the FEM and MPM outputs save it) the files no longer in
/// `out` (e.g. `vtu/` removed), so that the resumed `solution.pvd` lists only files that
/// exist. Returns the names dropped and the number of files left listed.
pub fn keep_existing_files(out: &Path, outputs: &mut serde_json::Value) -> (Vec<String>, usize) {
    let Some(pvd) = outputs.get_mut("pvd").and_then(|v| v.as_array_mut()) else {
        return (Vec::new(), 0);
    };
    let mut missing = Vec::new();
    pvd.retain(|entry| match entry.get(1).and_then(|f| f.as_str()) {
        Some(file) if !out.join(file).is_file() => {
            missing.push(file.to_string());
            false
        }
        _ => true,
    });
    (missing, pvd.len())
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
        let kept = history_prefix(&path, 2).unwrap();
        write_history(&path, &kept).unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "step,x\n0,a\n1,b\n2,c\n"
        );
        // Step 3 needs a complete row 3.
        std::fs::write(&path, "step,x\n0,a\n1,b\n2,c\n3,d").unwrap();
        let err = history_prefix(&path, 3).unwrap_err();
        assert!(err.to_string().contains("3 complete rows"), "{err}");
        std::fs::write(&path, "step,x\n0,a\n5,b\n").unwrap();
        let err = history_prefix(&path, 1).unwrap_err();
        assert!(err.to_string().contains("not step 1's"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_history_key_of_the_file_is_the_one_of_its_kept_rows() {
        let dir = std::env::temp_dir().join(format!("talus_key_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("history.csv");
        let long = "9".repeat(10_000);
        std::fs::write(&path, format!("step,x\n0,a\n1,{long}\n2,c\n")).unwrap();
        let key = key_of_file(&path, 2).unwrap();
        assert_eq!(key, history_key("step,x", "2,c"));
        assert_eq!(key_of_file(&path, 1), None, "the last row is step 2's");
        std::fs::write(&path, format!("step,x\n0,a\n1,{long}\n")).unwrap();
        assert_eq!(
            key_of_file(&path, 1),
            Some(history_key("step,x", &format!("1,{long}")))
        );
        std::fs::write(&path, format!("step,x\n0,a\n1,{long}\n2,c\n3,d\n")).unwrap();
        let kept = history_prefix(&path, 2).unwrap();
        assert_eq!(key_of_prefix(&kept), Some(key));
        std::fs::write(&path, "step,x\n").unwrap();
        assert_eq!(key_of_file(&path, 0), None);
        // The wall time aside.
        assert_eq!(
            history_key("step,seconds,x", "2,0.1,c"),
            history_key("step,seconds,x", "2,0.2,c")
        );
        assert_ne!(
            history_key("step,seconds,x", "2,0.1,c"),
            history_key("step,seconds,x", "2,0.1,d")
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn only_existing_files_stay_in_the_collection() {
        let dir = std::env::temp_dir().join(format!("talus_keep_{}", std::process::id()));
        std::fs::create_dir_all(dir.join("vtu")).unwrap();
        std::fs::write(dir.join("vtu/step_00010.vtu"), "").unwrap();
        let mut outputs = serde_json::json!({
            "pvd": [[0.0, "vtu/step_00000.vtu"], [0.1, "vtu/step_00010.vtu"]],
            "curve": []
        });
        let (missing, left) = keep_existing_files(&dir, &mut outputs);
        assert_eq!(missing, ["vtu/step_00000.vtu"]);
        assert_eq!(left, 1);
        assert_eq!(
            outputs["pvd"],
            serde_json::json!([[0.1, "vtu/step_00010.vtu"]])
        );
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
