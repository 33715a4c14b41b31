//! Seconds per Newton iteration and peak memory per rank of MUMPS' distributed
//! factorization (`docs/distributed.md`) against Talus' own solver, in one run on one
//! machine: the 3D slope's factor of safety (`scenes/slope_3d.toml`, 20k unknowns) and
//! the first steps of the paper footing on an NX×NY mesh (`footing_NXxNY`, graded as
//! `builtin_footing_with_cells`: 104×48 is 9 984 P2 triangles, 40k unknowns; 320×156,
//! 99 840 and 400k), each by `talus run`:
//!
//! - `own`: one rank, the scene's own solver (the baseline of the ratios);
//! - `mumps ×N`: `mpirun -np N`, every factorization by MUMPS over N ranks (`N = 1` is
//!   `linear_solver = "mumps"`);
//! - `mumps ×N on rank 0`: `reproducible = true` (N > 1): the ranks' entries gathered to
//!   rank 0, which factorizes alone (`docs/distributed.md`, 'Reproducibility').
//!
//! Reports Newton iterations (failed ones included) and the seconds of the steps, both
//! from `history.csv` (a factor-of-safety search's: the loading and each trial), seconds
//! per iteration, the ratio to
//! `own`, the largest peak resident memory of a rank (`VmHWM`, as each rank logs it) and
//! MUMPS' statistics of its first factorization (entries of the factors, flops, the
//! largest memory of a rank, INFOG(21)).
//!
//! Cases: `TALUS_DISTRIBUTED_BENCH_CASES` (default `slope_3d,footing_104x48`); ranks:
//! `TALUS_DISTRIBUTED_BENCH_RANKS` (default `1,2`); footing steps:
//! `TALUS_DISTRIBUTED_BENCH_STEPS` (default 3). Run with
//! `cargo bench -p talus --features mpi --bench distributed` (needs `mpirun`).
use std::path::{Path, PathBuf};
use std::process::Command;

use talus::scene::paper_grading;

// `--bind-to none`: OpenMPI binds each of up to 2 ranks to one core, which would leave a
// one-rank run one core for its threads.
const MPIRUN_FLAGS: &[&str] = &[
    "--allow-run-as-root",
    "--oversubscribe",
    "--bind-to",
    "none",
];

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// How a run factorizes.
#[derive(Clone, Copy)]
enum Config {
    Own,
    Mumps { ranks: usize, reproducible: bool },
}

/// A case's scene text, with `[solver]` keys appended when `mumps`.
fn scene_text(case: &str, steps: usize, config: Config) -> Result<String, String> {
    let (mumps, reproducible) = match config {
        Config::Own => (false, false),
        Config::Mumps { reproducible, .. } => (true, reproducible),
    };
    let read = |name: &str| {
        std::fs::read_to_string(scenes().join(name)).map_err(|e| format!("{name}: {e}"))
    };
    let mut text = match case {
        "slope_3d" => {
            let mesh = scenes().join("slope_3d.msh");
            let text = read("slope_3d.toml")?;
            let text = text.replacen(
                "path = \"slope_3d.msh\"",
                &format!("path = {:?}", mesh.display().to_string()),
                1,
            );
            if mumps {
                // The shipped f32 + GMRES keys give way to MUMPS' direct f64 solve.
                text.replace("linear_solver = \"krylov\"", "linear_solver = \"mumps\"")
                    .replace("precision = \"single\"\n", "")
                    .replace("reuse_factorization = false\n", "")
            } else {
                text
            }
        }
        footing if footing.starts_with("footing_") => {
            let (nx, ny) = footing["footing_".len()..]
                .split_once('x')
                .ok_or_else(|| format!("{case}: footing_NXxNY"))?;
            let ny_cells: usize = ny.parse().map_err(|_| format!("{case}: footing_NXxNY"))?;
            let text = read("footing.toml")?
                .replacen("cells = [32, 14]", &format!("cells = [{nx}, {ny}]"), 1)
                .replacen(
                    "ratio = [1.0, 1.1]",
                    &format!("ratio = [1.0, {}]", paper_grading(ny_cells)),
                    1,
                )
                .replacen("steps = 300", &format!("steps = {steps}"), 1)
                .replacen("vtu_every = 30", "vtu_every = 0", 1)
                .replacen("plots = true", "plots = false", 1);
            if mumps {
                text + "\n[solver]\nlinear_solver = \"mumps\"\n"
            } else {
                text
            }
        }
        other => return Err(format!("unknown case {other:?}")),
    };
    if reproducible {
        let key = "linear_solver = \"mumps\"";
        text = text.replacen(key, &format!("{key}\nreproducible = true"), 1);
    }
    if !text.ends_with('\n') {
        text.push('\n');
    }
    Ok(text)
}

struct Measured {
    iterations: usize,
    seconds: f64,
    peak_mib: Option<u64>,
    mumps: Option<String>,
}

/// The value of `key=` in a log line.
fn field<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    let at = line.find(&format!(" {key}="))? + key.len() + 2;
    line[at..].split_whitespace().next()
}

/// One `config`; always under `mpirun`, so that every rank logs its peak memory.
fn run(case: &str, config: Config, steps: usize, dir: &Path) -> Result<Measured, String> {
    let text = scene_text(case, steps, config)?;
    let scene = dir.join(format!("{case}.toml"));
    std::fs::write(&scene, text).map_err(|e| e.to_string())?;
    let out = dir.join("out");
    let _ = std::fs::remove_dir_all(&out);
    let talus = env!("CARGO_BIN_EXE_talus");
    let ranks = match config {
        Config::Own => 1,
        Config::Mumps { ranks, .. } => ranks,
    };
    let mut command = Command::new("mpirun");
    command
        .args(MPIRUN_FLAGS)
        .args(["-np", &ranks.to_string(), talus]);
    let output = command
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .env("TALUS_LOG", "info")
        .output()
        .map_err(|e| format!("talus run: {e}"))?;
    let stderr = String::from_utf8_lossy(&output.stderr);
    if !output.status.success() {
        return Err(format!("{case} on {ranks} rank(s) failed: {stderr}"));
    }
    let history = std::fs::read_to_string(out.join("history.csv")).map_err(|e| e.to_string())?;
    let mut lines = history.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name);
    let (its, failed, secs) = (
        column("newton_iterations"),
        column("failed_newton_iterations"),
        column("seconds"),
    );
    let mut iterations = 0usize;
    let mut seconds = 0.0;
    for line in lines {
        let v: Vec<&str> = line.split(',').collect();
        let get = |c: Option<usize>| c.and_then(|c| v.get(c)).copied().unwrap_or("0");
        iterations += get(its).parse::<usize>().unwrap_or(0);
        iterations += get(failed).parse::<usize>().unwrap_or(0);
        seconds += get(secs).parse::<f64>().unwrap_or(0.0);
    }
    let peak_mib = stderr
        .lines()
        .filter(|l| l.contains("peak resident memory"))
        .filter_map(|l| field(l, "peak_mib")?.parse::<u64>().ok())
        .max();
    let mumps = stderr
        .lines()
        .find(|l| l.contains("MUMPS factorization"))
        .map(|l| {
            format!(
                "{} entries, {} flops, {} MB/rank",
                field(l, "factor_entries").unwrap_or("?"),
                field(l, "flops").unwrap_or("?"),
                field(l, "peak_megabytes_per_rank").unwrap_or("?")
            )
        });
    Ok(Measured {
        iterations,
        seconds,
        peak_mib,
        mumps,
    })
}

fn main() {
    if std::env::args().any(|a| a == "--list") {
        return;
    }
    let cases = std::env::var("TALUS_DISTRIBUTED_BENCH_CASES")
        .unwrap_or_else(|_| "slope_3d,footing_104x48".into());
    let ranks: Vec<usize> = std::env::var("TALUS_DISTRIBUTED_BENCH_RANKS")
        .unwrap_or_else(|_| "1,2".into())
        .split(',')
        .filter_map(|r| r.trim().parse().ok())
        .collect();
    let steps: usize = std::env::var("TALUS_DISTRIBUTED_BENCH_STEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    let dir = std::env::temp_dir().join(format!("talus-distributed-bench-{}", std::process::id()));
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("{}: {e}", dir.display());
        std::process::exit(1);
    }
    println!("| case | solver | Newton its | seconds | s per iteration | ratio | peak MiB (largest rank) | MUMPS (first factorization) |");
    println!("|---|---|---|---|---|---|---|---|");
    let mut failed = false;
    for case in cases.split(',').map(str::trim) {
        let mut baseline = None;
        let mumps = |ranks, reproducible| Config::Mumps {
            ranks,
            reproducible,
        };
        let configs = std::iter::once(Config::Own)
            .chain(ranks.iter().map(|&n| mumps(n, false)))
            .chain(ranks.iter().filter(|&&n| n > 1).map(|&n| mumps(n, true)));
        for config in configs {
            let name = match config {
                Config::Own => "own".to_string(),
                Config::Mumps {
                    ranks,
                    reproducible: false,
                } => format!("mumps ×{ranks}"),
                Config::Mumps { ranks, .. } => format!("mumps ×{ranks} on rank 0"),
            };
            match run(case, config, steps, &dir) {
                Ok(m) => {
                    let per = m.seconds / m.iterations.max(1) as f64;
                    let base = *baseline.get_or_insert(per);
                    println!(
                        "| {case} | {name} | {} | {:.2} | {per:.4} | {:.2} | {} | {} |",
                        m.iterations,
                        m.seconds,
                        per / base,
                        m.peak_mib.map_or("–".into(), |p| p.to_string()),
                        m.mumps.unwrap_or_else(|| "–".into())
                    );
                }
                Err(e) => {
                    eprintln!("{e}");
                    failed = true;
                }
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    if failed {
        std::process::exit(1);
    }
}
