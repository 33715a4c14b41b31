//! The exit code table (README, 'Exit codes'; `talus::exit`) through the `talus` binary:
//! each cause gets its own code and `--help` lists them. Collapse (4) is tested in
//! `collapse.rs`, `talus reduced`'s 3 and 6 in `cli_reduced.rs`.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn talus(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_talus"))
        .args(args)
        .env("TALUS_LOG", "warn")
        .output()
        .unwrap()
}

fn dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("exit_codes")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn footing() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/footing.toml"))
        .unwrap()
}

fn run_scene(name: &str, text: &str, out: Option<&Path>) -> Output {
    let d = dir(name);
    let scene = d.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let out = out.map(Path::to_path_buf).unwrap_or_else(|| d.join("out"));
    talus(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
}

#[test]
fn help_lists_every_exit_code() {
    let out = talus(&["--help"]);
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout);
    for line in [
        "0    success",
        "1    invalid input",
        "2    usage",
        "3    a step did not converge",
        "4    collapsed",
        "5    an output file could not be written",
        "6    `talus reduced`: stopped at the round-off floor",
        "7    `talus verify`: a case failed",
        "130  interrupted",
    ] {
        assert!(help.contains(line), "`{line}` missing from:\n{help}");
    }
}

#[test]
fn usage_errors_exit_2() {
    assert_eq!(talus(&["run", "--no-such-option"]).status.code(), Some(2));
    assert_eq!(talus(&["no-such-command"]).status.code(), Some(2));
}

#[test]
fn a_bad_scene_exits_1() {
    let text = footing().replace("young_modulus = 1.0e9", "young_modulus = -1.0e9");
    let out = run_scene("bad_scene", &text, None);
    assert_eq!(out.status.code(), Some(1));
    let missing = talus(&["run", "/no/such/scene.toml"]);
    assert_eq!(missing.status.code(), Some(1));
}

#[test]
fn a_step_that_does_not_converge_exits_3() {
    let text = footing().replace("steps = 300", "steps = 3")
        + "\n[solver]\nmax_iterations = 1\nmax_step_halvings = 0\n";
    let out = run_scene("not_converged", &text, None);
    assert_eq!(
        out.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn an_output_folder_that_cannot_be_made_exits_5() {
    let d = dir("io");
    // A folder inside a regular file cannot be created.
    let file = d.join("a_file");
    std::fs::write(&file, "").unwrap();
    let text = footing().replace("steps = 300", "steps = 2");
    let out = run_scene("io_scene", &text, Some(&file.join("out")));
    assert_eq!(
        out.status.code(),
        Some(5),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
