//! Where the Newton iterations of the matched a = 2 column go (`scenes/column_newton.toml`,
//! issue 24 item 4): the same column, material, grid and particles, stepped by a driver that
//! mirrors talus-engine's `Stepper` (nested halvings, the halving memory) but logs every
//! friction pass of every attempt, failed ones included: its iterations, backtracks and
//! status. Step-control variants (`--control`) show what the column needs from the engine.
//!
//! ```sh
//! cargo run --release -p talus-mpm --example column_newton_probe -- --steps 60 -v
//! cargo run --release -p talus-mpm --example column_newton_probe -- --control grow
//! ```
//! Options: `--steps N` (60), `--h S` (1/60), `--halvings N` (4), `--memory N` (4),
//! `--control halve|grow` (`halve`: the engine's rule today; `grow`: the sub-step size
//! remembered across steps, halved on a failure and doubled after `--grow-after` (1)
//! successes, capped at h), `--max-iterations N` (50), `--stall W` (0: none),
//! `--all-stuck` (every friction node stuck at a sub-step's start, as before
//! `MpmSettings::contact_predictor`), `-v`.
use std::time::Instant;

use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_engine::StepSettings;
use talus_mpm::{
    Grid, GridBoundary, Mpm, MpmSettings, Particles, ShapeFunction, Side, Wall, WallCondition,
};
use talus_ssn::{SolveError, Solver, Stall, Status};

const L0: f64 = 0.2;
const H0: f64 = 0.4;

/// One solve (friction pass) of an attempt.
#[derive(Debug, Clone)]
struct Pass {
    iterations: usize,
    backtracks: usize,
    status: Status,
    /// Friction nodes (stuck, sliding) during the solve.
    states: (usize, usize),
}

/// One attempt at a sub-step: its passes, and whether it was accepted.
#[derive(Debug, Clone)]
struct Attempt {
    h: f64,
    passes: Vec<Pass>,
    accepted: bool,
    /// What each pass changed in the friction states (to slide, to stick, forces).
    changes: Vec<String>,
}

fn attempt(
    mpm: &Mpm,
    particles: &mut Particles,
    h: f64,
    settings: &talus_ssn::Settings,
) -> Attempt {
    let mut log = Attempt {
        h,
        passes: Vec::new(),
        accepted: false,
        changes: Vec::new(),
    };
    let (mut substep, system) = mpm.begin_substep(particles, h).expect("begin");
    let mut solver = Solver::new(system, *settings).expect("solver");
    let mut sigma: Vec<f64> = particles.stress.as_flattened().to_vec();
    loop {
        match solver.solve(&mut sigma) {
            Ok(r) => log.passes.push(Pass {
                iterations: r.iterations,
                backtracks: r.backtracks,
                status: r.status,
                states: substep.contact_states(),
            }),
            Err(SolveError::NotConverged(r)) => {
                if std::env::var("PROBE_HISTORY").is_ok() {
                    let hist: Vec<String> = r
                        .residual_history
                        .iter()
                        .step_by(5)
                        .map(|v| format!("{:.1e}", v / r.scale))
                        .collect();
                    eprintln!("      failed pass, every 5th residual: {}", hist.join(" "));
                }
                log.passes.push(Pass {
                    iterations: r.iterations,
                    backtracks: r.backtracks,
                    status: r.status,
                    states: substep.contact_states(),
                });
                return log;
            }
            Err(e) => panic!("solve: {e}"),
        }
        match substep
            .after_solve(mpm, particles, &sigma, solver.z())
            .expect("after_solve")
        {
            Some(next) => {
                solver.replace_problem(next).expect("replace");
            }
            None => break,
        }
    }
    log.changes = substep
        .contact_changes()
        .iter()
        .map(|c| format!("+{}/-{}/f{}", c.to_slide, c.to_stick, c.forces))
        .collect();
    substep.finish(mpm, particles, sigma).expect("finish");
    log.accepted = true;
    log
}

/// The engine's nested halving from `level`; false if it failed below `max_level`.
fn advance_level(
    mpm: &Mpm,
    particles: &mut Particles,
    h: f64,
    level: usize,
    max_level: usize,
    settings: &talus_ssn::Settings,
    log: &mut Vec<Attempt>,
) -> bool {
    let mut trial = particles.clone();
    let a = attempt(mpm, &mut trial, h, settings);
    let ok = a.accepted;
    log.push(a);
    if ok {
        *particles = trial;
        return true;
    }
    if level >= max_level {
        return false;
    }
    advance_level(mpm, particles, 0.5 * h, level + 1, max_level, settings, log)
        && advance_level(mpm, particles, 0.5 * h, level + 1, max_level, settings, log)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .map(|v| v.parse::<f64>().unwrap_or_else(|_| panic!("{name} {v}")))
    };
    let text = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let verbose = args.iter().any(|a| a == "-v");
    let steps = value("--steps").unwrap_or(60.0) as usize;
    let h = value("--h").unwrap_or(1.0 / 60.0);
    let max_halvings = value("--halvings").unwrap_or(4.0) as usize;
    let memory = value("--memory").unwrap_or(4.0) as usize;
    let grow_after = value("--grow-after").unwrap_or(1.0) as usize;
    let control = text("--control").unwrap_or_else(|| "halve".into());
    let mut settings = StepSettings::mpm().solver;
    settings.parallel = false;
    if let Some(n) = value("--max-iterations") {
        settings.max_iterations = n as usize;
    }
    if let Some(w) = value("--stall") {
        settings.stall = (w > 0.0).then_some(Stall {
            window: w as usize,
            ..Stall::DEFAULT
        });
    }
    if let Some(a) = value("--stall-after") {
        if let Some(s) = settings.stall.as_mut() {
            s.after = a as usize;
        }
    }

    let dx = L0 / 15.0;
    let soil = DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e7,
        poisson_ratio: 0.3,
        friction_angle: 0.5f64.atan().to_degrees(),
        cohesion: 0.0,
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::Explicit {
            k_d: std::f64::consts::SQRT_2,
        },
    })
    .expect("material");
    let grid =
        Grid::try_new([0.0, 0.0], dx, [99, 36], ShapeFunction::QuadraticBSpline).expect("grid");
    let boundary = GridBoundary {
        walls: vec![
            Wall {
                side: Side::Left,
                condition: WallCondition::Slip,
            },
            Wall {
                side: Side::Bottom,
                condition: WallCondition::Friction { coefficient: 0.5 },
            },
        ],
        prescribed: vec![],
    };
    let mpm_settings = MpmSettings {
        flip_ratio: value("--flip").unwrap_or(0.95),
        contact_predictor: !args.iter().any(|a| a == "--all-stuck"),
        ..MpmSettings::default()
    };
    let mpm = Mpm::try_new(grid, boundary, &soil, [0.0, -9.81], mpm_settings).expect("mpm");
    let mut particles =
        Particles::fill_rectangle([[0.0, 0.0], [L0, H0]], dx, 3, 1500.0).expect("particles");
    eprintln!(
        "{} particles, h = {h:.5} s, control {control}, max {max_halvings} halvings",
        particles.len()
    );

    let clock = Instant::now();
    let (mut accepted_its, mut failed_its, mut halved, mut substeps) = (0, 0, 0, 0);
    let (mut passes_accepted, mut first_pass_its) = (0, 0);
    let mut done = 0;
    // Engine memory (halve) or remembered sub-step level (grow).
    let (mut level, mut clean) = (0usize, 0usize);
    for k in 0..steps {
        let mut log = Vec::new();
        let start = level.min(max_halvings);
        let parts = 1usize << start;
        let ok = match control.as_str() {
            "halve" => {
                let mut ok = true;
                for _ in 0..parts {
                    ok = ok
                        && advance_level(
                            &mpm,
                            &mut particles,
                            h / parts as f64,
                            start,
                            max_halvings,
                            &settings,
                            &mut log,
                        );
                }
                ok
            }
            "grow" => {
                // Sub-steps of h / 2^level, the level remembered across steps; a failure
                // halves, `grow_after` successes in a row double (capped at h).
                let mut t = 0.0;
                let mut ok = true;
                while t < h * (1.0 - 1e-12) {
                    let hs = (h / (1usize << level) as f64).min(h - t);
                    let mut trial = particles.clone();
                    let a = attempt(&mpm, &mut trial, hs, &settings);
                    let acc = a.accepted;
                    log.push(a);
                    if acc {
                        particles = trial;
                        t += hs;
                        clean += 1;
                        if clean >= grow_after && level > 0 {
                            level -= 1;
                            clean = 0;
                        }
                    } else if level < max_halvings {
                        level += 1;
                        clean = 0;
                    } else {
                        ok = false;
                        break;
                    }
                }
                ok
            }
            other => panic!("--control {other}"),
        };
        if !ok {
            eprintln!("step {} failed", k + 1);
            for a in &log {
                let p: Vec<String> = a
                    .passes
                    .iter()
                    .map(|p| format!("{}({}){}", p.iterations, p.backtracks, p.status))
                    .collect();
                eprintln!("    h/{:<3} passes [{}]", (h / a.h).round(), p.join(" "));
            }
            break;
        }
        done += 1;
        let acc: Vec<&Attempt> = log.iter().filter(|a| a.accepted).collect();
        let smallest = acc.iter().map(|a| a.h).fold(h, f64::min);
        if control == "halve" && memory > 0 {
            let deepest = (h / smallest).log2().round() as usize;
            if deepest > start {
                level = deepest;
                clean = 0;
            } else {
                clean += 1;
                if clean >= memory {
                    level = start.saturating_sub(1);
                    clean = 0;
                }
            }
        }
        let its = |a: &Attempt| a.passes.iter().map(|p| p.iterations).sum::<usize>();
        let a_its: usize = acc.iter().map(|a| its(a)).sum();
        let f_its: usize = log.iter().filter(|a| !a.accepted).map(its).sum();
        accepted_its += a_its;
        failed_its += f_its;
        substeps += acc.len();
        halved += (acc.len() > 1 || smallest < h) as usize;
        passes_accepted += acc.iter().map(|a| a.passes.len()).sum::<usize>();
        first_pass_its += acc.iter().map(|a| a.passes[0].iterations).sum::<usize>();
        if verbose {
            let front = particles.position.iter().map(|x| x[0]).fold(0.0, f64::max);
            eprintln!(
                "step {:3} t={:.3} acc {:4} failed {:4} substeps {:2} runout {:.3}",
                k + 1,
                (k + 1) as f64 * h,
                a_its,
                f_its,
                acc.len(),
                (front - L0) / L0
            );
            for a in &log {
                let p: Vec<String> = a
                    .passes
                    .iter()
                    .map(|p| {
                        let (st, sl) = p.states;
                        if p.status == Status::Converged {
                            format!("{}({}){{{st}|{sl}}}", p.iterations, p.backtracks)
                        } else {
                            format!("{}({})!{}", p.iterations, p.backtracks, p.status)
                        }
                    })
                    .collect();
                eprintln!(
                    "    h/{:<3} {} passes [{}] changes [{}]",
                    (h / a.h).round(),
                    if a.accepted { "ok  " } else { "FAIL" },
                    p.join(" "),
                    a.changes.join(" ")
                );
            }
        }
    }
    let seconds = clock.elapsed().as_secs_f64();
    let front = particles.position.iter().map(|x| x[0]).fold(0.0, f64::max);
    let n = done.max(1) as f64;
    println!(
        "| control | steps | its/step acc + failed | halved | sub-steps/step | passes/sub-step | first-pass its/sub-step | wall s / simulated s | runout |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    println!(
        "| {control} | {done} | {:.1} + {:.1} | {halved} | {:.2} | {:.2} | {:.1} | {:.1} | {:.3} |",
        accepted_its as f64 / n,
        failed_its as f64 / n,
        substeps as f64 / n,
        passes_accepted as f64 / substeps.max(1) as f64,
        first_pass_its as f64 / substeps.max(1) as f64,
        seconds / (done as f64 * h),
        (front - L0) / L0
    );
}
