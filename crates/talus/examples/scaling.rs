//! Seconds per implicit step of the paper footing (`scenes/footing.toml`) at about 1k, 10k
//! and 100k P2 triangles, with Newton iterations per step and peak resident memory.
//!
//! Each size runs in a child process (this binary re-invoked with `--child`), so that each
//! peak (`VmHWM` of `/proc/self/status`) is its own. A child builds the model and steps the
//! scene from the K₀ state with the paper's loading (1 mm/s, h = 1e-2 s); steps 1–2 are not
//! timed (solver set-up, elastic predictor), steps 3 to 2 + N are: early plastic loading
//! (5 to 11 Newton iterations per step; the plateau, past step 65, takes 2 on the paper mesh).
//! Reaching the plateau would take 80 steps: minutes at 10k elements, hours at 100k; a
//! warm-up with h = 0.1 s fails on the 10k mesh (step 4, even after 4 halvings), and one at
//! ten times the velocity leaves an inertial transient. Seconds per Newton iteration
//! (per step / iterations per step) is the quantity that carries over to the plateau.
//!
//! ```sh
//! cargo run --release -p talus --example scaling                      # 1k, 10k, 100k
//! cargo run --release -p talus --example scaling -- --sizes 32x14,104x48 --steps 5
//! ```
use std::process::{Command, Stdio};
use std::time::Instant;

use talus::run::solver_settings;
use talus::scene::{builtin_footing, MeshSpec, Scene};
use talus::simulation::{Model, Stepper};

/// Cells (x, y): uniform in x with nx a multiple of 8, so the footing edges x = ±0.25 are
/// nodes; 2·nx·ny P2 triangles (896, 9984, 99840).
const SIZES: [[usize; 2]; 3] = [[32, 14], [104, 48], [320, 156]];
/// Steps not timed: the first builds the solver (symbolic analysis) and, like the second,
/// starts from the elastic predictor (no stress rate yet); from the third on each step
/// starts from σₙ + h σ̇ as in `talus run`.
const SKIPPED: usize = 2;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--child") {
        let nx = args[1].parse().expect("nx");
        let ny = args[2].parse().expect("ny");
        let steps = args[3].parse().expect("steps");
        child([nx, ny], steps);
        return;
    }
    let mut sizes = SIZES.to_vec();
    let mut steps: Option<usize> = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--sizes" => {
                sizes = it
                    .next()
                    .expect("--sizes NXxNY,...")
                    .split(',')
                    .map(|s| {
                        let (x, y) = s.split_once('x').expect("NXxNY");
                        [x.parse().expect("NX"), y.parse().expect("NY")]
                    })
                    .collect();
            }
            "--steps" => steps = Some(it.next().expect("--steps N").parse().expect("N")),
            other => panic!("unknown argument {other} (--sizes NXxNY,... --steps N)"),
        }
    }
    let exe = std::env::current_exe().expect("own path");
    println!(
        "| cells | elements | free dofs | Gauss points | s/step | Newton its/step | s/iteration | model s | step 1 s | peak MiB |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for cells in sizes {
        let elements = 2 * cells[0] * cells[1];
        // Fewer timed steps on the largest mesh (about a minute each).
        let n = steps.unwrap_or(if elements > 50_000 { 3 } else { 8 });
        let out = Command::new(&exe)
            .args([
                "--child".to_string(),
                cells[0].to_string(),
                cells[1].to_string(),
                n.to_string(),
            ])
            .stderr(Stdio::inherit())
            .output()
            .expect("child process");
        let text = String::from_utf8_lossy(&out.stdout);
        let Some(line) = text.lines().find_map(|l| l.strip_prefix("RESULT ")) else {
            eprintln!("{}×{}: child failed ({})", cells[0], cells[1], out.status);
            continue;
        };
        let v: Vec<f64> = line
            .split_whitespace()
            .map(|x| x.parse().unwrap_or(f64::NAN))
            .collect();
        let (elements, dofs, points, s_step, its, setup, peak_kib, first) =
            (v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]);
        println!(
            "| {}×{} | {elements} | {dofs} | {points} | {s_step:.3} | {its:.2} | {:.3} | {setup:.1} | {first:.1} | {:.0} |",
            cells[0],
            cells[1],
            s_step / its,
            peak_kib / 1024.0
        );
    }
}

/// The built-in footing on an `nx × ny` grid, with the same y-grading as the paper's 32 × 14
/// (1.1 per cell over 14 cells).
fn scene(cells: [usize; 2]) -> Scene {
    let mut scene = builtin_footing();
    if let MeshSpec::Rectangle {
        cells: c, ratio, ..
    } = &mut scene.spec.mesh
    {
        *c = cells;
        ratio[1] = 1.1f64.powf(14.0 / cells[1] as f64);
    }
    scene
}

fn child(cells: [usize; 2], steps: usize) {
    // `TALUS_LOG=talus_ssn=debug` shows each solve (and any stress-sized fallback).
    if std::env::var_os("TALUS_LOG").is_some() {
        tracing_subscriber::fmt()
            .with_env_filter(tracing_subscriber::EnvFilter::from_env("TALUS_LOG"))
            .with_writer(std::io::stderr)
            .init();
    }
    let start = Instant::now();
    let scene = scene(cells);
    let model = Model::from_scene(&scene).expect("model");
    let asm = &model.assembly;
    let mut state = model.initial_state(&scene).expect("K0 state");
    let (elements, dofs, points) = (
        model.mesh.triangles.len(),
        asm.dofs().n_free(),
        asm.n_points(),
    );
    let setup = start.elapsed().as_secs_f64();
    let settings = solver_settings(&scene);
    let halvings = scene.spec.solver.max_step_halvings;
    let h = scene.spec.time.step;
    let mut stepper = Stepper::new(&model, settings, halvings);
    let (mut seconds, mut iterations, mut first) = (0.0, 0, 0.0);
    for k in 0..SKIPPED + steps {
        let r = stepper.advance(&mut state, h).expect("step");
        let timed = k >= SKIPPED;
        eprintln!(
            "{}×{} step {}{}: {} its, {:.3} s, F = {:.1} kN/m",
            cells[0],
            cells[1],
            k + 1,
            if timed { "" } else { " (not timed)" },
            r.newton_iterations,
            r.seconds,
            r.reaction_force * 1e-3
        );
        if k == 0 {
            first = r.seconds;
        }
        if timed {
            seconds += r.seconds;
            iterations += r.newton_iterations;
        }
    }
    let n = steps as f64;
    println!(
        "RESULT {elements} {dofs} {points} {:.6} {:.4} {setup:.3} {} {first:.3}",
        seconds / n,
        iterations as f64 / n,
        peak_kib()
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
