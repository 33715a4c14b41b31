//! A `[mesh.rectangle]` whose cells span more than 1e3 in size along an axis draws a
//! warning naming the key, the span and a ratio that would make it 100
//! (`docs/performance.md`, 'Grading kept while refining'); the shipped footing does not.
use std::process::Command;

mod common;
use common::{replaced, target_tmp_dir, FOOTING};

/// `talus run`'s stderr at `warn` for the footing with `cells` and one step.
fn warnings(name: &str, cells: &str) -> String {
    let dir = target_tmp_dir("strong_grading", name);
    let text = replaced(FOOTING, "cells = [32, 14]", &format!("cells = {cells}"));
    let text = replaced(&text, "steps = 300", "steps = 1");
    let text = replaced(&text, "plots = true", "plots = false");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(dir.join("out"))
        .env("TALUS_LOG", "warn")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn a_grading_kept_over_many_cells_is_warned_with_a_milder_ratio() {
    // ratio 1.1 from the surface over 100 cells: 1.1^99 = 1.25e4.
    let stderr = warnings("steep", "[8, 100]");
    let line = stderr
        .lines()
        .find(|l| l.contains("mesh.rectangle.ratio"))
        .unwrap_or_else(|| panic!("no warning: {stderr}"));
    assert!(line.contains("along y") && line.contains("1.3e4"), "{line}");
    // The ratio offered makes the span 100: 100^(1/99) = 1.0476.
    assert!(line.contains("ratio = 1.0476"), "{line}");
    assert!(!stderr.contains("along x"), "x is uniform: {stderr}");
}

#[test]
fn the_shipped_footing_draws_no_grading_warning() {
    let stderr = warnings("shipped", "[32, 14]");
    assert!(!stderr.contains("mesh.rectangle.ratio"), "{stderr}");
}
