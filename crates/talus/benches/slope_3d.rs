//! Seconds to the factor of safety of the 3D slope of Sysala et al. (`scenes/slope_3d.toml`:
//! 45° slope, c = 6 kPa, φ = 45°, ψ = 0 by Davis, P2 tetrahedra) by strength reduction, on
//! its two meshes: `slope_3d.msh` (h = 2 m, about 20k unknowns) and `slope_3d_fine.msh`
//! (h = 1.25 m, about 70k; issue 25's target ≤ 120 s on this 2-core machine, against
//! 210 s for Sysala's PETSc code on 8 ranks). Reports per mesh: free dofs, Gauss points,
//! the factor and its bracket, trials, Newton iterations (loading and trials, failed
//! attempts included), the seconds of the model's build, the loading and the trials, and
//! the peak resident memory.
//!
//! Each mesh runs in a child process (this binary re-invoked with `--child MESH`), so
//! that each peak (`VmHWM` of `/proc/self/status`) is its own.
//!
//! Meshes: `TALUS_SLOPE3D_BENCH_MESHES` (comma-separated file names in `scenes/`, default
//! `slope_3d.msh,slope_3d_fine.msh`). Solver levers: `TALUS_SLOPE3D_BENCH_SOLVERS`
//! (`;`-separated variants, each `default` or comma-separated `key=value` of the scene's
//! `[solver]`, e.g. `default;linear_solver=krylov;linear_solver=krylov,precision=single`;
//! default `default`): every variant runs on every mesh, and its ratio is its total
//! seconds over the first variant's on the same mesh in the same run (the first should be
//! `default`). `ordering=nested_dissection` needs `--features metis`. Run with
//! `cargo bench -p talus --bench slope_3d`.
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use talus::analysis::stability::{self, Analysis};
use talus::run::RunOptions;
use talus::scene::{Scene3, SceneFile};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// On a worker of rayon's pool, as `talus run` solves (`talus_ssn::on_pool`).
fn main() {
    talus_ssn::on_pool(bench);
}

fn bench() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--child") {
        match (args.get(1), args.get(2)) {
            (Some(mesh), Some(variant)) => child(mesh, variant),
            _ => {
                eprintln!("usage: --child MESH SOLVER");
                std::process::exit(2);
            }
        }
        return;
    }
    let meshes = std::env::var("TALUS_SLOPE3D_BENCH_MESHES")
        .unwrap_or_else(|_| "slope_3d.msh,slope_3d_fine.msh".to_string());
    let solvers =
        std::env::var("TALUS_SLOPE3D_BENCH_SOLVERS").unwrap_or_else(|_| "default".to_string());
    let exe = match std::env::current_exe() {
        Ok(exe) => exe,
        Err(e) => {
            eprintln!("own path: {e}");
            std::process::exit(1);
        }
    };
    println!(
        "| mesh | solver | free dofs | Gauss points | F | bracket | trials | Newton its | build s | loading s | trials s | total s | ratio | peak MiB |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut failed = false;
    for mesh in meshes.split(',').filter(|m| !m.is_empty()) {
        let mut first: Option<f64> = None;
        for variant in solvers.split(';').map(str::trim).filter(|v| !v.is_empty()) {
            let out = Command::new(&exe)
                .args(["--child", mesh, variant])
                .stderr(Stdio::inherit())
                .output();
            match out {
                Ok(out) if out.status.success() => {
                    let row = String::from_utf8_lossy(&out.stdout);
                    // The child's row ends `| trials s | total s | peak MiB |`; the ratio of
                    // the total seconds (model, loading and search; against the first
                    // variant) goes before the peak.
                    let cells: Vec<&str> = row.trim().split('|').map(str::trim).collect();
                    if cells.len() != 15 {
                        eprintln!("{mesh} {variant}: unexpected row {row}");
                        failed = true;
                        continue;
                    }
                    let seconds = cells.get(12).and_then(|c| c.parse::<f64>().ok());
                    let ratio = match (seconds, first) {
                        (Some(s), Some(f)) => format!("{:.2}", s / f),
                        (Some(s), None) => {
                            first = Some(s);
                            "1".to_string()
                        }
                        _ => "-".to_string(),
                    };
                    println!("| {} | {ratio} | {} |", cells[1..13].join(" | "), cells[13]);
                }
                Ok(out) => {
                    eprintln!("{mesh} {variant}: child failed ({})", out.status);
                    failed = true;
                }
                Err(e) => {
                    eprintln!("{mesh} {variant}: {e}");
                    failed = true;
                }
            }
        }
    }
    if failed {
        std::process::exit(1);
    }
}

/// The scene with the variant's keys in its `[solver]` (a key the scene sets is replaced,
/// not repeated: TOML refuses a key twice); `true`, `false` and numbers are written bare,
/// other values as strings.
fn with_solver(text: &str, variant: &str) -> String {
    if variant == "default" {
        return text.to_string();
    }
    let pairs: Vec<(&str, String)> = variant
        .split(',')
        .filter(|kv| !kv.is_empty())
        .map(|kv| {
            let (key, value) = kv.split_once('=').unwrap_or((kv, ""));
            let value = value.trim();
            let bare = value == "true" || value == "false" || value.parse::<f64>().is_ok();
            let value = if bare {
                value.to_string()
            } else {
                format!("\"{value}\"")
            };
            (key.trim(), value)
        })
        .collect();
    let keys: String = pairs.iter().map(|(k, v)| format!("{k} = {v}\n")).collect();
    let (mut out, mut in_solver, mut found) = (String::new(), false, false);
    for line in text.lines() {
        let trimmed = line.trim_start();
        if trimmed.starts_with('[') {
            in_solver = trimmed.starts_with("[solver]");
            if in_solver {
                found = true;
                out.push_str(line);
                out.push('\n');
                out.push_str(&keys);
                continue;
            }
        }
        let key = trimmed.split('=').next().map(str::trim);
        if in_solver && pairs.iter().any(|(k, _)| Some(*k) == key) {
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    if !found {
        out.push_str("\n[solver]\n");
        out.push_str(&keys);
    }
    out
}

/// One mesh and solver variant: the scene with `[mesh.gmsh] path = MESH` and the
/// variant's `[solver]`, its model built, the loading and the search timed apart; one
/// table row on stdout, without the ratio (the parent's).
fn child(mesh: &str, variant: &str) {
    let path = scenes().join("slope_3d.toml");
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => with_solver(
            &t.replacen("path = \"slope_3d.msh\"", &format!("path = \"{mesh}\""), 1),
            variant,
        ),
        Err(e) => fail(&format!("{}: {e}", path.display())),
    };
    let scene: Scene3 = match SceneFile::parse(&text, Some(path)) {
        Ok(SceneFile::Fem3(s)) => s,
        Ok(_) => fail("slope_3d.toml is not read as a 3D scene"),
        Err(e) => fail(&e.to_string()),
    };
    let start = Instant::now();
    let mut analysis: Analysis<6> = match Analysis::new(&scene) {
        Ok(Some(a)) => a,
        Ok(None) => fail("no [stability]"),
        Err(e) => fail(&e.to_string()),
    };
    let build = start.elapsed().as_secs_f64();
    let dofs = analysis.model.assembly.dofs().n_free();
    let points = analysis.model.n_points();
    let equilibrium = match analysis.equilibrium(&scene) {
        Ok(e) => e,
        Err(e) => fail(&e.to_string()),
    };
    let loading = equilibrium.seconds;
    let loading_iterations = equilibrium.newton_iterations;
    let out = std::env::temp_dir().join(format!(
        "talus_slope_3d_bench_{mesh}_{}",
        variant.replace([',', '='], "_")
    ));
    if let Err(e) = std::fs::create_dir_all(&out) {
        fail(&format!("{}: {e}", out.display()));
    }
    let found = match stability::search(
        &mut analysis,
        equilibrium,
        &out.join("history.csv"),
        &RunOptions::new(&out),
    ) {
        Ok(f) => f,
        Err(e) => fail(&e.to_string()),
    };
    let total = start.elapsed().as_secs_f64();
    let fos = &found.factor_of_safety;
    let iterations = loading_iterations
        + found
            .trials
            .iter()
            .map(|t| t.newton_iterations)
            .sum::<usize>();
    let fmt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.4}"));
    println!(
        "| {mesh} | {variant} | {dofs} | {points} | {} | [{}, {}] | {} | {iterations} | {build:.1} | {loading:.1} | {:.1} | {total:.1} | {:.0} |",
        fmt(fos.value),
        fmt(fos.bracket[0]),
        fmt(fos.bracket[1]),
        found.trials.len(),
        found.seconds,
        peak_kib() as f64 / 1024.0
    );
    for t in &found.trials {
        eprintln!(
            "{mesh} {variant}: F = {:.4} from {:.4}: {}, {} steps, {} Newton iterations, {:.1} s",
            t.factor,
            t.start.unwrap_or(1.0),
            t.verdict.name(),
            t.steps(),
            t.newton_iterations,
            t.seconds
        );
    }
}

fn fail(message: &str) -> ! {
    eprintln!("{message}");
    std::process::exit(1);
}

/// Peak resident set size of this process (`VmHWM`, KiB); 0 if unavailable.
fn peak_kib() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("VmHWM:"))
                .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        })
        .unwrap_or(0)
}
