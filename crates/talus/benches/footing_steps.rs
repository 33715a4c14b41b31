//! Seconds per implicit step, Newton iterations and peak memory of the paper footing
//! (`scenes/footing.toml`, non-associative) at about 1k, 10k, 40k and 100k P2 triangles,
//! in the same two windows of the paper's loading (1 mm/s, h = 1e-2 s) for every size:
//! early plastic loading (steps 3–5, 0.03–0.05 mm) and the force plateau (steps 101–103,
//! 1.01–1.03 mm; the plateau starts near step 65 on the paper mesh).
//!
//! Each size runs in a child process (this binary re-invoked with `--child`), so that each
//! peak (`VmHWM` of `/proc/self/status`) is its own. A child builds the model and steps the
//! scene from the K₀ state as `talus run` does, to step 103, or to step 300 (the whole
//! loading) on meshes of at most `TALUS_FOOTING_BENCH_FULL` triangles (default 10k), and
//! reports each window and the whole run: accepted and failed Newton iterations per step,
//! the largest in one sub-step, halved steps, seconds. Meshes run in full also run with
//! associative flow (θ = φ, Cholesky), and the line `wall non-associative / associative`
//! gives the ratio of the two runs' seconds (issue 24's target: ≤ 4 on 104×48).
//!
//! Sizes: `TALUS_FOOTING_BENCH_SIZES` (comma-separated `NXxNY`, default
//! `32x14,104x48,208x96,320x156`; the 100k mesh takes tens of minutes, its full run hours).
//!
//! Run with `cargo bench -p talus --bench footing_steps`.
use std::process::{Command, Stdio};
use std::time::Instant;

use talus::model::fem::ReactionForce;
use talus::model::fem::{FromScene, Model};
use talus::run::fem::solver_settings;
use talus::scene::builtin_footing_with_cells;
use talus_engine::{StepSettings, Stepper};

/// Steps of the two windows (1-based, inclusive).
const EARLY: [usize; 2] = [3, 5];
const PLATEAU: [usize; 2] = [101, 103];
/// The paper's whole loading, run on meshes up to `FULL_RUN_ELEMENTS` triangles.
const FULL_RUN: usize = 300;
const FULL_RUN_ELEMENTS: usize = 10_000;

/// On a worker of rayon's pool, as `talus run` solves (`talus_ssn::on_pool`).
fn main() {
    talus_ssn::on_pool(bench);
}

fn bench() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--child") {
        let parse = |k: usize| args.get(k).and_then(|s| s.parse().ok());
        let flow = args.get(3).map(String::as_str).unwrap_or("as_given");
        match (parse(1), parse(2)) {
            (Some(nx), Some(ny)) => child([nx, ny], flow),
            _ => {
                eprintln!("usage: --child NX NY [as_given|associative]");
                std::process::exit(2);
            }
        }
        return;
    }
    let sizes = std::env::var("TALUS_FOOTING_BENCH_SIZES")
        .unwrap_or_else(|_| "32x14,104x48,208x96,320x156".to_string());
    let exe = match std::env::current_exe() {
        Ok(exe) => exe,
        Err(e) => {
            eprintln!("own path: {e}");
            std::process::exit(1);
        }
    };
    let mut failed = false;
    println!(
        "| cells | flow | elements | free dofs | window | steps | s/step | accepted its/step | failed its/step | max its | halved steps | peak MiB |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut walls = Vec::new();
    for cells in sizes.split(',').filter(|s| !s.is_empty()) {
        let Some((nx, ny)) = cells.split_once('x') else {
            eprintln!("TALUS_FOOTING_BENCH_SIZES: `{cells}` is not NXxNY");
            std::process::exit(2);
        };
        let mut wall = [None, None];
        for (k, flow) in ["as_given", "associative"].into_iter().enumerate() {
            let out = Command::new(&exe)
                .args(["--child", nx, ny, flow])
                .stderr(Stdio::inherit())
                .output();
            let text = match out {
                Ok(out) if out.status.success() => {
                    String::from_utf8_lossy(&out.stdout).into_owned()
                }
                Ok(out) => {
                    eprintln!("{cells} {flow}: child failed ({})", out.status);
                    failed = true;
                    continue;
                }
                Err(e) => {
                    eprintln!("{cells} {flow}: child not started: {e}");
                    failed = true;
                    continue;
                }
            };
            for line in text.lines().filter_map(|l| l.strip_prefix("ROW ")) {
                println!("{line}");
            }
            wall[k] = text
                .lines()
                .find_map(|l| l.strip_prefix("WALL "))
                .and_then(|v| v.trim().parse::<f64>().ok());
            // Only the meshes run in full have an associative twin.
            if !text.contains("FULL") {
                break;
            }
        }
        if let [Some(a), Some(b)] = wall {
            walls.push(format!(
                "{cells}: wall non-associative / associative = {:.2} ({a:.1} s / {b:.1} s)",
                a / b
            ));
        }
    }
    for line in walls {
        println!("{line}");
    }
    if failed {
        std::process::exit(1);
    }
}

/// One step's figures.
struct Step {
    seconds: f64,
    iterations: usize,
    failed_iterations: usize,
    max_iterations: usize,
    halved: bool,
}

/// Triangles up to which the whole loading is run (`TALUS_FOOTING_BENCH_FULL`).
fn full_run_elements() -> usize {
    std::env::var("TALUS_FOOTING_BENCH_FULL")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(FULL_RUN_ELEMENTS)
}

fn child(cells: [usize; 2], flow: &str) {
    if std::env::var_os("TALUS_LOG").is_some() {
        tracing_subscriber::fmt()
            .with_env_filter(tracing_subscriber::EnvFilter::from_env("TALUS_LOG"))
            .with_writer(std::io::stderr)
            .init();
    }
    let mut scene = builtin_footing_with_cells(cells);
    if flow == "associative" {
        for m in scene.spec.material.all_mut() {
            m.dilatancy_angle = m.friction_angle;
        }
    }
    let model = match Model::from_scene(&scene) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("model: {e}");
            std::process::exit(1);
        }
    };
    let mut state = match model.initial_state(&scene) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("K0 state: {e}");
            std::process::exit(1);
        }
    };
    let elements = model.mesh.triangles.len();
    let dofs = model.assembly.dofs().n_free();
    let full = elements <= full_run_elements();
    let last = if full { FULL_RUN } else { PLATEAU[1] };
    let h = scene.spec.time.step;
    let mut stepper = Stepper::new(
        &model,
        StepSettings::with_solver(solver_settings(&scene), scene.spec.solver.max_step_halvings),
    );
    let start = Instant::now();
    let mut steps = Vec::with_capacity(last);
    for k in 1..=last {
        let r = match stepper.advance(&mut state, h) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("{}×{} step {k}: {e}", cells[0], cells[1]);
                std::process::exit(1);
            }
        };
        eprintln!(
            "{}×{} step {k}: {} its (largest sub-step {}), {} sub-steps, {:.3} s, F = {:.1} kN/m",
            cells[0],
            cells[1],
            r.newton_iterations,
            r.max_newton_iterations,
            r.substeps,
            r.seconds,
            r.reaction_force() * 1e-3
        );
        steps.push(Step {
            seconds: r.seconds,
            iterations: r.newton_iterations,
            failed_iterations: r.failed_newton_iterations,
            max_iterations: r.max_newton_iterations,
            halved: r.substeps > 1,
        });
    }
    let peak = peak_kib() as f64 / 1024.0;
    let row = |name: &str, window: &[Step], range: String| {
        let n = window.len() as f64;
        println!(
            "ROW | {}×{} | {flow} | {elements} | {dofs} | {name} | {range} | {:.3} | {:.2} | {:.2} | {} | {} | {peak:.0} |",
            cells[0],
            cells[1],
            window.iter().map(|s| s.seconds).sum::<f64>() / n,
            window.iter().map(|s| s.iterations).sum::<usize>() as f64 / n,
            window.iter().map(|s| s.failed_iterations).sum::<usize>() as f64 / n,
            window.iter().map(|s| s.max_iterations).max().unwrap_or(0),
            window.iter().filter(|s| s.halved).count(),
        );
    };
    let window = |w: [usize; 2]| &steps[w[0] - 1..w[1]];
    row("early", window(EARLY), format!("{}–{}", EARLY[0], EARLY[1]));
    row(
        "plateau",
        window(PLATEAU),
        format!("{}–{}", PLATEAU[0], PLATEAU[1]),
    );
    row("whole run", &steps, format!("1–{last}"));
    let wall = start.elapsed().as_secs_f64();
    println!("WALL {wall}");
    if full {
        println!("FULL");
    }
    eprintln!(
        "{}×{}: {last} steps in {:.1} s",
        cells[0],
        cells[1],
        start.elapsed().as_secs_f64()
    );
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
