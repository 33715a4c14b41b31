//! The size check of `talus run` (`docs/scenes.md`, 'Size'), through the binary: a mesh
//! far beyond the memory of any machine is refused at once with the estimate and the
//! override, never an abort; `--allow-large` lets a run past the check.
use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::Instant;

fn run(name: &str, edits: &[(&str, &str)], extra: &[&str]) -> (Output, f64) {
    let mut text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/footing.toml"),
    )
    .unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("size_estimate")
        .join(name);
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let start = Instant::now();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(dir.join("out"))
        .args(extra)
        .env("TALUS_LOG", "warn")
        .output()
        .unwrap();
    (out, start.elapsed().as_secs_f64())
}

#[test]
fn huge_meshes_are_refused_at_once_with_the_estimate() {
    // 2000 × 2000 P2 cells: 2.4e7 Gauss points, about 630 GiB. 1e9 × 1e9: 6e18.
    for cells in ["[2000, 2000]", "[1000000000, 1000000000]"] {
        let cells = format!("cells = {cells}");
        let (out, seconds) = run("huge", &[("cells = [32, 14]", &cells)], &[]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(
            err.contains("stress points") && err.contains("GiB"),
            "{err}"
        );
        assert!(err.contains("--allow-large"), "{err}");
        assert!(seconds < 5.0, "took {seconds} s");
    }
}

#[test]
fn too_much_work_is_refused_unless_allowed() {
    // 5e7 steps × 2 688 Gauss points = 1.3e11 point-steps. With --allow-large the run gets
    // past the check, to the (deliberately) bad material that stops it before a step.
    let steps = ("steps = 300", "steps = 50000000");
    let bad = ("young_modulus = 1.0e9", "young_modulus = -1.0e9");
    let (out, _) = run("work", &[steps, bad], &[]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("point-steps") && err.contains("--allow-large"),
        "{err}"
    );
    assert!(!err.contains("material.young_modulus"), "{err}");
    let (out, _) = run("work_allowed", &[steps, bad], &["--allow-large"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let error = err.lines().find(|l| l.starts_with("error:")).unwrap_or("");
    assert!(error.contains("material.young_modulus"), "{err}");
}
