//! `cargo xtask fuzz [--cases N]`: the fuzz tests of the three readers users give files to
//! (`docs/scenes.md`, 'Fuzzing') with many more cases than `cargo test` runs: each
//! property's default times [`SCALE`], or `N` cases per property. Prints each property's
//! tally, then the cases run and the panics found.
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// Cases per property relative to `cargo test` (`TALUS_FUZZ_SCALE`).
const SCALE: u32 = 20;

/// (package, test target, filter) of each reader's fuzz test: `talus`' integration tests
/// are modules of one binary (`crates/talus/tests/suite.rs`).
const TESTS: [(&str, &str, &str); 3] = [
    ("talus-ssn", "fuzz_siconos_reader", ""),
    ("talus-fem", "fuzz_msh_reader", ""),
    ("talus", "suite", "fuzz_scene_reader::"),
];

/// `Ok(false)` when a property failed (a panic, an inconsistent result, an abort).
pub(crate) fn run(root: &Path, args: &[String]) -> Result<bool, String> {
    let cases = match args.iter().position(|a| a == "--cases") {
        Some(i) => Some(
            args.get(i + 1)
                .and_then(|n| n.parse::<u32>().ok())
                .filter(|&n| n > 0)
                .ok_or("fuzz: --cases takes a positive integer")?,
        ),
        None => None,
    };
    if let Some(other) = args
        .iter()
        .enumerate()
        .find(|&(i, a)| a != "--cases" && (i == 0 || args[i - 1] != "--cases"))
    {
        return Err(format!(
            "fuzz: unknown argument `{}` (usage: cargo xtask fuzz [--cases N])",
            other.1
        ));
    }
    let start = Instant::now();
    let (mut total, mut panics, mut inconsistent, mut failed) = (0u64, 0usize, 0usize, 0usize);
    for (package, test, filter) in TESTS {
        eprintln!("xtask fuzz: {package} --test {test} {filter}");
        let mut cmd = Command::new("cargo");
        cmd.args(["test", "--release", "-p", package, "--test", test]);
        if !filter.is_empty() {
            cmd.arg(filter);
        }
        cmd.args(["--", "--nocapture", "--test-threads", "1"])
            .current_dir(root)
            .env("RUST_BACKTRACE", "0");
        match cases {
            Some(n) => cmd.env("TALUS_FUZZ_CASES", n.to_string()),
            None => cmd.env("TALUS_FUZZ_SCALE", SCALE.to_string()),
        };
        let out = cmd
            .output()
            .map_err(|e| format!("fuzz: cannot run cargo: {e}"))?;
        let stdout = String::from_utf8_lossy(&out.stdout);
        let stderr = String::from_utf8_lossy(&out.stderr);
        // `fuzz <reader>: <N> cases (...)`, possibly after `test <name> ... ` on its line.
        for line in stdout.lines() {
            let Some(at) = line.find("fuzz ") else {
                continue;
            };
            let tally = &line[at..];
            let n = tally
                .split_once(": ")
                .and_then(|(_, rest)| rest.split_whitespace().next())
                .and_then(|n| n.parse::<u64>().ok());
            if let Some(n) = n {
                println!("{tally}");
                total += n;
            }
        }
        // A failed property panics with `fuzz <reader>: Test failed: PANIC ...` and the
        // shrunk input after `minimal failing input:`.
        for (k, line) in stderr.lines().enumerate() {
            if line.contains(": Test failed: PANIC in the") {
                panics += 1;
            } else if line.contains(": Test failed: INCONSISTENT") {
                inconsistent += 1;
            } else {
                continue;
            }
            println!("FAILED {line}");
            for more in stderr.lines().skip(k + 1).take(40) {
                if more.starts_with("test ") || more.trim().is_empty() {
                    break;
                }
                println!("  {more}");
            }
        }
        if !out.status.success() {
            failed += 1;
            if !stderr.contains(": Test failed: ") {
                // Not a property: a build error or an abort (e.g. a failed allocation).
                let tail: Vec<&str> = stderr.lines().rev().take(15).collect();
                println!("FAILED {package} --test {test} ({}):", out.status);
                for l in tail.into_iter().rev() {
                    println!("  {l}");
                }
            }
        }
    }
    println!(
        "xtask fuzz: {total} cases in {:.0} s; {panics} panics, {inconsistent} inconsistent \
         results, {failed} of {} test files failed",
        start.elapsed().as_secs_f64(),
        TESTS.len()
    );
    Ok(failed == 0)
}
