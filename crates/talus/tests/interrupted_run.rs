//! SIGINT and SIGTERM through the `talus` binary (`docs/scenes.md`, 'Durable outputs'): the
//! run finishes its step, then leaves `summary.json` with status `interrupted`, a
//! `solution.pvd` that lists only complete VTU files (each ending in `</VTKFile>`), the
//! plots, no temporary file, and exits 130.
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::Duration;

use crate::common;
fn interrupt_footing(signal: &str) {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("interrupted_run")
        .join(signal);
    let _ = std::fs::remove_dir_all(&out);
    // The built-in footing, 300 steps (several seconds), VTUs every 30 steps.
    let child = Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("run")
        .arg("--out")
        .arg(&out)
        .env("TALUS_LOG", "warn")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Until a few steps are written.
    let history = out.join("history.csv");
    for _ in 0..600 {
        let rows = std::fs::read_to_string(&history).map_or(0, |t| t.lines().count());
        if rows > 40 {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let output = common::signal(child, signal);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted after step"), "{stderr}");

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "interrupted");
    let steps = summary["steps"].as_u64().unwrap();
    assert!(steps < 300, "{summary}");
    // history.csv: the header, step 0 and every completed step.
    let rows = std::fs::read_to_string(&history).unwrap().lines().count() as u64;
    assert_eq!(rows, steps + 2);

    let pvd = std::fs::read_to_string(out.join("solution.pvd")).unwrap();
    assert!(pvd.trim_end().ends_with("</VTKFile>"), "{pvd}");
    let files: Vec<&str> = pvd
        .lines()
        .filter_map(|l| l.split("file=\"").nth(1))
        .map(|f| f.split('"').next().unwrap())
        .collect();
    // Step 0, every 30 steps, and the last completed step.
    assert_eq!(files.first(), Some(&"vtu/step_00000.vtu"));
    assert_eq!(
        files.last().copied(),
        Some(format!("vtu/step_{steps:05}.vtu").as_str())
    );
    for f in &files {
        let vtu = std::fs::read_to_string(out.join(f)).unwrap();
        assert!(vtu.trim_end().ends_with("</VTKFile>"), "{f} is incomplete");
    }
    assert!(out.join("force_displacement.png").exists());
    assert!(out.join("plastic_strain.png").exists());
    for dir in [out.clone(), out.join("vtu")] {
        for e in std::fs::read_dir(dir).unwrap() {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            assert!(!name.contains(".partial"), "{name} left behind");
        }
    }
}

#[test]
fn sigint_leaves_complete_outputs_and_exits_130() {
    interrupt_footing("INT");
}

#[test]
fn sigterm_leaves_complete_outputs_and_exits_130() {
    interrupt_footing("TERM");
}
