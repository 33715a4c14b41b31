//! Project chores: `cargo xtask test` (every test: crates, verification, Python),
//! `cargo xtask verify` (verification suites), `cargo xtask bench`, `cargo xtask fuzz`
//! (the readers' fuzz tests, longer than in CI) and `cargo xtask docs` (the pictures of
//! docs/img drawn again).
//! Few dependencies on purpose: it drives the release `talus` binary and `cargo bench`.
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

mod bench;
mod docs;
mod fuzz;
mod mpi;
mod test;
mod verify;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (task, flags) = match args.split_first() {
        Some((task, flags)) => (task.as_str(), flags),
        None => ("", &[][..]),
    };
    // Each task's flags; anything else (`--help` included) prints the usage. `fuzz`
    // checks its own (`--cases N`).
    let known: &[&str] = match task {
        "test" => &["--no-python"],
        "verify" => &["--quick"],
        _ => &[],
    };
    let unknown = flags
        .iter()
        .find(|f| task != "fuzz" && !known.contains(&f.as_str()));
    let has = |flag: &str| flags.iter().any(|f| f == flag);
    let result = match (task, unknown) {
        ("test", None) => test::run(&workspace_root(), !has("--no-python")),
        ("verify", None) => verify::run(&workspace_root(), has("--quick")),
        ("bench", None) => bench::run(&workspace_root()),
        ("docs", None) => docs::run(&workspace_root()),
        ("fuzz", None) => fuzz::run(&workspace_root(), flags),
        (_, unknown) => {
            if let Some(flag) = unknown {
                eprintln!("xtask {task}: unknown argument {flag:?}");
            }
            eprintln!(
                "usage: cargo xtask <test [--no-python]|verify [--quick]|bench|fuzz [--cases N]|docs>"
            );
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

/// The release `talus` binary that `cargo build --release -p talus` leaves: under
/// `CARGO_TARGET_DIR` when it is set (cargo's own rule), else the workspace's `target/`.
fn release_talus(root: &Path) -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|t| if t.is_absolute() { t } else { root.join(t) })
        .unwrap_or_else(|| root.join("target"))
        .join("release/talus")
}

/// Runs a command in the workspace and returns its captured output whatever its exit
/// status; fails, naming the command, only if it cannot start.
pub(crate) fn run_output(
    root: &Path,
    program: &str,
    args: &[&str],
) -> Result<std::process::Output, String> {
    Command::new(program)
        .args(args)
        .current_dir(root)
        .output()
        .map_err(|e| format!("cannot run `{}`: {e}", command_line(program, args)))
}

/// Runs a command in the workspace, failing with its name if it cannot start or fails:
/// the error names the command and its exit status, followed by the end of its stderr.
pub(crate) fn run_checked(
    root: &Path,
    program: &str,
    args: &[&str],
) -> Result<std::process::Output, String> {
    let output = run_output(root, program, args)?;
    if output.status.success() {
        return Ok(output);
    }
    let mut message = format!(
        "`{}` failed ({})",
        command_line(program, args),
        output.status
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    let lines: Vec<&str> = stderr.trim_end().lines().collect();
    if !lines.is_empty() {
        const TAIL: usize = 20;
        message.push_str(":\n");
        message.push_str(&lines[lines.len().saturating_sub(TAIL)..].join("\n"));
    }
    Err(message)
}

fn command_line(program: &str, args: &[&str]) -> String {
    std::iter::once(program)
        .chain(args.iter().copied())
        .collect::<Vec<_>>()
        .join(" ")
}
