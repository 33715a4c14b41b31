//! Every output file is written under a temporary name in its folder, then renamed: a
//! reader (ParaView, a script, a run interrupted half way, a full disk) sees the old file
//! or the new one, never a truncated one.
use std::path::{Path, PathBuf};

use super::OutputError;

/// `.NAME.partial.EXT` beside `path` (the extension kept: the PNG encoder reads it).
fn temporary(path: &Path) -> PathBuf {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
    let name = match (stem, path.extension()) {
        (Some(stem), Some(ext)) => format!(".{stem}.partial.{}", ext.to_string_lossy()),
        (Some(stem), None) => format!(".{stem}.partial"),
        _ => ".partial".to_string(),
    };
    path.with_file_name(name)
}

/// Runs `write` on a temporary path, then renames it to `path`; on failure the temporary
/// file is removed and the error names `path`.
pub(crate) fn through_temp(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), OutputError>,
) -> Result<(), OutputError> {
    let tmp = temporary(path);
    let result = write(&tmp)
        .and_then(|()| std::fs::rename(&tmp, path).map_err(|e| OutputError::io(path, e)));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(|e| match e {
        OutputError::Io { source, .. } => OutputError::io(path, source),
        OutputError::Plot { message, .. } => OutputError::plot(path, message),
        other => other,
    })
}

/// `bytes` into `path`, atomically.
pub(crate) fn write(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), OutputError> {
    through_temp(path, |tmp| {
        std::fs::write(tmp, bytes).map_err(|e| OutputError::io(tmp, e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_neither_a_partial_file_nor_a_changed_one() {
        let dir = std::env::temp_dir().join(format!("talus_atomic_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.vtu");
        write(&path, "old").unwrap();
        let err = through_temp(&path, |tmp| {
            std::fs::write(tmp, "half").unwrap();
            Err(OutputError::invalid("x", "disk full"))
        });
        assert!(err.is_err());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("a.vtu")]);
        write(&path, "new").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(temporary(&path).file_name().unwrap(), ".a.partial.vtu");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
