//! Collapse (`docs/scenes.md`, 'Collapse'), through the `talus` binary: the paper footing
//! (`scenes/footing.toml`, and its MPM twin `scenes/mpm_footing.toml`) loaded by a pressure
//! on the footing instead of its prescribed velocity. 2 MPa is five times the capacity the
//! velocity-driven run measures (its plateau 1.9517e5 N/m over b = 0.5 m: 390 kPa,
//! `docs/scenes.md`, 'summary.json'): the run ends `collapsed` with exit code 4. 80% of that
//! plateau, 312 kPa, is carried: the run finishes, exit code 0.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const FOOTING_BOUNDARY: &str = r#"[[boundary]]
name = "footing"
nodes = { box = [[-0.25, -1e-9], [0.25, 1e-9]] }
fix = "xy"
velocity = [0.0, -1.0e-3]  # m/s, downward
"#;

const MPM_FOOTING_BOX: &str = r#"[[prescribed]]
name = "footing"
region = [[-0.25, 0.0], [0.25, 0.1875]]
velocity = [0.0, -1.0e-3]  # m/s, downward
"#;

/// The velocity-driven footing's plateau (N/m) over its width (m): its capacity (Pa).
const CAPACITY: f64 = 1.9517e5 / 0.5;

fn scene(file: &str, replaced: &str, by: &str, steps: usize) -> String {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenes")
            .join(file),
    )
    .unwrap();
    assert!(
        text.contains(replaced),
        "{file} no longer holds the footing"
    );
    text.replace(replaced, by)
        .replace("reaction = \"footing\"\n", "")
        .replace("steps = 300", &format!("steps = {steps}"))
}

fn fem_pressure(p: f64, steps: usize) -> String {
    let load = format!(
        "[[pressure]]\nedges = {{ box = [[-0.25, -1e-9], [0.25, 1e-9]] }}\nvalue = {p:e}\n"
    );
    scene("footing.toml", FOOTING_BOUNDARY, &load, steps)
}

fn mpm_pressure(p: f64, steps: usize) -> String {
    let load =
        format!("[[surface_load]]\nregion = [[-0.25, -0.03125], [0.25, 0.0]]\npressure = {p:e}\n");
    scene("mpm_footing.toml", MPM_FOOTING_BOX, &load, steps)
}

/// Runs `text` with `talus run`: its output and summary.json.
fn run(text: &str, name: &str) -> (Output, serde_json::Value) {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("collapse")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("run")
        .arg(&path)
        .arg("--out")
        .arg(dir.join("out"))
        .env("TALUS_LOG", "warn")
        .output()
        .unwrap();
    let summary = std::fs::read_to_string(dir.join("out/summary.json")).unwrap();
    (out, serde_json::from_str(&summary).unwrap())
}

fn last_line(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .last()
        .unwrap_or("")
        .to_string()
}

#[test]
fn fem_footing_under_2_mpa_collapses_with_exit_code_4() {
    let (out, summary) = run(&fem_pressure(2.0e6, 40), "fem_2mpa");
    assert_eq!(
        out.status.code(),
        Some(4),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(summary["status"], "collapsed");
    let step = summary["collapse"]["step"].as_u64().unwrap();
    let time = summary["collapse"]["time"].as_f64().unwrap();
    // Found within the first steps, long before the 40 asked for.
    assert!((1..40).contains(&step), "{summary}");
    assert!((time - step as f64 * 1e-2).abs() < 1e-12, "{summary}");
    assert_eq!(summary["steps"].as_u64(), Some(step));
    assert!(last_line(&out).contains("COLLAPSED"), "{}", last_line(&out));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("collapse at step"), "{stderr}");
}

#[test]
fn fem_footing_at_80_percent_of_its_capacity_is_not_flagged() {
    let (out, summary) = run(&fem_pressure(0.8 * CAPACITY, 60), "fem_80");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(summary["status"], "finished");
    assert!(summary.get("collapse").is_none());
    assert_eq!(summary["steps"].as_u64(), Some(60));
}

#[test]
fn mpm_footing_under_2_mpa_collapses_instead_of_blaming_the_grid() {
    let (out, summary) = run(&mpm_pressure(2.0e6, 40), "mpm_2mpa");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(4), "{stderr}");
    assert_eq!(summary["status"], "collapsed");
    assert!(summary["collapse"]["step"].as_u64().unwrap() < 40);
    assert!(!stderr.contains("enlarge the grid"), "{stderr}");
    assert!(last_line(&out).contains("COLLAPSED"), "{}", last_line(&out));
}

#[test]
fn mpm_footing_at_80_percent_of_its_capacity_is_not_flagged() {
    let (out, summary) = run(&mpm_pressure(0.8 * CAPACITY, 40), "mpm_80");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(summary["status"], "finished");
}
