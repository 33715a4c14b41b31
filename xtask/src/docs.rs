//! `cargo xtask docs`: the pictures of `docs/img` drawn again by the release `talus` binary
//! from the scenes behind them, so that they show what the code draws today. Each run
//! writes into a temporary folder; its PNGs are then copied under their docs names.
//! Pictures that need long runs (more than 2 minutes on 2 cores) or another tool are left
//! as they are, with a note saying how to make them.
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::{run_checked, run_output};

/// One `talus` run and the pictures it draws: `(file in its output folder, name in
/// docs/img)`.
struct Job {
    /// What the pictures show, for the log.
    name: &'static str,
    /// The run's folder under the temporary one.
    dir: &'static str,
    /// `talus` arguments; `{out}` stands for the run's temporary folder.
    args: &'static [&'static str],
    pictures: &'static [(&'static str, &'static str)],
}

const JOBS: &[Job] = &[
    // docs/footing.md and the README: the paper's strip footing (about 3 s).
    Job {
        name: "strip footing (scenes/footing.toml)",
        dir: "footing",
        args: &["run", "scenes/footing.toml", "--out", "{out}"],
        pictures: &[
            ("force_displacement.png", "footing_force_displacement.png"),
            ("plastic_strain.png", "footing_plastic_strain.png"),
            ("newton_residuals.png", "footing_newton_residuals.png"),
        ],
    },
    // docs/stability.md: the slope's failure mechanism (about 6 s).
    Job {
        name: "slope by strength reduction (scenes/slope.toml)",
        dir: "slope",
        args: &["run", "scenes/slope.toml", "--out", "{out}"],
        pictures: &[("mechanism.png", "slope_mechanism.png")],
    },
    // docs/verification.md: the built-in verification cases' figures (about 45 s; the
    // cases `--quick` skips draw none).
    Job {
        name: "verification figures (talus verify --quick)",
        dir: "verify",
        args: &["verify", "--quick", "--figures", "{out}"],
        pictures: &[
            (
                "verification_prandtl_phi30_p2.png",
                "verification_prandtl_phi30_p2.png",
            ),
            (
                "verification_newton_residuals.png",
                "verification_newton_residuals.png",
            ),
        ],
    },
];

/// The docs/img pictures this task does not draw, and why.
const SKIPPED: &[(&str, &str)] = &[
    (
        "tradeoff_pareto.png",
        "26 runs, about 200 s: `cargo run --release -p talus-studies --bin tradeoffs` (docs/tradeoffs.md)",
    ),
    (
        "python_speed_accuracy.png",
        "Python and matplotlib, 24 runs, about 2 min 20 s: `python examples/python/speed_accuracy.py` (docs/python-examples.md)",
    ),
    (
        "python_column_runout.png",
        "Python and matplotlib, 10–20 min: `python examples/python/column_runout.py` (docs/python-examples.md)",
    ),
];

pub(crate) fn run(root: &Path) -> Result<bool, String> {
    let start = Instant::now();
    run_checked(
        root,
        "cargo",
        &["build", "--release", "--quiet", "-p", "talus"],
    )?;
    let talus = crate::release_talus(root);
    let talus = talus.to_str().ok_or("non-UTF-8 path")?;
    let img = root.join("docs/img");
    let tmp = TempDir::new()?;

    let mut ok = true;
    for job in JOBS {
        let out = tmp.0.join(job.dir);
        let out_str = out.to_str().ok_or("non-UTF-8 path")?;
        std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
        let args: Vec<&str> = job
            .args
            .iter()
            .map(|&a| if a == "{out}" { out_str } else { a })
            .collect();
        let t = Instant::now();
        println!("docs: {} — talus {}", job.name, args.join(" "));
        // A verification case that fails still draws its figure: a missing PNG is the
        // failure, reported with the run's stderr.
        let output = run_output(root, talus, &args)?;
        for (from, to) in job.pictures {
            let src = out.join(from);
            if !src.is_file() {
                ok = false;
                let stderr = String::from_utf8_lossy(&output.stderr);
                let tail: Vec<&str> = stderr.trim_end().lines().rev().take(10).collect();
                eprintln!(
                    "docs: {} did not draw {from} ({}); its last lines:\n{}",
                    job.name,
                    output.status,
                    tail.into_iter().rev().collect::<Vec<_>>().join("\n")
                );
                continue;
            }
            let dst = img.join(to);
            std::fs::copy(&src, &dst)
                .map_err(|e| format!("{} → {}: {e}", src.display(), dst.display()))?;
            println!("  docs/img/{to}");
        }
        println!("  {:.1} s", t.elapsed().as_secs_f64());
    }
    for (picture, why) in SKIPPED {
        println!("docs: docs/img/{picture} left as it is ({why})");
    }
    println!(
        "docs: {} in {:.0} s",
        if ok { "done" } else { "FAILED" },
        start.elapsed().as_secs_f64()
    );
    Ok(ok)
}

/// A folder under the system's temporary directory, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new() -> Result<Self, String> {
        let dir = std::env::temp_dir().join(format!("talus-xtask-docs-{}", std::process::id()));
        if dir.exists() {
            std::fs::remove_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        Ok(Self(dir))
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
