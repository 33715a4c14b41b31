//! The output folder of a run (`docs/scenes.md`, 'Durable outputs'): the lock that keeps
//! a second run or resume out of a folder in use, and the files a run owns, cleared when a
//! fresh run starts (and no other file).
//!
//! The lock is the operating system's lock on `OUT/.talus.lock` (`File::try_lock`: `flock`
//! on Unix): it is released when the run ends, also on an error, a panic or SIGINT, and by
//! the system when the process is killed, so that no stale lock can remain. The file holds
//! the holder's pid (for the refusal's message) and is removed on release.
use std::cell::RefCell;
use std::fs::{File, OpenOptions, TryLockError};
use std::io::Write;
use std::marker::PhantomData;
use std::path::{Path, PathBuf};

use super::checkpoint::CheckpointError;

/// The lock file, in the output folder, while a run holds it.
pub const LOCK_FILE: &str = ".talus.lock";

/// A folder this thread holds, and how many guards of it are alive (the `talus` binary
/// holds its folder for the whole command; the run loop takes it again).
struct Held {
    dir: PathBuf,
    lock: PathBuf,
    /// `None`: the file system does not lock (a warning said so).
    file: Option<File>,
    count: usize,
    /// The folder did not exist: removed again on release if still empty.
    created: bool,
}

thread_local! {
    static HELD: RefCell<Vec<Held>> = const { RefCell::new(Vec::new()) };
}

/// The output folder held: no other run or resume (another process, or another thread)
/// takes it until the last guard of it in this thread is dropped.
#[must_use = "the folder is released when the lock is dropped"]
pub struct FolderLock {
    dir: PathBuf,
    /// Held by this thread only.
    _thread: PhantomData<*const ()>,
}

impl std::fmt::Debug for FolderLock {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "FolderLock({})", self.dir.display())
    }
}

/// Takes `dir` (created if missing) for this run; refused with
/// [`CheckpointError::InUse`] (exit 1) when another run or resume holds it, before
/// anything in it is changed. Taken again by the thread that holds it, it is the same lock.
pub fn lock(dir: &Path) -> Result<FolderLock, CheckpointError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| CheckpointError::Io { path, source }
    };
    let created = !dir.exists();
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let key = dir.canonicalize().map_err(io(dir))?;
    let guard = FolderLock {
        dir: key.clone(),
        _thread: PhantomData,
    };
    let again = HELD.with_borrow_mut(|held| {
        held.iter_mut()
            .find(|h| h.dir == key)
            .map(|h| h.count += 1)
            .is_some()
    });
    if again {
        return Ok(guard);
    }
    let lock = key.join(LOCK_FILE);
    let file = match acquire(dir, &lock) {
        Ok(file) => file,
        Err(e) => {
            if created {
                let _ = std::fs::remove_dir(dir);
            }
            return Err(e);
        }
    };
    HELD.with_borrow_mut(|held| {
        held.push(Held {
            dir: key,
            lock,
            file,
            count: 1,
            created,
        })
    });
    Ok(guard)
}

/// The lock on `lock`, the file then holding this process's pid.
fn acquire(dir: &Path, lock: &Path) -> Result<Option<File>, CheckpointError> {
    let io = |source| CheckpointError::Io {
        path: lock.to_path_buf(),
        source,
    };
    let in_use = || CheckpointError::InUse {
        dir: dir.to_path_buf(),
        lock: lock.to_path_buf(),
        holder: std::fs::read_to_string(lock)
            .ok()
            .and_then(|t| t.trim().strip_prefix("pid ").map(|p| format!(" (pid {p})")))
            .unwrap_or_default(),
    };
    // A holder removes the file as it releases it: the file opened may then be gone, and
    // another run may hold a new one. Locked, it must still be the file of that name.
    for _ in 0..16 {
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(lock)
            .map_err(io)?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => return Err(in_use()),
            Err(TryLockError::Error(e)) if e.kind() == std::io::ErrorKind::Unsupported => {
                tracing::warn!(
                    folder = %dir.display(),
                    "this file system does not lock files: nothing keeps a second talus run \
                     or resume out of this folder"
                );
                return Ok(Some(file));
            }
            Err(TryLockError::Error(e)) => return Err(io(e)),
        }
        if still_named(&file, lock) {
            // The pid only serves the message of a run refused: a failure to write it is
            // not the run's.
            let _ = file.set_len(0);
            let _ = (&file).write_all(format!("pid {}\n", std::process::id()).as_bytes());
            return Ok(Some(file));
        }
    }
    Err(in_use())
}

/// Whether `file` is still the file at `path`.
#[cfg(unix)]
fn still_named(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Elsewhere the file is never removed (see [`release`]): it is always the one named.
#[cfg(not(unix))]
fn still_named(_: &File, _: &Path) -> bool {
    true
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        // During the thread's own teardown there is nothing left to release but the file,
        // which the system closes.
        let _ = HELD.try_with(|held| {
            let mut held = held.borrow_mut();
            let Some(k) = held.iter().position(|h| h.dir == self.dir) else {
                return;
            };
            held[k].count -= 1;
            if held[k].count == 0 {
                release(held.swap_remove(k));
            }
        });
    }
}

/// Removes the lock file while still holding it (Unix: a run that opened it meanwhile
/// sees it is no longer the file of that name), then unlocks it.
fn release(held: Held) {
    #[cfg(unix)]
    let _ = std::fs::remove_file(&held.lock);
    drop(held.file);
    if held.created {
        // Only if empty: the run stopped before writing anything.
        let _ = std::fs::remove_dir(&held.dir);
    }
}

/// What a run writes at the top of its folder; with `trials_NAME.csv`
/// ([`owned_at_top`]), `vtu/step_NNNNN.vtu`, `snapshots/step_NNNNN.png` and
/// `checkpoint/last.checkpoint`, the files a run owns (`docs/scenes.md`, 'Durable
/// outputs').
pub const OWNED_AT_TOP: [&str; 9] = [
    "history.csv",
    "summary.json",
    "solution.pvd",
    "force_displacement.png",
    "newton_residuals.png",
    "plastic_strain.png",
    "mechanism.vtu",
    "mechanism.png",
    ".talus_write_test",
];

/// Whether a run writes `name` at the top of its folder: [`OWNED_AT_TOP`], and the factor
/// of safety trials of a stage, `trials_NAME.csv` (NAME of letters, digits, `-`, `_`).
fn owned_at_top(name: &str) -> bool {
    OWNED_AT_TOP.contains(&name)
        || name
            .strip_prefix("trials_")
            .and_then(|n| n.strip_suffix(".csv"))
            .is_some_and(|n| {
                !n.is_empty()
                    && n.chars()
                        .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
            })
}

/// `step_NNNNN.EXT` (at least five digits), the name of a step's file.
fn step_file(name: &str, ext: &str) -> bool {
    name.strip_prefix("step_")
        .and_then(|n| n.strip_suffix(ext))
        .is_some_and(|n| n.len() >= 5 && n.bytes().all(|b| b.is_ascii_digit()))
}

/// The name a temporary file (`.NAME.partial.EXT`, `crate::output::write_atomically`)
/// stands for, or `name` itself.
fn real_name(name: &str) -> String {
    let Some(hidden) = name.strip_prefix('.') else {
        return name.to_string();
    };
    match hidden.rfind(".partial") {
        Some(i) if hidden[i + 8..].is_empty() || hidden[i + 8..].starts_with('.') => {
            format!("{}{}", &hidden[..i], &hidden[i + 8..])
        }
        _ => name.to_string(),
    }
}

/// Whether a run writes the file `name` of its folder's `sub`folder ("" its top), or a
/// temporary copy of it.
pub fn is_owned(sub: &str, name: &str) -> bool {
    let real = real_name(name);
    match sub {
        "" => owned_at_top(&real),
        "vtu" => step_file(&real, ".vtu") || step_file(&real, ".pvtu"),
        // A snapshot's pieces under `mpirun` (`crate::run::pieces`), in `vtu/step_NNNNN/`.
        piece_dir if piece_dir.starts_with("vtu/") => {
            step_file(&piece_dir[4..], "")
                && real
                    .strip_prefix("piece_")
                    .and_then(|n| n.strip_suffix(".vtu"))
                    .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
        }
        "snapshots" => step_file(&real, ".png"),
        "checkpoint" => real == "last.checkpoint",
        _ => false,
    }
}

/// Removes from `out` the files an earlier run left that this fresh run would write (or
/// leave stale beside its own): [`is_owned`], and nothing else. Says so in the log, and
/// returns their names relative to `out`.
pub fn clear_owned(out: &Path) -> Result<Vec<String>, CheckpointError> {
    let mut removed = Vec::new();
    // In words: the top's files by name, a subfolder's by name when few, else counted.
    let mut said = Vec::new();
    // The snapshots' folders of pieces, `vtu/step_NNNNN` (before `vtu` itself).
    let mut piece_dirs: Vec<String> = std::fs::read_dir(out.join("vtu"))
        .map(|entries| {
            entries
                .flatten()
                .filter(|e| e.file_type().is_ok_and(|t| t.is_dir()))
                .filter_map(|e| e.file_name().to_str().map(|n| format!("vtu/{n}")))
                .filter(|sub| step_file(&sub[4..], ""))
                .collect()
        })
        .unwrap_or_default();
    piece_dirs.sort();
    let subs = piece_dirs
        .iter()
        .map(String::as_str)
        .chain(["", "vtu", "snapshots", "checkpoint"]);
    for sub in subs {
        let dir = if sub.is_empty() {
            out.to_path_buf()
        } else {
            out.join(sub)
        };
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        let mut names: Vec<String> = entries
            .flatten()
            .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
            .filter_map(|e| e.file_name().to_str().map(str::to_string))
            .filter(|name| is_owned(sub, name))
            .collect();
        names.sort();
        for name in &names {
            let path = dir.join(name);
            std::fs::remove_file(&path).map_err(|source| CheckpointError::Io { path, source })?;
        }
        let relative: Vec<String> = names
            .iter()
            .map(|n| match sub {
                "" => n.clone(),
                _ => format!("{sub}/{n}"),
            })
            .collect();
        match (sub, &relative[..]) {
            (_, []) => {}
            ("", _) | (_, [_] | [_, _] | [_, _, _]) => said.extend(relative.iter().cloned()),
            (_, [first, .., last]) => said.push(format!(
                "{} files in {sub}/ ({first} ... {last})",
                relative.len()
            )),
        }
        removed.extend(relative);
        if !sub.is_empty() && !names.is_empty() {
            // Only if nothing else is in it.
            let _ = std::fs::remove_dir(&dir);
        }
    }
    if !removed.is_empty() {
        tracing::warn!(
            "cleared {} file(s) an earlier run left in {}: {} (a fresh run replaces the files \
             a run writes; other files are kept)",
            removed.len(),
            out.display(),
            said.join(", ")
        );
    }
    Ok(removed)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("talus_folder_{name}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn only_the_files_a_run_writes_are_owned() {
        for name in [
            "history.csv",
            "summary.json",
            ".summary.partial.json",
            "solution.pvd",
            ".solution.partial.pvd",
            "plastic_strain.png",
            "trials_lift_3.csv",
            "mechanism.vtu",
        ] {
            assert!(is_owned("", name), "{name}");
        }
        for name in [
            "notes.txt",
            "history.csv.bak",
            "trials_.csv",
            "trials_a b.csv",
            "my_history.csv",
            ".talus.lock",
            ".notes.partial.txt",
            "step_00001.vtu",
        ] {
            assert!(!is_owned("", name), "{name}");
        }
        assert!(is_owned("vtu", "step_00999.vtu"));
        assert!(is_owned("vtu", "step_123456.vtu"));
        assert!(is_owned("vtu", ".step_00010.partial.vtu"));
        assert!(!is_owned("vtu", "step_1.vtu"));
        assert!(!is_owned("vtu", "mine.vtu"));
        assert!(!is_owned("vtu", "step_0001a.vtu"));
        assert!(is_owned("vtu", "step_00030.pvtu"));
        assert!(is_owned("vtu/step_00030", "piece_12.vtu"));
        assert!(is_owned("vtu/step_00030", ".piece_1.partial.vtu"));
        assert!(!is_owned("vtu/step_00030", "piece_.vtu"));
        assert!(!is_owned("vtu/step_00030", "notes.vtu"));
        assert!(!is_owned("vtu/mine", "piece_1.vtu"));
        assert!(is_owned("snapshots", "step_00020.png"));
        assert!(!is_owned("snapshots", "step_00020.vtu"));
        assert!(is_owned("checkpoint", "last.checkpoint"));
        assert!(is_owned("checkpoint", ".last.partial.checkpoint"));
        assert!(!is_owned("checkpoint", "old.checkpoint"));
        assert!(!is_owned("elsewhere", "history.csv"));
    }

    #[test]
    fn clearing_keeps_what_the_run_does_not_write() {
        let dir = temp("clear");
        std::fs::create_dir_all(dir.join("vtu/step_00030")).unwrap();
        std::fs::create_dir_all(dir.join("vtu/step_00060")).unwrap();
        std::fs::create_dir_all(dir.join("snapshots")).unwrap();
        for name in [
            "history.csv",
            "notes.txt",
            "vtu/step_00999.vtu",
            "vtu/step_00030.pvtu",
            "vtu/step_00030/piece_0.vtu",
            "vtu/step_00030/piece_1.vtu",
            "vtu/step_00060/piece_0.vtu",
            "vtu/step_00060/mine.txt",
            "vtu/mine.vtu",
            "snapshots/step_00000.png",
        ] {
            std::fs::write(dir.join(name), name).unwrap();
        }
        let removed = clear_owned(&dir).unwrap();
        assert_eq!(
            removed,
            [
                "vtu/step_00030/piece_0.vtu",
                "vtu/step_00030/piece_1.vtu",
                "vtu/step_00060/piece_0.vtu",
                "history.csv",
                "vtu/step_00030.pvtu",
                "vtu/step_00999.vtu",
                "snapshots/step_00000.png"
            ]
        );
        assert!(dir.join("notes.txt").exists());
        assert!(dir.join("vtu/mine.vtu").exists());
        assert!(!dir.join("vtu/step_00030").exists(), "emptied: removed");
        assert!(dir.join("vtu/step_00060/mine.txt").exists());
        assert!(!dir.join("snapshots").exists(), "emptied: removed");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_held_folder_is_refused_to_another_thread_and_released_by_the_last_guard() {
        let dir = temp("lock");
        let first = lock(&dir).unwrap();
        let again = lock(&dir).unwrap();
        let lock_file = dir.join(LOCK_FILE);
        assert_eq!(
            std::fs::read_to_string(&lock_file).unwrap(),
            format!("pid {}\n", std::process::id())
        );
        let other = dir.clone();
        let refused = std::thread::spawn(move || lock(&other).map(|_| ()))
            .join()
            .unwrap()
            .unwrap_err();
        let message = refused.to_string();
        assert!(
            matches!(refused, CheckpointError::InUse { .. }),
            "{message}"
        );
        assert!(message.contains(&dir.display().to_string()), "{message}");
        assert!(
            message.contains(&format!("(pid {})", std::process::id())),
            "{message}"
        );
        drop(first);
        assert!(lock_file.exists(), "still held by the second guard");
        drop(again);
        assert!(!lock_file.exists());
        // Created by the lock and left empty: removed with it.
        assert!(!dir.exists());
        let other = dir.clone();
        std::thread::spawn(move || drop(lock(&other).unwrap()))
            .join()
            .unwrap();
    }
}
