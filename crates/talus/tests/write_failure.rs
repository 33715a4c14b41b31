//! A file that cannot be written half way through a run (a full disk, a folder taken
//! away; `docs/scenes.md`, 'Durable outputs'), through the `talus` binary: the run stops with
//! exit code 5 and an error naming the file, `summary.json` says `failed` and why,
//! `history.csv` keeps the completed steps, `solution.pvd` lists only the VTUs on disk, and
//! no file is left half written. The failure is made by a directory standing where the
//! VTU of step 20 writes its temporary copy (`.step_00020.partial.vtu`): creating that
//! file fails exactly as on a full disk, at a chosen step, without root.
use std::path::{Path, PathBuf};
use std::process::Command;

fn scene(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/footing.toml"),
    )
    .unwrap();
    assert!(text.contains("steps = 300") && text.contains("vtu_every = 30"));
    let text = text
        .replace("steps = 300", "steps = 40")
        .replace("vtu_every = 30", "vtu_every = 10")
        .replace("plots = true", "plots = false");
    let path = dir.join("footing.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn an_unwritable_vtu_at_step_20_stops_the_run_with_a_failed_summary() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("write_failure");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scene = scene(&dir);
    let out = dir.join("out");
    std::fs::create_dir_all(out.join("vtu").join(".step_00020.partial.vtu")).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_talus"))
        .args([
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .env("TALUS_LOG", "warn")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(5), "{stderr}");
    let last = stderr.lines().last().unwrap_or_default();
    assert!(last.contains("step_00020.vtu"), "{last}");

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "failed");
    let error = summary["error"].as_str().unwrap();
    assert!(
        error.starts_with("step 20:") && error.contains("step_00020.vtu"),
        "{error}"
    );
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let steps: Vec<&str> = history
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(steps.first(), Some(&"0"));
    assert_eq!(steps.last(), Some(&"20"));

    let pvd = std::fs::read_to_string(out.join("solution.pvd")).unwrap();
    assert!(pvd.trim_end().ends_with("</VTKFile>"), "{pvd}");
    let listed: Vec<&str> = pvd
        .split("file=\"")
        .skip(1)
        .map(|s| &s[..s.find('"').unwrap()])
        .collect();
    assert_eq!(listed, ["vtu/step_00000.vtu", "vtu/step_00010.vtu"]);
    let mut on_disk: Vec<String> = std::fs::read_dir(out.join("vtu"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    on_disk.sort();
    // Our obstacle stays; nothing else half written.
    assert_eq!(
        on_disk,
        [
            ".step_00020.partial.vtu",
            "step_00000.vtu",
            "step_00010.vtu"
        ]
    );
    for f in &listed {
        let text = std::fs::read_to_string(out.join(f)).unwrap();
        assert!(text.trim_end().ends_with("</VTKFile>"), "{f}");
    }
}
