//! Checkpoints and `talus resume` through the `talus` binary (`docs/scenes.md`,
//! 'Checkpoints and resume'): a run killed (SIGKILL) or interrupted (SIGINT) after a
//! checkpoint, then resumed, ends with the same `history.csv` (the `seconds` column
//! aside), the same VTU files, `solution.pvd`, `summary.json` and final checkpoint, byte for
//! byte, as the run that was never stopped (FEM, 2D and 3D MPM); a changed scene or a
//! damaged checkpoint is refused with exit 1.
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use crate::common;
fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("checkpoint_resume")
}

/// `scenes/NAME` with `replacements` made (each must apply), written to `root()/file`.
fn scene(name: &str, file: &str, replacements: &[(&str, &str)]) -> PathBuf {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    let mut text = std::fs::read_to_string(path).unwrap();
    for (from, to) in replacements {
        assert!(text.contains(from), "{name} has no `{from}`");
        text = text.replace(from, to);
    }
    std::fs::create_dir_all(root()).unwrap();
    let out = root().join(file);
    // Renamed into place: the tests run at once, and a run reading the scene while
    // another test rewrites it must see the whole text.
    let tmp = root().join(format!("{file}.{:?}", std::thread::current().id()));
    std::fs::write(&tmp, text).unwrap();
    std::fs::rename(&tmp, &out).unwrap();
    out
}

/// The paper footing, 40 steps, VTUs every 10.
fn footing() -> PathBuf {
    scene(
        "footing.toml",
        "footing40.toml",
        &[
            ("steps = 300", "steps = 40"),
            ("vtu_every = 30", "vtu_every = 10"),
        ],
    )
}

/// The column collapse a = 2, 40 steps, VTUs and snapshots every 10; at most 10 Newton
/// iterations, so that steps 1 to 13 are halved and the stepper remembers it (the
/// step control, `talus_engine::StepControl`) across the checkpoint of step 10.
fn column() -> PathBuf {
    scene(
        "column_a2.toml",
        "column40.toml",
        &[
            ("steps = 1072", "steps = 40"),
            ("vtu_every = 108", "vtu_every = 10"),
            ("snapshot_every = 108", "snapshot_every = 20"),
            ("[mpm]", "[solver]\nmax_iterations = 10\n\n[mpm]"),
        ],
    )
}

/// The 3D column collapse (`scenes/column_3d.toml`, 395 particles), 40 steps, VTUs every
/// 10: a 3D MPM run checkpoints and resumes as a 2D one.
fn column_3d() -> PathBuf {
    scene(
        "column_3d.toml",
        "column3d40.toml",
        &[
            ("steps = 786", "steps = 40"),
            ("vtu_every = 78", "vtu_every = 10"),
        ],
    )
}

fn talus(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_talus"));
    c.args(args)
        .env("TALUS_LOG", "warn")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    c
}

fn out_dir(name: &str) -> PathBuf {
    let out = root().join(name);
    let _ = std::fs::remove_dir_all(&out);
    out
}

fn run(scene: &Path, out: &Path, every: Option<usize>) -> Output {
    let mut args = vec![
        "run".to_string(),
        scene.display().to_string(),
        "--out".into(),
        out.display().to_string(),
    ];
    if let Some(n) = every {
        args.extend(["--checkpoint-every".into(), n.to_string()]);
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    talus(&args).output().unwrap()
}

fn resume(out: &Path) -> Output {
    talus(&["resume", &out.display().to_string()])
        .output()
        .unwrap()
}

fn assert_ok(o: &Output) {
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The checkpoint's step, from its header line.
fn checkpoint_step(out: &Path) -> Option<usize> {
    let text = std::fs::read(out.join("checkpoint/last.checkpoint")).ok()?;
    let header =
        String::from_utf8_lossy(&text[..text.iter().position(|&b| b == b'\n')?]).into_owned();
    header
        .split(' ')
        .find_map(|w| w.strip_prefix("step="))?
        .parse()
        .ok()
}

fn history_rows(out: &Path) -> usize {
    std::fs::read_to_string(out.join("history.csv")).map_or(0, |t| t.lines().count())
}

/// A run with a checkpoint every `every` steps, sent `signal` once its checkpoint reaches
/// `at` and `history.csv` has `rows_after` rows past it (polled every 2 ms); returns its
/// exit and the checkpoint's step then.
fn stopped_run(
    scene: &Path,
    out: &Path,
    every: usize,
    at: usize,
    rows_after: usize,
    signal: &str,
) -> (Output, usize) {
    let mut child: Child = talus(&[
        "run",
        &scene.display().to_string(),
        "--out",
        &out.display().to_string(),
        "--checkpoint-every",
        &every.to_string(),
    ])
    .spawn()
    .unwrap();
    let start = Instant::now();
    while checkpoint_step(out).is_none_or(|s| s < at || history_rows(out) < s + 2 + rows_after) {
        assert!(start.elapsed() < Duration::from_secs(120), "no checkpoint");
        if child.try_wait().unwrap().is_some() {
            let o = child.wait_with_output().unwrap();
            panic!(
                "the run ended before its checkpoint of step {at}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let output = common::signal(child, signal);
    let step = checkpoint_step(out).unwrap();
    eprintln!(
        "{}: SIG{signal} with the checkpoint of step {step} and {} rows in history.csv",
        scene.display(),
        history_rows(out)
    );
    (output, step)
}

/// The files of `dir` (relative names, sorted) and their bytes.
fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .map(|d| {
            d.map(|e| {
                let e = e.unwrap();
                (
                    e.file_name().to_string_lossy().into_owned(),
                    std::fs::read(e.path()).unwrap(),
                )
            })
            .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Everything but the timings and the plots (PNG) is the same, byte for byte.
fn assert_same_run(reference: &Path, resumed: &Path, steps: usize) {
    let (a, b) = (
        common::history_without_seconds(reference),
        common::history_without_seconds(resumed),
    );
    assert_eq!(a.len(), steps + 2, "rows of {}", reference.display());
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        assert_eq!(x, y, "history.csv line {}", k + 1);
    }
    assert_eq!(a.len(), b.len(), "history.csv rows");
    let (va, vb) = (files(&reference.join("vtu")), files(&resumed.join("vtu")));
    assert!(va.iter().any(|(n, _)| *n == format!("step_{steps:05}.vtu")));
    assert_eq!(
        va.iter().map(|f| &f.0).collect::<Vec<_>>(),
        vb.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    for ((name, x), (_, y)) in va.iter().zip(&vb) {
        assert!(x == y, "vtu/{name} differs");
    }
    for file in ["solution.pvd", "summary.json"] {
        let x = std::fs::read(reference.join(file)).unwrap();
        let y = std::fs::read(resumed.join(file)).unwrap();
        assert!(x == y, "{file} differs");
    }
    // The state after the last step, bit for bit: every particle or Gauss point value,
    // the predictor's stress rate, the collapse watch, the outputs' record.
    let x = std::fs::read(reference.join("checkpoint/last.checkpoint")).unwrap();
    let y = std::fs::read(resumed.join("checkpoint/last.checkpoint")).unwrap();
    assert_eq!(checkpoint_step(reference), Some(steps));
    assert!(x == y, "final checkpoints differ");
}

/// The footing run from start to end with checkpoints every 10 steps (shared by the
/// tests), checked against the same run without checkpoints: writing them changes nothing.
fn footing_reference() -> &'static Path {
    static REFERENCE: OnceLock<PathBuf> = OnceLock::new();
    REFERENCE.get_or_init(|| {
        let scene = footing();
        let out = out_dir("footing_reference");
        assert_ok(&run(&scene, &out, Some(10)));
        let plain = out_dir("footing_plain");
        assert_ok(&run(&scene, &plain, None));
        assert_eq!(
            common::history_without_seconds(&out),
            common::history_without_seconds(&plain)
        );
        assert!(files(&out.join("vtu")) == files(&plain.join("vtu")));
        out
    })
}

#[test]
fn fem_footing_killed_half_way_then_resumed_matches_the_uninterrupted_run() {
    let reference = footing_reference();
    let out = out_dir("footing_killed");
    // Killed with a row past the checkpoint: resume cuts it.
    let (killed, step) = stopped_run(&footing(), &out, 10, 20, 1, "KILL");
    assert_eq!(
        killed.status.code(),
        None,
        "SIGKILL ends it without an exit code"
    );
    assert!(
        (20..40).contains(&step),
        "killed at the checkpoint of step {step}"
    );
    assert!(!out.join("summary.json").exists());
    let resumed = resume(&out);
    assert_ok(&resumed);
    assert!(String::from_utf8_lossy(&resumed.stderr).contains(&format!("step {step} of 40")));
    assert_same_run(reference, &out, 40);
}

#[test]
fn fem_footing_interrupted_then_resumed_matches_the_uninterrupted_run() {
    let reference = footing_reference();
    let out = out_dir("footing_sigint");
    let (stopped, step) = stopped_run(&footing(), &out, 10, 10, 0, "INT");
    assert_eq!(
        stopped.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&stopped.stderr)
    );
    // The interruption wrote its own checkpoint, at the step the run stopped after.
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        summary.contains(&format!("\"steps\": {step},")),
        "checkpoint at {step}: {summary}"
    );
    assert!(step < 40, "interrupted after the end");
    let resumed = resume(&out);
    assert_ok(&resumed);
    assert_same_run(reference, &out, 40);
}

#[test]
fn mpm_column_killed_half_way_then_resumed_matches_the_uninterrupted_run() {
    let scene = column();
    let reference = out_dir("column_reference");
    assert_ok(&run(&scene, &reference, Some(5)));
    let out = out_dir("column_killed");
    let (killed, step) = stopped_run(&scene, &out, 5, 10, 1, "KILL");
    assert_eq!(killed.status.code(), None);
    assert!(
        (10..40).contains(&step),
        "killed at the checkpoint of step {step}"
    );
    let bytes = std::fs::read(out.join("checkpoint/last.checkpoint")).unwrap();
    let at = bytes.iter().position(|&b| b == b'\n').unwrap();
    let saved: serde_json::Value = serde_json::from_slice(&bytes[at + 1..]).unwrap();
    if step <= 13 {
        assert!(
            saved["stepper"]["control"]["level"].as_u64() > Some(0),
            "the set-up must carry a halving over the checkpoint: {}",
            saved["stepper"]
        );
    }
    assert_ok(&resume(&out));
    assert_same_run(&reference, &out, 40);
    assert!(files(&reference.join("snapshots")) == files(&out.join("snapshots")));
}

#[test]
fn mpm_3d_column_killed_half_way_then_resumed_matches_the_uninterrupted_run() {
    let scene = column_3d();
    let reference = out_dir("column_3d_reference");
    assert_ok(&run(&scene, &reference, Some(5)));
    let out = out_dir("column_3d_killed");
    let (killed, step) = stopped_run(&scene, &out, 5, 10, 1, "KILL");
    assert_eq!(killed.status.code(), None);
    assert!(
        (10..40).contains(&step),
        "killed at the checkpoint of step {step}"
    );
    assert_ok(&resume(&out));
    assert_same_run(&reference, &out, 40);
}

fn assert_refused(o: &Output, words: &str) {
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains(words), "expected `{words}` in: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn a_changed_scene_or_a_damaged_checkpoint_is_refused_with_exit_1() {
    let scene = scene(
        "footing.toml",
        "footing4.toml",
        &[("steps = 300", "steps = 4")],
    );
    let out = out_dir("refused");
    assert_ok(&run(&scene, &out, Some(2)));
    let checkpoint = out.join("checkpoint/last.checkpoint");
    let good = std::fs::read(&checkpoint).unwrap();
    let text = std::fs::read_to_string(&scene).unwrap();

    std::fs::write(&scene, format!("{text}\n# edited\n")).unwrap();
    assert_refused(&resume(&out), "changed since the checkpoint of step 4");
    std::fs::write(&scene, &text).unwrap();

    // One digit of the state changed: the length is right, the hash is not.
    let mut bad = good.clone();
    let at = bad.len() / 2
        + bad[bad.len() / 2..]
            .iter()
            .position(|b| b.is_ascii_digit())
            .unwrap();
    bad[at] = if bad[at] == b'1' { b'2' } else { b'1' };
    std::fs::write(&checkpoint, &bad).unwrap();
    assert_refused(&resume(&out), "is corrupt (content hash");
    std::fs::write(&checkpoint, &good[..good.len() - 100]).unwrap();
    assert_refused(&resume(&out), "is corrupt");
    std::fs::write(&checkpoint, b"not a checkpoint").unwrap();
    assert_refused(&resume(&out), "is corrupt (no header line)");

    // A well-formed checkpoint of another model (one stress point fewer): its sizes are
    // refused before any step indexes with them.
    let at = good.iter().position(|&b| b == b'\n').unwrap();
    let mut other: serde_json::Value = serde_json::from_slice(&good[at + 1..]).unwrap();
    let sigma = other["state"]["sigma"].as_array_mut().unwrap();
    sigma.truncate(sigma.len() - 4);
    let payload = serde_json::to_vec(&other).unwrap();
    let fnv = payload.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    let mut forged = format!(
        "talus-checkpoint format=1 step=4 bytes={} fnv1a64={fnv:016x}\n",
        payload.len()
    )
    .into_bytes();
    forged.extend(payload);
    std::fs::write(&checkpoint, forged).unwrap();
    assert_refused(&resume(&out), "its state has sizes");

    // A history.csv that does not reach the checkpoint's step.
    std::fs::write(&checkpoint, &good).unwrap();
    let rows = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let short: String = rows.lines().take(3).map(|l| format!("{l}\n")).collect();
    std::fs::write(out.join("history.csv"), short).unwrap();
    assert_refused(&resume(&out), "2 complete rows after the header");
    std::fs::write(out.join("history.csv"), &rows).unwrap();

    std::fs::remove_file(&checkpoint).unwrap();
    assert_refused(&resume(&out), "no checkpoint in");
    assert_refused(&resume(&root().join("no_such_folder")), "no checkpoint in");

    // The untouched folder resumes (nothing left to step): the refusals above were theirs.
    std::fs::write(&checkpoint, &good).unwrap();
    assert_ok(&resume(&out));
}
