//! Seconds per implicit step of the paper footing (`scenes/footing.toml`) at about 1k, 10k
//! and 100k P2 triangles, with Newton iterations per step and peak resident memory.
//!
//! Each size runs in a child process (this binary re-invoked with `--child`), so that each
//! peak (`VmHWM` of `/proc/self/status`) is its own. A child builds the model, starts from
//! the K₀ state, pushes the footing to 0.8 mm (past the onset of the plateau, about 0.6 mm)
//! at ten times the paper's velocity (0.1 mm per step: few steps), then switches to the
//! paper's loading (1 mm/s, h = 1e-2 s). The first steps after the switch use the elastic
//! predictor (a jump in the prescribed velocity) and build the solver: they are skipped;
//! the next steps, in steady plastic flow warm-started from σₙ + h σ̇ as in `talus run`,
//! are the ones timed.
//!
//! ```sh
//! cargo run --release -p talus --example scaling                      # 1k, 10k, 100k
//! cargo run --release -p talus --example scaling -- --sizes 32x14,100x50 --steps 5
//! ```
use std::process::Command;
use std::time::Instant;

use talus::run::solver_settings;
use talus::scene::{builtin_footing, MeshSpec, Scene};
use talus::simulation::{k0_stress, Model, State, Stepper};

/// Cells (x, y): uniform in x with nx a multiple of 4, so the footing edges x = ±0.25 are
/// nodes; 2·nx·ny P2 triangles.
const SIZES: [[usize; 2]; 3] = [[32, 14], [100, 50], [320, 156]];
/// Footing displacement before the timed steps (m) and the warm-up speed-up.
const WARM_DISPLACEMENT: f64 = 0.8e-3;
const WARM_SPEEDUP: f64 = 10.0;
/// Steps after the loading switch that are not timed (elastic predictor, solver set-up).
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
        "| cells | elements | free dofs | Gauss points | s/step | Newton its/step | s/iteration | setup s | peak MiB |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for cells in sizes {
        let elements = 2 * cells[0] * cells[1];
        // Fewer timed steps on the largest mesh: the time per step is what matters.
        let n = steps.unwrap_or(if elements > 50_000 { 4 } else { 8 });
        let out = Command::new(&exe)
            .args([
                "--child".to_string(),
                cells[0].to_string(),
                cells[1].to_string(),
                n.to_string(),
            ])
            .output()
            .expect("child process");
        let text = String::from_utf8_lossy(&out.stdout);
        let Some(line) = text.lines().find_map(|l| l.strip_prefix("RESULT ")) else {
            eprintln!(
                "{}×{}: child failed ({}):\n{}",
                cells[0],
                cells[1],
                out.status,
                String::from_utf8_lossy(&out.stderr)
            );
            continue;
        };
        let v: Vec<f64> = line
            .split_whitespace()
            .map(|x| x.parse().unwrap_or(f64::NAN))
            .collect();
        let (elements, dofs, points, s_step, its, setup, peak_kib) =
            (v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
        println!(
            "| {}×{} | {elements} | {dofs} | {points} | {s_step:.3} | {its:.2} | {:.3} | {setup:.1} | {:.0} |",
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
    let start = Instant::now();
    let scene = scene(cells);
    let mut model = Model::from_scene(&scene).expect("model");
    let asm = &model.assembly;
    let mut state = State::at_rest(
        asm.n_points(),
        asm.dofs().n_free(),
        asm.dofs().n_prescribed(),
        model.mesh.nodes.len(),
    );
    let initial = scene.spec.initial_stress.as_ref().expect("K0 state");
    state.sigma = k0_stress(&scene, &model, initial).expect("K0");
    let (elements, dofs, points) = (
        model.mesh.triangles.len(),
        asm.dofs().n_free(),
        asm.n_points(),
    );
    let setup = start.elapsed().as_secs_f64();
    let settings = solver_settings(&scene);
    let halvings = scene.spec.solver.max_step_halvings;
    let h = scene.spec.time.step;
    let paper_velocity = model.prescribed_velocity.clone();
    let speed = paper_velocity.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let warm_steps = (WARM_DISPLACEMENT / (WARM_SPEEDUP * speed * h)).round() as usize;

    model
        .prescribed_velocity
        .iter_mut()
        .for_each(|v| *v *= WARM_SPEEDUP);
    {
        let mut stepper = Stepper::new(&model, settings, halvings);
        for k in 0..warm_steps {
            let r = stepper.advance(&mut state, h).expect("warm-up step");
            eprintln!(
                "{}×{} warm-up {}/{warm_steps}: {} its, {:.3} s",
                cells[0],
                cells[1],
                k + 1,
                r.newton_iterations,
                r.seconds
            );
        }
    }
    model.prescribed_velocity = paper_velocity;
    let mut stepper = Stepper::new(&model, settings, halvings);
    let (mut seconds, mut iterations) = (0.0, 0);
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
        if timed {
            seconds += r.seconds;
            iterations += r.newton_iterations;
        }
    }
    let n = steps as f64;
    println!(
        "RESULT {elements} {dofs} {points} {:.6} {:.4} {setup:.3} {}",
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
