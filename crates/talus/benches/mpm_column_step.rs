//! Wall time per implicit MPM step of a granular column collapse, against one elastic step
//! of the same particles: the ratio of the two medians is the figure of merit printed by
//! `cargo xtask bench` ("plastic step / elastic step").
//!
//! Set-up: a column `L₀ × 2L₀` (`L₀` = 0.1 m) of cohesionless Drucker-Prager sand (φ = 30°,
//! θ = 0, E = 1e7 Pa, ν = 0.3, ρ = 1800 kg/m³, plane-strain cone fit) standing on a fixed
//! floor against a slip left wall (the symmetry plane), under gravity; quadratic B-splines,
//! 2 × 2 particles per cell, `MpmSettings::default()`. `n` cells across the column:
//! `8 n²` particles (35 → 9 800, 112 → 100 352). The grid spans `5 L₀ × 2.2 L₀`, room for
//! the whole run-out. The step is `h = 20 dx / c_p`, twenty times the explicit limit, with
//! `c_p = √(E(1−ν)/((1+ν)(1−2ν)ρ))`.
//!
//! Three steps from rest are not timed (the column is then moving and yielding); each of
//! the next N steps is timed twice from the same particles: first an elastic step (a copy
//! of the particles advanced by an `Mpm` whose material has c = 1e6 Pa, about 300 times the
//! largest stress, so that every particle stays elastic: one Newton iteration), then the
//! plastic step that advances the column. Times are `StepReport::seconds` (all of
//! the engine's `advance`: P2G, assembly, solver set-up, Newton, G2P); medians over the N steps.
//!
//! Each size runs in a child process (this binary re-invoked with `--child`), so that its
//! peak resident memory (`VmHWM`) is its own.
//!
//! ```sh
//! cargo bench -p talus --bench mpm_column_step                   # 10k (5 steps), 100k (2)
//! TALUS_MPM_BENCH_SIZES=10k cargo bench -p talus --bench mpm_column_step   # skip 100k
//! cargo bench -p talus --bench mpm_column_step -- --sizes 10k,100k --steps 3
//! ```
//!
//! Without `--bench` (`cargo test --benches`) it takes one step of a 128-particle column,
//! as a smoke test.
use std::process::{Command, Stdio};

use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_engine::StepSettings;
use talus_mpm::{
    Grid, GridBoundary, Mpm, MpmSettings, Particles, ShapeFunction, Side, Wall, WallCondition,
};
use talus_mpm::{MpmStepReport as StepReport, MpmStepper};

const YOUNG: f64 = 1e7;
const POISSON: f64 = 0.3;
const DENSITY: f64 = 1800.0;
const FRICTION_ANGLE: f64 = 30.0;
/// Cohesion of the elastic baseline (Pa): the largest stress of the column is about
/// ρ g 2L₀ ≈ 3.5 kPa.
const ELASTIC_COHESION: f64 = 1e6;
/// Column width (m); its height is 2 L₀.
const WIDTH: f64 = 0.1;
/// h / (dx / c_p).
const CFL_MULTIPLE: f64 = 20.0;
/// Steps from rest before the timed ones.
const WARM_UP: usize = 3;
/// Name, cells across the column, timed steps.
const SIZES: [(&str, usize, usize); 2] = [("10k", 35, 5), ("100k", 112, 2)];

/// On a worker of rayon's pool, as `talus run` solves (`talus_ssn::on_pool`).
fn main() {
    talus_ssn::on_pool(bench);
}

fn bench() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--child") {
        let n = args[1].parse().expect("cells across the column");
        let steps = args[2].parse().expect("timed steps");
        let r = measure(n, steps, true);
        println!("RESULT {}", r.to_line());
        return;
    }
    if !args.iter().any(|a| a == "--bench") {
        // `cargo test --benches`: one quick step, in process.
        let r = measure(4, 1, false);
        assert!(
            r.plastic_seconds > 0.0 && r.elastic_iterations >= 1.0,
            "{r:?}"
        );
        println!(
            "column_step smoke test: {} particles, one step ok",
            r.particles
        );
        return;
    }
    let mut selected: Option<String> = std::env::var("TALUS_MPM_BENCH_SIZES").ok();
    let mut steps: Option<usize> = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--sizes" => selected = Some(it.next().expect("--sizes 10k,100k").clone()),
            "--steps" => steps = Some(it.next().expect("--steps N").parse().expect("N")),
            _ => {} // `--bench` and cargo's filters
        }
    }
    let names: Vec<&str> = match &selected {
        Some(s) => s
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect(),
        None => SIZES.iter().map(|s| s.0).collect(),
    };
    let exe = std::env::current_exe().expect("own path");
    let mut results = Vec::new();
    for name in names {
        let Some(&(_, n, default_steps)) = SIZES.iter().find(|s| s.0 == name) else {
            panic!("unknown size {name} (one of 10k, 100k)");
        };
        let steps = steps.unwrap_or(default_steps);
        let out = Command::new(&exe)
            .args(["--child".to_string(), n.to_string(), steps.to_string()])
            .stderr(Stdio::inherit())
            .output()
            .expect("child process");
        let text = String::from_utf8_lossy(&out.stdout);
        match text.lines().find_map(|l| l.strip_prefix("RESULT ")) {
            Some(line) => results.push((name, steps, Measurement::from_line(line))),
            None => {
                eprintln!("column_step {name}: child failed ({})", out.status);
                std::process::exit(1);
            }
        }
    }
    println!(
        "\ncolumn collapse, φ = 30°, θ = 0, quadratic B-splines, 2×2 particles per cell, \
         h = {CFL_MULTIPLE} dx/c_p; medians after {WARM_UP} warm-up steps"
    );
    println!(
        "| case | particles | grid cells | free dofs | h (s) | dx/c_p (s) | h/limit | steps timed \
         | s/step | Newton its/step | substeps/step | solve fraction | wall s per simulated s \
         | elastic s/step | elastic its/step | plastic/elastic | peak MiB | warm-up peak MiB |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (name, steps, r) in &results {
        println!(
            "| {name} | {} | {}×{} | {} | {:.3e} | {:.3e} | {:.1} | {steps} | {:.3} | {:.2} | {:.1} | {:.2} \
             | {:.0} | {:.3} | {:.2} | {:.2} | {:.0} | {:.0} |",
            r.particles,
            r.cells[0],
            r.cells[1],
            r.free_dofs,
            r.h,
            r.limit,
            r.h / r.limit,
            r.plastic_seconds,
            r.plastic_iterations,
            r.plastic_substeps,
            r.solve_fraction,
            r.plastic_seconds / r.h,
            r.elastic_seconds,
            r.elastic_iterations,
            r.plastic_seconds / r.elastic_seconds,
            r.peak_kib / 1024.0,
            r.warm_up_peak_kib / 1024.0,
        );
    }
    println!();
    for (name, _, r) in &results {
        println!(
            "plastic step / elastic step, column {name}: {:.2} ({:.3} s / {:.3} s, {:.2} / {:.2} Newton its)",
            r.plastic_seconds / r.elastic_seconds,
            r.plastic_seconds,
            r.elastic_seconds,
            r.plastic_iterations,
            r.elastic_iterations,
        );
    }
}

#[derive(Debug, Clone, Default)]
struct Measurement {
    particles: usize,
    cells: [usize; 2],
    free_dofs: usize,
    /// Step and explicit limit dx/c_p (s).
    h: f64,
    limit: f64,
    /// Medians of the timed steps (s).
    plastic_seconds: f64,
    elastic_seconds: f64,
    /// Means of the timed steps. A sub-step whose Newton solve fails is redone as two
    /// halves; `StepReport` counts the iterations and solve time of successful sub-steps
    /// only, so the failed attempt shows as time outside the solve.
    plastic_iterations: f64,
    plastic_substeps: f64,
    elastic_iterations: f64,
    /// Σ solve_seconds / Σ seconds of the timed plastic steps.
    solve_fraction: f64,
    /// VmHWM during the timed steps, and during set-up and warm-up (KiB).
    peak_kib: f64,
    warm_up_peak_kib: f64,
}

impl Measurement {
    fn to_line(&self) -> String {
        format!(
            "{} {} {} {} {:e} {:e} {:e} {:e} {} {} {} {} {} {}",
            self.particles,
            self.cells[0],
            self.cells[1],
            self.free_dofs,
            self.h,
            self.limit,
            self.plastic_seconds,
            self.elastic_seconds,
            self.plastic_iterations,
            self.elastic_iterations,
            self.solve_fraction,
            self.peak_kib,
            self.warm_up_peak_kib,
            self.plastic_substeps
        )
    }

    fn from_line(line: &str) -> Self {
        let v: Vec<f64> = line
            .split_whitespace()
            .map(|x| x.parse().unwrap_or(f64::NAN))
            .collect();
        Self {
            particles: v[0] as usize,
            cells: [v[1] as usize, v[2] as usize],
            free_dofs: v[3] as usize,
            h: v[4],
            limit: v[5],
            plastic_seconds: v[6],
            elastic_seconds: v[7],
            plastic_iterations: v[8],
            elastic_iterations: v[9],
            solve_fraction: v[10],
            peak_kib: v[11],
            warm_up_peak_kib: v[12],
            plastic_substeps: v[13],
        }
    }
}

fn material(cohesion: f64) -> DruckerPrager {
    DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: YOUNG,
        poisson_ratio: POISSON,
        friction_angle: FRICTION_ANGLE,
        cohesion,
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::PlaneStrain,
    })
    .expect("material")
}

/// The column with `n` cells across, `WARM_UP` untimed steps, then `steps` timed pairs
/// (elastic copy, plastic step). Progress on stderr if `verbose`.
fn measure(n: usize, steps: usize, verbose: bool) -> Measurement {
    let dx = WIDTH / n as f64;
    let c_p =
        (YOUNG * (1.0 - POISSON) / ((1.0 + POISSON) * (1.0 - 2.0 * POISSON) * DENSITY)).sqrt();
    let limit = dx / c_p;
    let h = CFL_MULTIPLE * limit;
    let cells = [5 * n, (2.2 * n as f64).ceil() as usize];
    let grid = Grid::try_new([0.0, 0.0], dx, cells, ShapeFunction::QuadraticBSpline).expect("grid");
    let boundary = GridBoundary {
        walls: vec![
            Wall {
                side: Side::Left,
                condition: WallCondition::Slip,
            },
            Wall {
                side: Side::Bottom,
                condition: WallCondition::Fixed,
            },
        ],
        prescribed: vec![],
    };
    let gravity = [0.0, -9.81];
    let settings = MpmSettings::default();
    let plastic = Mpm::try_new(
        grid.clone(),
        boundary.clone(),
        &material(0.0),
        gravity,
        settings,
    )
    .expect("plastic mpm");
    // TALUS_MPM_BENCH_NO_REUSE=1: a new solver (pattern and symbolic analysis) for every
    // friction pass, the cost before the passes shared one analysis.
    let mut plastic = MpmStepper::with_settings(
        plastic,
        StepSettings {
            reuse_analysis: std::env::var("TALUS_MPM_BENCH_NO_REUSE").is_err(),
            ..StepSettings::mpm()
        },
    );
    let elastic = Mpm::try_new(
        grid,
        boundary,
        &material(ELASTIC_COHESION),
        gravity,
        settings,
    )
    .expect("elastic mpm");
    let mut elastic = MpmStepper::new(elastic);
    let mut particles =
        Particles::fill_rectangle([[0.0, 0.0], [WIDTH, 2.0 * WIDTH]], dx, 2, DENSITY)
            .expect("particles");
    let log = |what: &str, r: &StepReport| {
        if verbose {
            eprintln!(
                "column {n}: {what}: {} its (first pass {}, {} backtracks of {}), {} passes ({} reused analyses), {} substeps, {:.3} s (solve {:.3} s), residual {:.1e}, {} free dofs",
                r.total_newton_iterations(), r.first_solve_iterations, r.first_solve_backtracks, r.backtracks,
                r.solves_per_substep, r.reused_analyses, r.substeps, r.seconds, r.solve_seconds, r.relative_residual, r.stats.as_ref().map_or(0, |s| s.free_dofs)
            );
        }
    };
    for k in 0..WARM_UP {
        let r = plastic.advance(&mut particles, h).expect("warm-up step");
        log(&format!("warm-up step {}", k + 1), &r);
    }
    // Peak of the set-up and warm-up, then restart the count for the timed steps
    // (writing 5 to clear_refs resets VmHWM to the current RSS).
    let warm_up_peak_kib = peak_kib() as f64;
    let _ = std::fs::write("/proc/self/clear_refs", "5");
    let mut plastic_reports = Vec::new();
    let mut elastic_reports = Vec::new();
    for k in 0..steps {
        let mut copy = particles.clone();
        let before = copy.plastic_strain.clone();
        let r = elastic.advance(&mut copy, h).expect("elastic step");
        log(&format!("step {} elastic", WARM_UP + k + 1), &r);
        let max_increment = copy
            .plastic_strain
            .iter()
            .zip(&before)
            .map(|(a, b)| a - b)
            .fold(0.0, f64::max);
        // z is zero at an elastic particle up to rounding (about 1e-15 here).
        assert!(
            max_increment < 1e-10,
            "the elastic baseline yielded: plastic strain increment {max_increment:e}"
        );
        elastic_reports.push(r);
        let r = plastic.advance(&mut particles, h).expect("plastic step");
        log(&format!("step {} plastic", WARM_UP + k + 1), &r);
        plastic_reports.push(r);
    }
    let last = plastic_reports.last().expect("at least one timed step");
    let total = |rs: &[StepReport], f: fn(&StepReport) -> f64| rs.iter().map(f).sum::<f64>();
    Measurement {
        particles: particles.len(),
        cells,
        free_dofs: last.stats.as_ref().map_or(0, |s| s.free_dofs),
        h,
        limit,
        plastic_seconds: median(plastic_reports.iter().map(|r| r.seconds).collect()),
        elastic_seconds: median(elastic_reports.iter().map(|r| r.seconds).collect()),
        plastic_iterations: total(&plastic_reports, |r| r.total_newton_iterations() as f64)
            / steps as f64,
        plastic_substeps: total(&plastic_reports, |r| r.substeps as f64) / steps as f64,
        elastic_iterations: total(&elastic_reports, |r| r.total_newton_iterations() as f64)
            / steps as f64,
        solve_fraction: total(&plastic_reports, |r| r.solve_seconds)
            / total(&plastic_reports, |r| r.seconds),
        peak_kib: peak_kib() as f64,
        warm_up_peak_kib,
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len().is_multiple_of(2) {
        0.5 * (v[m - 1] + v[m])
    } else {
        v[m]
    }
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
