//! Logs and version of the `talus` binary: no colour codes when stderr is not a terminal,
//! an invalid `TALUS_LOG` reported, `--version` naming the commit it was built from.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common;
fn footing_run(name: &str, log: &str) -> Output {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("cli_logs")
        .join(name);
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/footing.toml"),
    )
    .unwrap()
    .replace("steps = 300", "steps = 2");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(dir.join("out"))
        .env("TALUS_LOG", log)
        .output()
        .unwrap()
}

#[test]
fn logs_into_a_pipe_carry_no_colour_codes() {
    let out = footing_run("plain", "info");
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("INFO"), "{err}");
    assert!(!err.contains('\u{1b}'), "escape codes in: {err:?}");
}

#[test]
fn an_invalid_talus_log_is_reported() {
    for bad in ["talus=loud", "verbose"] {
        let out = footing_run("bad_filter", bad);
        assert!(out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("TALUS_LOG") && err.contains(bad),
            "{bad}: {err}"
        );
    }
    let out = footing_run("good_filter", "talus=warn");
    assert!(!String::from_utf8_lossy(&out.stderr).contains("TALUS_LOG"));
}

#[test]
fn version_names_the_commit() {
    let out = Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("--version")
        .output()
        .unwrap();
    let version = String::from_utf8_lossy(&out.stdout);
    let head = Command::new("git")
        .args(["rev-parse", "--short=12", "HEAD"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown".into());
    assert!(
        version.contains(&format!("(commit {head})")),
        "{version} against {head}"
    );
}

/// A 300-step run piped to a file prints a line per tenth of the run and its summary, not a
/// line per step (at most 40 lines); `-v` gives every step. The cadence counts steps, not
/// cells: the footing on 8 × 4 cells, no plots; `-v` on 30 steps.
#[test]
fn a_piped_run_prints_a_line_per_tenth() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("cli_logs")
        .join("tenths");
    std::fs::create_dir_all(&dir).unwrap();
    let run = |steps: usize, verbose: bool| {
        let text = common::replaced(common::FOOTING, "cells = [32, 14]", "cells = [8, 4]");
        let text = common::replaced(&text, "plots = true", "plots = false");
        let text = common::replaced(&text, "steps = 300", &format!("steps = {steps}"));
        let scene = dir.join(format!("scene_{steps}.toml"));
        std::fs::write(&scene, text).unwrap();
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_talus"));
        cmd.arg("run").arg(&scene).arg("--out").arg(dir.join("out"));
        if verbose {
            cmd.arg("-v");
        }
        cmd.env_remove("TALUS_LOG").output().unwrap()
    };
    let out = run(300, false);
    assert!(out.status.success());
    let lines = String::from_utf8_lossy(&out.stderr).lines().count()
        + String::from_utf8_lossy(&out.stdout).lines().count();
    assert!(lines <= 40, "{lines} lines");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("step 300/300 (100%)"), "{err}");
    assert!(err.contains("step 30/300 (10%)"), "{err}");
    let verbose = run(30, true);
    assert!(verbose.status.success());
    let steps = String::from_utf8_lossy(&verbose.stderr)
        .lines()
        .filter(|l| l.contains(" step ") && l.contains("iterations="))
        .count();
    assert_eq!(steps, 30, "-v logs every step");
}

/// A factor-of-safety search piped to a file says each trial once, as an outcome at INFO,
/// with no WARN line for the trials that fail as expected (`scenes/slope.toml`: ten or so
/// trials, some failing).
#[test]
fn a_factor_of_safety_search_says_each_trial_once() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("cli_logs")
        .join("slope");
    // A fresh folder: a rerun would otherwise warn that it cleared the last run's files.
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("run")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/slope.toml"))
        .arg("--out")
        .arg(dir.join("out"))
        .env_remove("TALUS_LOG")
        .output()
        .unwrap();
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    let trials = err.lines().filter(|l| l.contains(" trial factor=")).count();
    let history = std::fs::read_to_string(dir.join("out/history.csv")).unwrap();
    // history.csv: the header, row 0 (the loading), one row per trial.
    assert_eq!(trials, history.lines().count() - 2, "{err}");
    assert!(err.contains("outcome=\"fails\""), "some trials fail: {err}");
    assert!(!err.contains("WARN"), "{err}");
    assert!(err.lines().count() <= 40, "{err}");
}

/// The run's line on stdout gives its cost: accepted and failed Newton iterations,
/// sub-steps and the smallest sub-step, the sums and minimum of history.csv's columns.
#[test]
fn the_runs_line_gives_its_iterations_substeps_and_smallest_step() {
    let out = footing_run("cost", "warn");
    assert!(out.status.success());
    let stdout = String::from_utf8_lossy(&out.stdout);
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_logs/cost/out");
    // Rows after step 0 (the initial state).
    let sum = |name: &str| common::history_column(&dir, name)[1..].iter().sum::<f64>() as usize;
    let expected = format!(
        "Newton iterations {} accepted + {} failed",
        sum("newton_iterations"),
        sum("failed_newton_iterations")
    );
    assert!(stdout.contains(&expected), "{expected}: {stdout}");
    assert!(
        stdout.contains(&format!("{} sub-steps", sum("substeps"))),
        "{stdout}"
    );
    // Two steps of h = 1e-2 s, none halved.
    assert!(stdout.contains("smallest h 1.000e-2 s"), "{stdout}");
}
