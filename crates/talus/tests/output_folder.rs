//! The output folder as a user meets it (`docs/scenes.md`, 'Durable outputs' and
//! 'Checkpoints and resume'), through the `talus` binary: one run or resume at a time in a
//! folder (the second refused with exit 1, the folder untouched), a refused resume leaves
//! the folder byte for byte as it was, a fresh run clears what an earlier run left (and
//! nothing else), a resume after `vtu/` was removed lists only files that exist, and another
//! run's checkpoint copied into a folder is refused.
use std::collections::BTreeMap;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use talus::run::fem::run_scene;
use talus::run::{folder, RunError, RunOptions, StepProgress};
use talus::scene::Scene;

use crate::common;
fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("output_folder")
}

/// `scenes/footing.toml` on 8 × 4 cells (folder handling does not depend on the mesh) with
/// `steps` steps, VTUs every 5, no plots (`extra` replacements too), written to
/// `root()/file`.
fn footing(file: &str, steps: usize, extra: &[(&str, &str)]) -> PathBuf {
    let mut edits = vec![("cells = [32, 14]", "cells = [8, 4]")];
    edits.extend_from_slice(extra);
    paper_footing(file, steps, &edits)
}

/// As [`footing`] on the paper's 32 × 14 cells: for a run still going when the test acts.
fn paper_footing(file: &str, steps: usize, extra: &[(&str, &str)]) -> PathBuf {
    let mut text = common::FOOTING.to_string();
    let steps = format!("steps = {steps}");
    let replacements = [
        ("steps = 300", steps.as_str()),
        ("vtu_every = 30", "vtu_every = 5"),
        ("plots = true", "plots = false"),
    ];
    for (from, to) in replacements.iter().chain(extra) {
        assert!(text.contains(from), "footing.toml has no `{from}`");
        text = text.replace(from, to);
    }
    std::fs::create_dir_all(root()).unwrap();
    let out = root().join(file);
    std::fs::write(&out, text).unwrap();
    out
}

fn out_dir(name: &str) -> PathBuf {
    let out = root().join(name);
    let _ = std::fs::remove_dir_all(&out);
    out
}

fn talus(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_talus"));
    c.args(args)
        .env("TALUS_LOG", "warn")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    c
}

fn run(scene: &Path, out: &Path, every: Option<usize>) -> Output {
    let (scene, out) = (scene.display().to_string(), out.display().to_string());
    let every = every.map(|n| n.to_string());
    let mut args = vec!["run", &scene, "--out", &out];
    if let Some(n) = &every {
        args.extend(["--checkpoint-every", n]);
    }
    talus(&args).output().unwrap()
}

fn resume(out: &Path) -> Output {
    talus(&["resume", &out.display().to_string()])
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assert_ok(o: &Output) {
    assert_eq!(o.status.code(), Some(0), "{}", stderr(o));
}

/// Exit 1, and every one of `words` in the error.
fn assert_refused(o: &Output, words: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    for w in words {
        assert!(err.contains(w), "expected `{w}` in: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

/// Every file under `dir` (relative path → bytes).
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(base: &Path, dir: &Path, into: &mut BTreeMap<String, Vec<u8>>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                walk(base, &path, into);
            } else {
                let name = path.strip_prefix(base).unwrap().display().to_string();
                into.insert(name, std::fs::read(&path).unwrap());
            }
        }
    }
    let mut files = BTreeMap::new();
    walk(dir, dir, &mut files);
    files
}

/// Asserts `dir` holds exactly `before`, byte for byte.
fn assert_unchanged(dir: &Path, before: &BTreeMap<String, Vec<u8>>) {
    let after = snapshot(dir);
    assert_eq!(
        before.keys().collect::<Vec<_>>(),
        after.keys().collect::<Vec<_>>(),
        "the files of {}",
        dir.display()
    );
    for (name, bytes) in before {
        assert!(after[name] == *bytes, "{name} changed");
    }
}

/// The step column of `history.csv`.
fn history_steps(out: &Path) -> Vec<usize> {
    common::history_column(out, "step")
        .into_iter()
        .map(|s| s as usize)
        .collect()
}

/// The files `solution.pvd` lists, relative to `out`.
fn pvd_files(out: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(out.join("solution.pvd")).unwrap();
    text.split("file=\"")
        .skip(1)
        .map(|s| s[..s.find('"').unwrap()].to_string())
        .collect()
}

fn assert_every_listed_file_exists(out: &Path) {
    let listed = pvd_files(out);
    assert!(!listed.is_empty());
    for f in &listed {
        assert!(out.join(f).is_file(), "solution.pvd lists {f}, not on disk");
    }
}

/// `scene` run by the library into `out` with a checkpoint every `every` steps, stopped
/// (as by SIGINT) after step `at`: a folder `talus resume` continues from step `at`.
fn interrupted(scene: &Path, out: &Path, every: usize, at: usize) {
    let scene = Scene::from_path(scene).unwrap();
    interrupted_scene(&scene, out, every, at);
}

fn interrupted_scene(scene: &Scene, out: &Path, every: usize, at: usize) {
    let options = RunOptions {
        write_fields: true,
        checkpoint_every: every,
        observer: Some(std::sync::Arc::new(move |p: &StepProgress| {
            if p.step == at {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })),
        ..RunOptions::new(out)
    };
    match run_scene(scene, &options) {
        Err(RunError::Interrupted { step, .. }) => assert_eq!(step, at),
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("the run was not interrupted"),
    }
}

/// The checkpoint's header and JSON.
fn checkpoint_parts(out: &Path) -> (String, serde_json::Value) {
    let bytes = std::fs::read(out.join("checkpoint/last.checkpoint")).unwrap();
    let at = bytes.iter().position(|&b| b == b'\n').unwrap();
    let header = String::from_utf8(bytes[..at].to_vec()).unwrap();
    (header, serde_json::from_slice(&bytes[at + 1..]).unwrap())
}

/// Rewrites the checkpoint with `payload`, its header's length and hash made right (the
/// other fields, `history` among them, kept): a well-formed checkpoint.
fn forge(out: &Path, header: &str, payload: &serde_json::Value) {
    let payload = serde_json::to_vec(payload).unwrap();
    let fnv = payload.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    let header: Vec<String> = header
        .split(' ')
        .map(|w| match w.split_once('=') {
            Some(("bytes", _)) => format!("bytes={}", payload.len()),
            Some(("fnv1a64", _)) => format!("fnv1a64={fnv:016x}"),
            _ => w.to_string(),
        })
        .collect();
    let mut bytes = format!("{}\n", header.join(" ")).into_bytes();
    bytes.extend(payload);
    std::fs::write(out.join("checkpoint/last.checkpoint"), bytes).unwrap();
}

#[test]
fn two_resumes_of_one_folder_at_once_one_proceeds_and_every_step_is_once() {
    let scene = paper_footing("together.toml", 60, &[]);
    let out = out_dir("together");
    interrupted(&scene, &out, 5, 5);
    let folder = out.display().to_string();
    let spawn = || talus(&["resume", &folder]).spawn().unwrap();
    let (a, b) = (spawn(), spawn());
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    let (ok, refused) = match (a.status.code(), b.status.code()) {
        (Some(0), _) => (a, b),
        (_, Some(0)) => (b, a),
        _ => panic!("neither resume finished:\n{}\n{}", stderr(&a), stderr(&b)),
    };
    assert_ok(&ok);
    assert_refused(
        &refused,
        &[
            // (Its pid too, unless read in the microseconds before the holder wrote it.)
            &format!("the output folder {folder} is in use by another talus run or resume"),
            "nothing in it was changed",
        ],
    );
    assert_eq!(history_steps(&out), (0..=60).collect::<Vec<_>>());
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"finished\""), "{summary}");
    assert_every_listed_file_exists(&out);
    assert!(
        !out.join(folder::LOCK_FILE).exists(),
        "the lock is released"
    );
}

#[test]
fn a_folder_in_use_is_refused_to_a_run_and_a_resume_and_left_as_it_was() {
    let scene = footing("in_use.toml", 10, &[]);
    let out = out_dir("in_use");
    interrupted(&scene, &out, 5, 5);
    // This test's process holds the folder, as a running `talus` would.
    let held = folder::lock(&out).unwrap();
    let before = snapshot(&out);
    assert!(before.contains_key(folder::LOCK_FILE));
    let words = [
        format!(
            "the output folder {} is in use by another talus run or resume (pid {})",
            out.display(),
            std::process::id()
        ),
        "nothing in it was changed".to_string(),
    ];
    let words: Vec<&str> = words.iter().map(String::as_str).collect();
    assert_refused(&resume(&out), &words);
    assert_unchanged(&out, &before);
    assert_refused(&run(&scene, &out, None), &words);
    assert_unchanged(&out, &before);
    // Released: the folder resumes, and the lock goes with the run.
    drop(held);
    assert!(!out.join(folder::LOCK_FILE).exists());
    assert_ok(&resume(&out));
    assert_eq!(history_steps(&out), (0..=10).collect::<Vec<_>>());
    assert!(!out.join(folder::LOCK_FILE).exists());
}

#[test]
fn sigint_releases_the_folder_after_the_step_in_progress() {
    let scene = paper_footing("sigint.toml", 300, &[]);
    let out = out_dir("sigint");
    let child = talus(&[
        "run",
        &scene.display().to_string(),
        "--out",
        &out.display().to_string(),
        "--checkpoint-every",
        "5",
    ])
    .spawn()
    .unwrap();
    let start = std::time::Instant::now();
    while !out.join("checkpoint/last.checkpoint").exists() {
        assert!(start.elapsed().as_secs() < 60, "no checkpoint");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    assert!(out.join(folder::LOCK_FILE).exists(), "held while it runs");
    let o = common::signal(child, "INT");
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(!out.join(folder::LOCK_FILE).exists(), "released");
    // Free for the next run: the resume takes it (and is interrupted in turn).
    let child = talus(&["resume", &out.display().to_string()])
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(500));
    let o = common::signal(child, "INT");
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(!out.join(folder::LOCK_FILE).exists());
}

#[test]
fn a_refused_resume_leaves_summary_json_and_every_file_as_they_were() {
    let scene = footing("refused.toml", 10, &[]);
    let out = out_dir("refused");
    interrupted(&scene, &out, 5, 7);
    let history = out.join("history.csv");
    let good_history = std::fs::read(&history).unwrap();
    let (header, good) = checkpoint_parts(&out);
    assert!(header.contains(" history="), "{header}");

    // A history.csv that does not reach the checkpoint's step.
    let short: String = String::from_utf8(good_history.clone())
        .unwrap()
        .lines()
        .take(4)
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&history, short).unwrap();
    let before = snapshot(&out);
    assert!(before.contains_key("summary.json"));
    assert_refused(
        &resume(&out),
        &[
            &history.display().to_string(),
            "3 complete rows after the header, the checkpoint needs 8",
        ],
    );
    assert_unchanged(&out, &before);
    std::fs::write(&history, &good_history).unwrap();

    // A well-formed checkpoint whose outputs cannot be restored: refused by the run loop,
    // before it removes summary.json or cuts history.csv.
    let mut broken = good.clone();
    broken["outputs"].as_object_mut().unwrap().remove("curve");
    forge(&out, &header, &broken);
    let before = snapshot(&out);
    assert_refused(&resume(&out), &["its FEM outputs", "curve"]);
    assert_unchanged(&out, &before);

    // The same folder with its own checkpoint resumes: the refusals were theirs.
    forge(&out, &header, &good);
    assert_ok(&resume(&out));
    assert_eq!(history_steps(&out), (0..=10).collect::<Vec<_>>());
}

#[test]
fn a_fresh_run_clears_what_an_earlier_run_left_and_keeps_the_rest() {
    let scene = footing("fresh.toml", 20, &[]);
    let out = out_dir("fresh");
    for (name, text) in [
        ("vtu/step_00999.vtu", "stale"),
        ("vtu/.step_00998.partial.vtu", "stale"),
        ("vtu/mine.vtu", "the user's"),
        ("summary.json", "{\"old\": true}"),
        ("history.csv", "step\n0\n1\n"),
        ("solution.pvd", "old"),
        ("checkpoint/last.checkpoint", "old"),
        ("snapshots/step_00100.png", "old"),
        ("trials_old.csv", "old"),
        ("plastic_strain.png", "old"),
        ("notes.txt", "the user's"),
        ("history.csv.bak", "the user's"),
    ] {
        let path = out.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    let o = run(&scene, &out, None);
    assert_ok(&o);
    let err = stderr(&o);
    assert!(
        err.contains(&format!(
            "cleared 9 file(s) an earlier run left in {}",
            out.display()
        )),
        "{err}"
    );
    assert!(err.contains("vtu/step_00999.vtu"), "{err}");
    for gone in [
        "vtu/step_00999.vtu",
        "vtu/.step_00998.partial.vtu",
        "checkpoint",
        "snapshots",
        "trials_old.csv",
        "plastic_strain.png",
    ] {
        assert!(!out.join(gone).exists(), "{gone} left");
    }
    for kept in ["vtu/mine.vtu", "notes.txt", "history.csv.bak"] {
        assert!(out.join(kept).exists(), "{kept} removed");
    }
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"finished\""), "{summary}");
    assert_eq!(history_steps(&out), (0..=20).collect::<Vec<_>>());
    // The run's VTUs are exactly those its collection lists.
    let mut on_disk: Vec<String> = std::fs::read_dir(out.join("vtu"))
        .unwrap()
        .map(|e| format!("vtu/{}", e.unwrap().file_name().to_string_lossy()))
        .filter(|n| n != "vtu/mine.vtu")
        .collect();
    on_disk.sort();
    assert_eq!(on_disk, pvd_files(&out));
    assert_every_listed_file_exists(&out);
}

#[test]
fn a_resume_after_vtu_was_removed_lists_only_files_that_exist() {
    let scene = footing("no_vtu.toml", 20, &[]);
    let out = out_dir("no_vtu");
    interrupted(&scene, &out, 5, 10);
    assert!(pvd_files(&out).contains(&"vtu/step_00005.vtu".to_string()));
    std::fs::remove_dir_all(out.join("vtu")).unwrap();
    let o = resume(&out);
    assert_ok(&o);
    let err = stderr(&o);
    assert!(
        err.contains(&format!(
            "3 file(s) of the checkpoint's solution.pvd are missing from {}",
            out.display()
        )),
        "{err}"
    );
    assert_every_listed_file_exists(&out);
    assert_eq!(
        pvd_files(&out),
        ["vtu/step_00015.vtu", "vtu/step_00020.vtu"],
        "the VTUs written after the checkpoint"
    );
    assert_eq!(history_steps(&out), (0..=20).collect::<Vec<_>>());
}

#[test]
fn another_runs_checkpoint_copied_into_a_folder_is_refused() {
    // Folder `mine`: the scene as it was. Folder `theirs`: the same file edited since
    // (another scene), and its checkpoint copied over mine: its scene file is unchanged
    // since *its* run, so only the folder can tell.
    let scene = footing("copied.toml", 20, &[]);
    let mine = out_dir("copied_mine");
    assert_ok(&run(&scene, &mine, Some(5)));
    let theirs = out_dir("copied_theirs");
    let scene = footing(
        "copied.toml",
        20,
        &[("cohesion = 2.0e3", "cohesion = 2.5e3")],
    );
    assert_ok(&run(&scene, &theirs, Some(5)));
    let own = std::fs::read(mine.join("checkpoint/last.checkpoint")).unwrap();
    std::fs::copy(
        theirs.join("checkpoint/last.checkpoint"),
        mine.join("checkpoint/last.checkpoint"),
    )
    .unwrap();
    let before = snapshot(&mine);
    let checkpoint = mine.join("checkpoint/last.checkpoint");
    let words = [
        format!(
            "checkpoint {} is not the one of the run in {}",
            checkpoint.display(),
            mine.display()
        ),
        "resume refused, nothing in the folder was changed".to_string(),
    ];
    let words: Vec<&str> = words.iter().map(String::as_str).collect();
    assert_refused(&resume(&mine), &words);
    assert_unchanged(&mine, &before);

    // Its own checkpoint, its history.csv replaced by the other run's: refused alike.
    std::fs::write(&checkpoint, &own).unwrap();
    std::fs::copy(theirs.join("history.csv"), mine.join("history.csv")).unwrap();
    let before = snapshot(&mine);
    assert_refused(&resume(&mine), &words);
    assert_unchanged(&mine, &before);

    // The same scene run again elsewhere is the same computation: its checkpoint of step
    // 10 (the key leaves out the wall time) continues this folder as its own would, each
    // step once, every row (but the wall time) that of the uninterrupted run.
    let uninterrupted = common::history_without_seconds(&theirs);
    let again = out_dir("copied_again");
    interrupted(&scene, &again, 5, 10);
    std::fs::copy(
        again.join("checkpoint/last.checkpoint"),
        theirs.join("checkpoint/last.checkpoint"),
    )
    .unwrap();
    let o = resume(&theirs);
    assert_ok(&o);
    assert!(
        stderr(&o).contains("checkpoint of step 10"),
        "{}",
        stderr(&o)
    );
    assert_eq!(history_steps(&theirs), (0..=20).collect::<Vec<_>>());
    assert_eq!(common::history_without_seconds(&theirs), uninterrupted);
}

#[test]
fn an_in_memory_scenes_checkpoint_resumes_with_the_text_it_holds() {
    // A scene without a file (the Python package's `Scene.from_toml`) is not the built-in
    // footing: its checkpoint holds the text.
    let path = footing("in_memory.toml", 10, &[]);
    let text = std::fs::read_to_string(&path).unwrap();
    let scene = Scene::parse(&text, None).unwrap();
    let out = out_dir("in_memory");
    interrupted_scene(&scene, &out, 5, 5);
    let o = resume(&out);
    assert_ok(&o);
    assert!(
        stderr(&o)
            .contains("resuming the scene the checkpoint holds from its checkpoint of step 5"),
        "{}",
        stderr(&o)
    );
    assert_eq!(history_steps(&out), (0..=10).collect::<Vec<_>>());
}
