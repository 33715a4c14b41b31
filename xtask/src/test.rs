//! `cargo xtask test`: every test of the repository, in the order a failure is cheapest to
//! read: the crates' tests (release), talus-ssn's with METIS, the distributed tests under `mpirun` when MUMPS and
//! OpenMPI are installed (`docs/distributed.md`), the verification suite, then the Python
//! package's tests in a virtual environment under `target/python-venv`
//! (`python/README.md`).
use std::path::Path;
use std::process::Command;

/// `Ok(false)` when a stage fails; later stages still run, so one run shows every failure.
pub(crate) fn run(root: &Path, python: bool) -> Result<bool, String> {
    let mut ok = stage(
        root,
        "crates",
        "cargo",
        // talus-mumps links MUMPS: built by the distributed stage only.
        &[
            "test",
            "--release",
            "--workspace",
            "--exclude",
            "talus-mumps",
        ],
    )?;
    // METIS (built from source by `cc`): the nested-dissection ordering and the ranks'
    // partition of `K` (`docs/distributed.md`).
    ok &= stage(
        root,
        "metis",
        "cargo",
        &[
            "test",
            "--release",
            "-p",
            "talus-ssn",
            "--features",
            "metis",
        ],
    )?;
    ok &= distributed_tests(root)?;
    ok &= crate::verify::run(root, false)?;
    if python {
        ok &= python_tests(root)?;
    } else {
        eprintln!("xtask test: Python tests skipped (--no-python)");
    }
    Ok(ok)
}

/// The MUMPS handle's test and `mpirun -np 2 talus run` against one rank (cargo feature
/// `mpi`), when `mpirun` and MUMPS' header are installed; skipped, saying so, otherwise.
fn distributed_tests(root: &Path) -> Result<bool, String> {
    if let Some(missing) = crate::mpi::missing() {
        eprintln!("xtask test: distributed tests skipped ({missing})");
        return Ok(true);
    }
    Ok(stage(
        root,
        "mumps",
        "cargo",
        &["test", "--release", "-p", "talus-mumps"],
    )? & stage(
        root,
        "distributed newton",
        "cargo",
        &[
            "test",
            "--release",
            "-p",
            "talus-ssn",
            "--features",
            "mpi",
            "--test",
            "distributed_newton",
        ],
    )? & stage(
        root,
        "distributed",
        "cargo",
        &[
            "test",
            "--release",
            "-p",
            "talus",
            "--features",
            "mpi",
            "--test",
            "distributed_ranks",
        ],
    )?)
}

fn python_tests(root: &Path) -> Result<bool, String> {
    let venv = root.join("target").join("python-venv");
    let bin = venv.join("bin");
    if !bin.join("python").exists() {
        let made = stage(root, "python venv", "python3", &["-m", "venv", path(&venv)?])
            .map_err(|e| format!("{e} (the Python tests need python3 ≥ 3.9 with venv; `cargo xtask test --no-python` skips them)"))?;
        if !made {
            return Ok(false);
        }
    }
    let python = bin.join("python");
    let python = path(&python)?;
    // In-tree build: maturin reuses the workspace's release artefacts.
    Ok(stage(
        root,
        "python install",
        python,
        &["-m", "pip", "install", "--quiet", "./python[test]"],
    )? && stage(
        root,
        "python tests",
        python,
        &["-m", "pytest", "-q", "python/tests"],
    )?)
}

fn path(p: &Path) -> Result<&str, String> {
    p.to_str()
        .ok_or_else(|| format!("path {} is not UTF-8", p.display()))
}

/// Runs one stage with its output shown; `Ok(false)` if it fails.
fn stage(root: &Path, name: &str, program: &str, args: &[&str]) -> Result<bool, String> {
    eprintln!("xtask test: {name}: {program} {}", args.join(" "));
    let start = std::time::Instant::now();
    let status = Command::new(program)
        .args(args)
        .current_dir(root)
        .status()
        .map_err(|e| format!("{name}: cannot run {program}: {e}"))?;
    // Each stage's wall time, builds included: CI's budget is spent stage by stage.
    let seconds = start.elapsed().as_secs();
    if status.success() {
        eprintln!("xtask test: {name} took {seconds} s");
    } else {
        eprintln!("xtask test: {name} failed ({status}) after {seconds} s");
    }
    Ok(status.success())
}
