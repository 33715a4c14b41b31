//! One Newton iteration of the paper footing (`scenes/footing.toml`) against one elastic
//! Cholesky factorization and solve of the same mesh (issue 10: target ≤ 2.0 at 10k and
//! 100k elements), printed as `ratio CASE: …` lines that `cargo xtask bench` collects.
//!
//! Cases: `lu` is the paper's non-associative soil (tan θ = tan φ / 2: the no-pivot LU of
//! the velocity-sized Newton matrix), `llt` the associative variant (θ = φ: Cholesky);
//! `32x14` is the paper mesh (896 P2 triangles), `104x48` 9 984 and `320x156` 99 840
//! triangles, graded as the paper's mesh. The state is reached outside the timed region by
//! stepping the scene 4 steps as `talus run` does (early plastic loading).
//!
//! - `newton iteration`: a `Solver` on the operator and `q` of the next step with
//!   `max_iterations = 1` and no line search, `solve` from the stepper's start σₙ + h σ̇:
//!   residual at the start, local blocks, assembly, numeric factorization and solve, the
//!   check `‖J d + F‖`, residual at the new iterate (one evaluation more than an iteration
//!   inside a longer solve). The symbolic analysis is done once, outside the timed region.
//! - `cholesky`: the baseline, faer's supernodal Cholesky of the elastic matrix
//!   `K = M + h² Σ Bᵢᵀ Sᵢ⁻¹ Bᵢ` (the Newton matrix's pattern) with its own AMD symbolic
//!   analysis done once and its storage reused (`SupernodalCholesky`): numeric
//!   factorization and one solve.
//! - `lu on K`: our no-pivot LU (`talus_ssn::factorization`) of the same SPD `K`, numeric
//!   factorization and one solve: the factorization's share of the ratio.
//! - `evaluation`: `Solver::residual_at` (`z = Wσ + q`, the linearization at every point).
//!
//! Each time is the median of `REPEATS` runs (3 at 100k). Sizes: `TALUS_STEP_BENCH_SIZES`
//! (comma-separated `NXxNY`, default `32x14,104x48,320x156`; 100k takes about 10 minutes).
//!
//! Run with `cargo bench -p talus --bench step`.

use std::sync::Arc;
use std::time::Instant;

use nalgebra::{SMatrix, SVector};
use talus::model::fem::{FromScene, Model};
use talus::run::fem::solver_settings;
use talus::scene::{builtin_footing_with_cells, Scene};
use talus_engine::{StepSettings, Stepper};
use talus_ssn::factorization::{
    SupernodalCholesky, SymbolicSymmetricPatternLu, SymmetricPatternLu, DEFAULT_PIVOT_TOLERANCE,
};
use talus_ssn::faer::sparse::{SparseColMat, Triplet};
use talus_ssn::{SolveError, Solver};

/// Steps taken before timing: early plastic loading on every mesh.
const STEPS: usize = 4;

/// On a worker of rayon's pool, as `talus run` solves (`talus_ssn::on_pool`).
fn main() {
    talus_ssn::on_pool(bench);
}

fn bench() {
    let sizes = std::env::var("TALUS_STEP_BENCH_SIZES")
        .unwrap_or_else(|_| "32x14,104x48,320x156".to_string());
    // `cargo bench` passes `--bench`; nothing else is understood.
    for cells in sizes.split(',').filter(|s| !s.is_empty()) {
        let Some((nx, ny)) = cells.split_once('x') else {
            eprintln!("TALUS_STEP_BENCH_SIZES: `{cells}` is not NXxNY");
            std::process::exit(2);
        };
        let (Ok(nx), Ok(ny)) = (nx.parse::<usize>(), ny.parse::<usize>()) else {
            eprintln!("TALUS_STEP_BENCH_SIZES: `{cells}` is not NXxNY");
            std::process::exit(2);
        };
        for associative in [false, true] {
            run_case([nx, ny], associative);
        }
    }
}

fn scene(cells: [usize; 2], associative: bool) -> Scene {
    let mut scene = builtin_footing_with_cells(cells);
    if associative {
        let m = scene.spec.material.single_mut().expect("one material");
        m.dilatancy_angle = m.friction_angle;
    }
    scene
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn run_case(cells: [usize; 2], associative: bool) {
    let case = format!(
        "{} {}x{}",
        if associative { "llt" } else { "lu" },
        cells[0],
        cells[1]
    );
    let scene = scene(cells, associative);
    let model = Model::from_scene(&scene).expect("model");
    let asm = &model.assembly;
    let h = scene.spec.time.step;
    let mut state = model.initial_state(&scene).expect("K0 state");
    let settings = solver_settings(&scene);
    let mut stepper = Stepper::new(
        &model,
        StepSettings::with_solver(settings, scene.spec.solver.max_step_halvings),
    );
    let mut previous = state.sigma.clone();
    for _ in 0..STEPS {
        previous.clone_from(&state.sigma);
        stepper.advance(&mut state, h).expect("step converges");
    }
    drop(stepper);
    let repeats = if asm.n_points() > 200_000 { 3 } else { 9 };

    let mut one = settings;
    one.max_iterations = 1;
    one.line_search = None;
    let system = model.reduced_system(h).expect("W");
    let mut solver = Solver::new(system, one).expect("solver");
    solver
        .set_q(model.reduced_rhs(&state, h))
        .expect("q of the next step");
    let start: Vec<f64> = state
        .sigma
        .iter()
        .zip(&previous)
        .map(|(s, p)| s + (s - p))
        .collect();
    let compliance = model.compliance_blocks();
    let lower = elastic_matrix(&model, &compliance, h, true);
    let full = elastic_matrix(&model, &compliance, h, false);
    let rhs: Vec<f64> = (0..full.nrows()).map(|i| 1.0 + (i % 7) as f64).collect();
    let mut llt = SupernodalCholesky::try_new(lower.symbolic()).expect("symbolic");
    let lu_symbolic =
        Arc::new(SymbolicSymmetricPatternLu::try_new(full.symbolic()).expect("LU symbolic"));
    let fill = lu_symbolic.factor_nnz();
    let mut lu = SymmetricPatternLu::new(lu_symbolic);
    // Interleaved, so that a change of the machine's load touches every figure alike.
    let (mut iteration, mut cholesky, mut lu_times, mut evaluation) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for _ in 0..repeats {
        let mut sigma = start.clone();
        let t = Instant::now();
        match solver.solve(&mut sigma) {
            Err(SolveError::NotConverged(r)) => {
                assert_eq!((r.iterations, r.schur_steps), (1, 1), "{case}: {r:?}")
            }
            other => panic!("{case}: expected one iteration, got {other:?}"),
        }
        iteration.push(t.elapsed().as_secs_f64());

        let t = Instant::now();
        llt.factorize(lower.as_ref()).expect("K is SPD");
        let mut x = rhs.clone();
        llt.solve_in_place(&mut x);
        cholesky.push(t.elapsed().as_secs_f64());

        let t = Instant::now();
        lu.factorize(full.val(), DEFAULT_PIVOT_TOLERANCE)
            .expect("K is SPD: no pivot breaks down");
        let mut x = rhs.clone();
        lu.solve_in_place(&mut x);
        lu_times.push(t.elapsed().as_secs_f64());

        let t = Instant::now();
        solver.residual_at(&start).expect("evaluation");
        evaluation.push(t.elapsed().as_secs_f64());
    }
    let cholesky_fill = llt.factor_nnz();

    let (it, ch, lu, ev) = (
        median(iteration),
        median(cholesky),
        median(lu_times),
        median(evaluation),
    );
    println!(
        "{case}: {} dofs, {} points, Cholesky fill {cholesky_fill}, LU fill {fill}; medians of {repeats}: newton iteration \
         {:.2} ms, cholesky {:.2} ms, lu on K {:.2} ms, evaluation {:.2} ms",
        full.nrows(),
        asm.n_points(),
        it * 1e3,
        ch * 1e3,
        lu * 1e3,
        ev * 1e3
    );
    println!(
        "ratio {case}: newton iteration / cholesky {:.2}, lu on K / cholesky {:.2}",
        it / ch,
        lu / ch
    );
}

/// `M + h² Σ Bᵢᵀ Sᵢ⁻¹ Bᵢ` on the pattern of the Newton matrix (lower triangle if `lower`).
fn elastic_matrix(
    model: &Model,
    compliance: &[SMatrix<f64, 4, 4>],
    h: f64,
    lower: bool,
) -> SparseColMat<usize, f64> {
    let asm = &model.assembly;
    let n = asm.lumped_mass_free.len();
    // Bᵀ in CSC: column 4i + k holds row k of point i.
    let bt = asm.b_free.as_ref().transpose().to_col_major().expect("Bᵀ");
    let (cp, ri, v) = (bt.symbolic().col_ptr(), bt.symbolic().row_idx(), bt.val());
    let mut triplets: Vec<Triplet<usize, usize, f64>> = asm
        .lumped_mass_free
        .iter()
        .enumerate()
        .map(|(j, m)| Triplet::new(j, j, *m))
        .collect();
    for (i, s) in compliance.iter().enumerate() {
        let c = s.try_inverse().expect("S invertible") * (h * h);
        let mut dofs: Vec<usize> = (4 * i..4 * i + 4)
            .flat_map(|col| ri[cp[col]..cp[col + 1]].iter().copied())
            .collect();
        dofs.sort_unstable();
        dofs.dedup();
        let m = dofs.len();
        let mut b = vec![0.0; 4 * m];
        for k in 0..4 {
            for e in cp[4 * i + k]..cp[4 * i + k + 1] {
                let a = dofs.binary_search(&ri[e]).expect("dof");
                b[k * m + a] = v[e];
            }
        }
        for a in 0..m {
            let ca = c * SVector::<f64, 4>::from_fn(|k, _| b[k * m + a]);
            for (bb, &col) in dofs.iter().enumerate() {
                if lower && dofs[a] < col {
                    continue;
                }
                let val: f64 = (0..4).map(|k| ca[k] * b[k * m + bb]).sum();
                triplets.push(Triplet::new(dofs[a], col, val));
            }
        }
    }
    SparseColMat::try_new_from_triplets(n, n, &triplets).expect("K")
}
