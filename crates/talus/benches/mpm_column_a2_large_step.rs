//! The a = 2 granular column (`scenes/column_a2.toml`: L₀ = 0.1 m, H₀ = 0.2 m, φ = 30°,
//! θ = 0, c = 0, E = 1e7 Pa, ν = 0.3, ρ = 1800 kg/m³, slip left wall, Coulomb floor μ = 0.6,
//! dx = 0.01 m, quadratic B-splines) with 4 × 4 particles per cell (3 200 particles) at
//! h = 1/60 s, 144 times the explicit limit dx/c_p, for 1 s of collapse with
//! `MpmSettings::default()`. Prints whether it finished, Newton iterations per step (mean,
//! first friction pass, backtracks), halved steps, wall seconds per simulated second and
//! the runout `(L − L₀)/L₀` (front = largest particle x).
//!
//! ```sh
//! cargo bench -p talus --bench mpm_column_a2_large_step
//! cargo bench -p talus --bench mpm_column_a2_large_step -- --per-cell 2 --steps 30
//! ```
//! Without `--bench` (`cargo test --benches`) it runs 3 steps of a 200-particle column.
use std::time::Instant;

use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_engine::{PredictorRule, StepSettings};
use talus_mpm::MpmStepper;
use talus_mpm::{
    Grid, GridBoundary, Mpm, MpmSettings, Particles, ShapeFunction, Side, Wall, WallCondition,
};

const WIDTH: f64 = 0.1;
const HEIGHT: f64 = 0.2;
const DX: f64 = 0.01;
const H: f64 = 1.0 / 60.0;

/// On a worker of rayon's pool, as `talus run` solves (`talus_ssn::on_pool`).
fn main() {
    talus_ssn::on_pool(bench);
}

fn bench() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .map(|v| v.parse::<f64>().unwrap_or_else(|_| panic!("{name} {v}")))
    };
    let bench = args.iter().any(|a| a == "--bench");
    let per_cell = value("--per-cell").unwrap_or(if bench { 4.0 } else { 1.0 }) as usize;
    let steps = value("--steps").unwrap_or(if bench { 60.0 } else { 3.0 }) as usize;
    let mut settings = MpmSettings::default();
    if let Some(a) = value("--flip") {
        settings.flip_ratio = a;
    }
    let mut stepping = StepSettings::mpm();
    if args.iter().any(|a| a == "--elastic-predictor") {
        stepping.predictor = PredictorRule::Elastic;
    }
    // A new solver for every friction pass (the cost before the passes shared one).
    stepping.reuse_analysis = !args.iter().any(|a| a == "--no-reuse");
    if let Some(f) = value("--rho-diagonal") {
        stepping.solver.rho = talus_ssn::Rho::PerPointDiagonal { factor: f };
    }
    if let Some(f) = value("--rho-compliance") {
        stepping.solver.rho = talus_ssn::Rho::PerPointCompliance { factor: f };
    }
    let soil = DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e7,
        poisson_ratio: 0.3,
        friction_angle: 30.0,
        cohesion: 0.0,
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::PlaneStrain,
    })
    .expect("material");
    let grid =
        Grid::try_new([0.0, 0.0], DX, [59, 24], ShapeFunction::QuadraticBSpline).expect("grid");
    let boundary = GridBoundary {
        walls: vec![
            Wall {
                side: Side::Left,
                condition: WallCondition::Slip,
            },
            Wall {
                side: Side::Bottom,
                condition: WallCondition::Friction { coefficient: 0.6 },
            },
        ],
        prescribed: vec![],
    };
    let mpm = Mpm::try_new(grid, boundary, &soil, [0.0, -9.81], settings).expect("mpm");
    let mut mpm = MpmStepper::with_settings(mpm, stepping);
    let mut particles =
        Particles::fill_rectangle([[0.0, 0.0], [WIDTH, HEIGHT]], DX, per_cell, 1800.0)
            .expect("particles");
    let verbose = std::env::var("TALUS_BENCH_VERBOSE").is_ok();
    let clock = Instant::now();
    let (mut its, mut first, mut backtracks, mut halved, mut done) = (0, 0, 0, 0, 0);
    let mut failure = None;
    for k in 0..steps {
        match mpm.advance(&mut particles, H) {
            Ok(r) => {
                done += 1;
                its += r.total_newton_iterations();
                first += r.first_solve_iterations;
                backtracks += r.backtracks;
                halved += (r.substeps > 1) as usize;
                if verbose {
                    eprintln!(
                        "step {:3} t = {:.3}: {:4} its (first pass {:3}), {:4} backtracks, {} passes, {:2} substeps, {:.2} s",
                        k + 1,
                        (k + 1) as f64 * H,
                        r.total_newton_iterations(),
                        r.first_solve_iterations,
                        r.backtracks,
                        r.solves_per_substep,
                        r.substeps,
                        r.seconds
                    );
                }
            }
            Err(e) => {
                failure = Some(format!("step {} (t = {:.3} s): {e}", k + 1, k as f64 * H));
                break;
            }
        }
    }
    let seconds = clock.elapsed().as_secs_f64();
    let front = particles.position.iter().map(|x| x[0]).fold(0.0, f64::max);
    let n = done.max(1) as f64;
    println!(
        "\na = 2 column, {} particles, h = 1/60 s = {:.0} dx/c_p, {} steps",
        particles.len(),
        H / (DX / 86.48),
        steps
    );
    println!("| finished | steps done | Newton its/step | first pass its/step | backtracks/step | halved steps | wall s per simulated s | runout (L−L0)/L0 |");
    println!("|---|---|---|---|---|---|---|---|");
    println!(
        "| {} | {done} | {:.1} | {:.1} | {:.1} | {halved} | {:.1} | {:.2} |",
        failure.is_none(),
        its as f64 / n,
        first as f64 / n,
        backtracks as f64 / n,
        seconds / (done as f64 * H).max(H),
        (front - WIDTH) / WIDTH
    );
    println!(
        "column a2 large step: finished {} after {:.3} s, {:.1} Newton its/step, {:.1} wall s per simulated s",
        failure.is_none(),
        done as f64 * H,
        its as f64 / n,
        seconds / (done as f64 * H).max(H)
    );
    if let Some(f) = failure {
        println!("failed at {f}");
        if !bench {
            std::process::exit(1);
        }
    }
}
