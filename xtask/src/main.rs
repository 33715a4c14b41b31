//! Project chores: `cargo xtask test` (every test: crates, verification, Python),
//! `cargo xtask verify` (verification suites) and `cargo xtask bench`.
//! Few dependencies on purpose: it drives the release `talus` binary and `cargo bench`.
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

mod bench;
mod fuzz;
mod test;
mod verify;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("test") => test::run(&workspace_root(), !args.iter().any(|a| a == "--no-python")),
        Some("verify") => verify::run(&workspace_root(), args.iter().any(|a| a == "--quick")),
        Some("bench") => bench::run(&workspace_root()),
        Some("fuzz") => fuzz::run(&workspace_root(), &args[1..]),
        _ => {
            eprintln!("usage: cargo xtask <test [--no-python]|verify [--quick]|bench>");
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

/// Runs a command in the workspace, failing with its name if it cannot start or fails.
pub(crate) fn run_checked(
    root: &Path,
    program: &str,
    args: &[&str],
) -> Result<std::process::Output, String> {
    let output = Command::new(program)
        .args(args)
        .current_dir(root)
        .output()
        .map_err(|e| format!("cannot run {program}: {e}"))?;
    Ok(output)
}
