//! Newton iterations per step of the paper footing on a finer mesh, with a saved state to
//! replay only the hard steps (the mechanism forming, steps 30–50 at 104×48).
//!
//! ```sh
//! # run steps 1..=28 and save the state after step 28
//! cargo run --release -p talus --example newton_replay -- --cells 64x30 --steps 28 --save s28.bin
//! # replay steps 29..=60 from it, printing the residual histories of steps 30..=40
//! cargo run --release -p talus --example newton_replay -- --cells 64x30 --load s28.bin \
//!     --steps 60 --histories 30-40
//! ```
//! The mesh is `scenes/footing.toml` with `cells = [nx, ny]` and the y-grading of the paper's
//! 32×14 (`ratio = [1, 1.1^(14/ny)]`), as `benches/footing_steps.rs` builds it. One line per step:
//! `STEP k substeps iterations failed_iterations backtracks max_iterations residual
//! reaction_kN seconds statuses` (iterations of accepted sub-steps; failed: of halved attempts).
//! `--max-halvings N` overrides the scene's `solver.max_step_halvings` (4).
use std::io::{Read, Write};

use talus::model::fem::ReactionForce;
use talus::model::fem::{FromScene, Model, State};
use talus::run::fem::solver_settings;
use talus::scene::{builtin_footing_with_cells, Scene};
use talus_engine::{StepSettings, Stepper};

fn scene(cells: [usize; 2], associative: bool) -> Scene {
    let mut scene = builtin_footing_with_cells(cells);
    if associative {
        let m = scene.spec.material.single_mut().expect("one material");
        m.dilatancy_angle = m.friction_angle;
    }
    scene
}

fn write_vec(out: &mut impl Write, v: &[f64]) {
    out.write_all(&(v.len() as u64).to_le_bytes()).unwrap();
    for x in v {
        out.write_all(&x.to_le_bytes()).unwrap();
    }
}

fn read_vec(input: &mut impl Read) -> Vec<f64> {
    let mut b = [0u8; 8];
    input.read_exact(&mut b).unwrap();
    let n = u64::from_le_bytes(b) as usize;
    (0..n)
        .map(|_| {
            input.read_exact(&mut b).unwrap();
            f64::from_le_bytes(b)
        })
        .collect()
}

fn save(path: &str, step: usize, state: &State, rate: Option<&[f64]>) {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    write_vec(&mut f, &[step as f64, state.time]);
    write_vec(&mut f, &state.sigma);
    write_vec(&mut f, &state.plastic_strain);
    write_vec(&mut f, &state.velocity_free);
    write_vec(&mut f, &state.velocity_prescribed);
    let disp: Vec<f64> = state.displacement.iter().flat_map(|u| *u).collect();
    write_vec(&mut f, &disp);
    write_vec(&mut f, rate.unwrap_or(&[]));
}

fn load(path: &str, state: &mut State) -> (usize, Option<Vec<f64>>) {
    let mut f = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let head = read_vec(&mut f);
    state.time = head[1];
    state.sigma = read_vec(&mut f);
    state.plastic_strain = read_vec(&mut f);
    state.velocity_free = read_vec(&mut f);
    state.velocity_prescribed = read_vec(&mut f);
    let disp = read_vec(&mut f);
    state.displacement = disp.chunks(2).map(|c| [c[0], c[1]]).collect();
    let rate = read_vec(&mut f);
    (head[0] as usize, (!rate.is_empty()).then_some(rate))
}

fn main() {
    if std::env::var_os("TALUS_LOG").is_some() {
        tracing_subscriber::fmt()
            .with_env_filter(tracing_subscriber::EnvFilter::from_env("TALUS_LOG"))
            .with_writer(std::io::stderr)
            .init();
    }
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut cells = [64, 30];
    let mut steps = 60;
    let mut save_path = None;
    let mut load_path = None;
    let mut histories = (usize::MAX, 0);
    let mut associative = false;
    let mut rho_factor = None;
    let mut max_iterations = None;
    let mut max_halvings = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().expect("value").clone();
        match a.as_str() {
            "--cells" => {
                let v = value();
                let (x, y) = v.split_once('x').expect("NXxNY");
                cells = [x.parse().unwrap(), y.parse().unwrap()];
            }
            "--steps" => steps = value().parse().unwrap(),
            "--save" => save_path = Some(value()),
            "--load" => load_path = Some(value()),
            "--histories" => {
                let v = value();
                let (a, b) = v.split_once('-').expect("A-B");
                histories = (a.parse().unwrap(), b.parse().unwrap());
            }
            "--associative" => associative = true,
            "--rho-factor" => rho_factor = Some(value().parse::<f64>().unwrap()),
            "--max-iterations" => max_iterations = Some(value().parse::<usize>().unwrap()),
            "--max-halvings" => max_halvings = Some(value().parse::<usize>().unwrap()),
            other => panic!("unknown argument {other}"),
        }
    }
    let mut scene = scene(cells, associative);
    if let Some(f) = rho_factor {
        scene.spec.solver.rho_factor = f;
    }
    if let Some(m) = max_iterations {
        scene.spec.solver.max_iterations = m;
    }
    if let Some(m) = max_halvings {
        scene.spec.solver.max_step_halvings = m;
    }
    let model = Model::from_scene(&scene).expect("model");
    let mut state = model.initial_state(&scene).expect("K0 state");
    let settings = solver_settings(&scene);
    let h = scene.spec.time.step;
    let mut stepper = Stepper::new(
        &model,
        StepSettings::with_solver(settings, scene.spec.solver.max_step_halvings),
    );
    let mut done = 0;
    if let Some(p) = &load_path {
        let (k, rate) = load(p, &mut state);
        stepper.set_stress_rate(rate);
        done = k;
    }
    eprintln!(
        "{}×{}: {} elements, {} Gauss points, from step {done}",
        cells[0],
        cells[1],
        model.mesh.triangles.len(),
        model.assembly.n_points()
    );
    let mut total = 0;
    for k in done + 1..=steps {
        match stepper.advance(&mut state, h) {
            Ok(r) => {
                total += r.newton_iterations + r.failed_newton_iterations;
                println!(
                    "STEP {k} {} {} {} {} {} {:.3e} {:.3} {:.3} {}",
                    r.substeps,
                    r.newton_iterations,
                    r.failed_newton_iterations,
                    r.backtracks,
                    r.max_newton_iterations,
                    r.residual,
                    r.reaction_force() * 1e-3,
                    r.seconds,
                    r.statuses
                        .iter()
                        .map(|s| s.as_str())
                        .collect::<Vec<_>>()
                        .join(",")
                );
                if (histories.0..=histories.1).contains(&k) {
                    for (s, (res, mer)) in r
                        .residual_histories
                        .iter()
                        .zip(&r.merit_histories)
                        .enumerate()
                    {
                        let f = |v: &[f64]| {
                            v.iter()
                                .map(|x| format!("{x:.2e}"))
                                .collect::<Vec<_>>()
                                .join(" ")
                        };
                        println!("HIST {k}.{s} residual {}", f(res));
                        println!("HIST {k}.{s} merit {}", f(mer));
                    }
                }
            }
            Err(e) => {
                println!("FAIL {k} {e}");
                break;
            }
        }
        std::io::stdout().flush().unwrap();
        if let (Some(path), true) = (&save_path, k == steps) {
            save(path, k, &state, stepper.stress_rate());
        }
    }
    eprintln!("total Newton iterations {total}");
}
