//! One Newton iteration of the paper footing (`scenes/footing.toml`) against one elastic
//! factorization and solve of the same mesh: the ratio of the two medians is the figure of
//! merit (issue 4: target ≤ 1.3), printed by `cargo xtask bench`.
//!
//! Cases (the divan argument): `lu` is the paper's non-associative soil (tan θ = tan φ / 2:
//! sparse LU of the velocity-sized Newton matrix), `llt` the associative variant (θ = φ:
//! sparse Cholesky); `32x14` is the paper mesh (896 P2 triangles), `104x48` a finer one
//! (9984). The state is reached outside the timed region by stepping the scene as `talus
//! run` does: to step 100 on the paper mesh (the force plateau), to step 4 on the finer one
//! (early plastic loading; stepping it to the plateau would take minutes). The solver is
//! then a `Solver` of our own on the same operator, `q` of the next step, and
//! `max_iterations = 1`, no line search.
//!
//! - `newton_iteration`: `solve` from the stepper's starting point σₙ + h σ̇, which returns
//!   `Err(NotConverged)` after exactly one Newton iteration: residual at the start, local
//!   blocks, assembly, numeric factorization and solve of the velocity-sized system, the
//!   check `‖J d + F‖`, residual at the new iterate.
//! - `elastic_solve`: `Solver::elastic_predictor` from σₙ on the same solver: one evaluation
//!   of `z`, the same Schur path with every point elastic (factorization and solve), the
//!   same check. Same factorization kind as the Newton iteration (LU for `lu`).
//! - the parts: `local_evaluation` (`Solver::residual_at`: `z = Wσ + q`, the natural-map
//!   linearization at every Gauss point, `‖F‖∞`), and on the elastic matrix
//!   `K = M + h² Σ Bᵢᵀ Sᵢ⁻¹ Bᵢ` (the pattern of the Newton matrix, assembled here with faer
//!   directly, symbolic analysis outside the timed region) `factorization` (numeric LU or
//!   Cholesky) and `triangular_solve` (one right-hand side).
//!
//! Run with `cargo bench -p talus --bench step` (about 1 minute on 2 cores).

use std::collections::HashMap;
use std::sync::{LazyLock, Mutex};

use divan::Bencher;
use nalgebra::{SMatrix, SVector};
use talus::run::solver_settings;
use talus::scene::{builtin_footing, MeshSpec, Scene};
use talus::simulation::{Model, Stepper};
use talus_ssn::faer::linalg::solvers::Solve;
use talus_ssn::faer::sparse::linalg::solvers::{Llt, Lu, SymbolicLlt, SymbolicLu};
use talus_ssn::faer::sparse::{SparseColMat, Triplet};
use talus_ssn::faer::{Mat, Side};
use talus_ssn::{Operator, ReducedSystem, SolveError, Solver, Structured};

const CASES: [&str; 4] = ["lu 32x14", "llt 32x14", "lu 104x48", "llt 104x48"];

fn main() {
    divan::main();
}

/// What one case needs, built once and shared by the benchmarks.
struct Fixture {
    solver: Solver<4>,
    /// σₙ + h σ̇: where the stepper starts the Newton iteration of the next step.
    start: Vec<f64>,
    /// σₙ: where the stepper applies the elastic predictor.
    sigma_n: Vec<f64>,
    /// `K = M + h² Σ Bᵢᵀ Sᵢ⁻¹ Bᵢ`, full (for LU) or its lower triangle (for Cholesky).
    k: SparseColMat<usize, f64>,
    symbolic: Symbolic,
    rhs: Mat<f64>,
}

enum Symbolic {
    Lu(SymbolicLu<usize>),
    Llt(SymbolicLlt<usize>),
}

static FIXTURES: LazyLock<Mutex<HashMap<&'static str, Fixture>>> =
    LazyLock::new(|| Mutex::new(HashMap::new()));

fn with_fixture<R>(case: &'static str, f: impl FnOnce(&mut Fixture) -> R) -> R {
    let mut map = FIXTURES.lock().unwrap_or_else(|e| e.into_inner());
    let fixture = map.entry(case).or_insert_with(|| fixture(case));
    f(fixture)
}

fn scene(case: &str) -> (Scene, usize) {
    let (kind, cells) = case.split_once(' ').expect("`kind NXxNY`");
    let (nx, ny) = cells.split_once('x').expect("NXxNY");
    let cells = [nx.parse().expect("NX"), ny.parse().expect("NY")];
    let mut scene = builtin_footing();
    if let MeshSpec::Rectangle {
        cells: c, ratio, ..
    } = &mut scene.spec.mesh
    {
        *c = cells;
        // The paper's grading, 1.1 per cell over 14 cells, at any size.
        ratio[1] = 1.1f64.powf(14.0 / cells[1] as f64);
    }
    if kind == "llt" {
        scene.spec.material.dilatancy_angle = Some(scene.spec.material.friction_angle);
    }
    let steps = if cells == [32, 14] { 100 } else { 4 };
    (scene, steps)
}

fn fixture(case: &'static str) -> Fixture {
    let (scene, steps) = scene(case);
    let model = Model::from_scene(&scene).expect("model");
    let asm = &model.assembly;
    let h = scene.spec.time.step;
    let mut state = model.initial_state(&scene).expect("K0 state");
    let settings = solver_settings(&scene);
    let mut stepper = Stepper::new(&model, settings, scene.spec.solver.max_step_halvings);
    let mut previous = state.sigma.clone();
    for _ in 0..steps {
        previous.clone_from(&state.sigma);
        stepper.advance(&mut state, h).expect("step converges");
    }
    drop(stepper);

    // The operator and q of the next step, as `Stepper` builds them.
    let compliance = asm.compliance_blocks(&model.compliance);
    let operator = Operator::Structured(Structured {
        compliance: compliance.clone(),
        b: asm.b_free.clone(),
        lumped_mass: asm.lumped_mass_free.clone(),
        h,
    });
    let rules = vec![model.flow_rule; asm.n_points()];
    let system = ReducedSystem::try_new(operator, model.reduced_rhs(&state, h), rules).expect("W");
    let mut one = settings;
    one.max_iterations = 1;
    one.line_search = None;
    let solver = Solver::new(system, one).expect("solver");
    let start: Vec<f64> = state
        .sigma
        .iter()
        .zip(&previous)
        .map(|(s, p)| s + (s - p))
        .collect();

    let symmetric = case.starts_with("llt");
    let k = elastic_matrix(&model, &compliance, h, symmetric);
    let symbolic = if symmetric {
        Symbolic::Llt(SymbolicLlt::try_new(k.symbolic(), Side::Lower).expect("symbolic"))
    } else {
        Symbolic::Lu(SymbolicLu::try_new(k.symbolic()).expect("symbolic"))
    };
    let rhs = Mat::from_fn(k.nrows(), 1, |i, _| 1.0 + (i % 7) as f64);
    let mut fixture = Fixture {
        solver,
        start,
        sigma_n: state.sigma.clone(),
        k,
        symbolic,
        rhs,
    };
    // One Newton iteration exactly, through the velocity-sized system.
    match fixture.solver.solve(&mut fixture.start.clone()) {
        Err(SolveError::NotConverged(r)) => {
            assert_eq!((r.iterations, r.schur_steps), (1, 1), "{case}: {r:?}")
        }
        other => panic!("{case}: expected one iteration, got {other:?}"),
    }
    fixture
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

/// One Newton iteration (see the module doc); the figure of merit's numerator.
#[divan::bench(args = CASES, sample_count = 30, sample_size = 1, max_time = 4)]
fn newton_iteration(bencher: Bencher, case: &'static str) {
    with_fixture(case, |fx| {
        let Fixture { solver, start, .. } = fx;
        bencher
            .with_inputs(|| start.clone())
            .bench_local_refs(|sigma| solver.solve(sigma))
    });
}

/// One elastic factorization and solve on the same solver (the elastic predictor).
#[divan::bench(args = CASES, sample_count = 30, sample_size = 1, max_time = 4)]
fn elastic_solve(bencher: Bencher, case: &'static str) {
    with_fixture(case, |fx| {
        let Fixture {
            solver, sigma_n, ..
        } = fx;
        bencher
            .with_inputs(|| sigma_n.clone())
            .bench_local_refs(|sigma| solver.elastic_predictor(sigma))
    });
}

/// `z = Wσ + q`, the linearization at every point and `‖F‖∞` at the Newton start.
#[divan::bench(args = CASES, sample_count = 30, sample_size = 1, max_time = 3)]
fn local_evaluation(bencher: Bencher, case: &'static str) {
    with_fixture(case, |fx| {
        let Fixture { solver, start, .. } = fx;
        bencher.bench_local(|| solver.residual_at(start))
    });
}

/// Numeric LU or Cholesky of the elastic matrix (symbolic analysis done once, untimed).
#[divan::bench(args = CASES, sample_count = 30, sample_size = 1, max_time = 3)]
fn factorization(bencher: Bencher, case: &'static str) {
    with_fixture(case, |fx| {
        let k = fx.k.as_ref();
        match &fx.symbolic {
            Symbolic::Lu(s) => bencher.bench_local(|| {
                Lu::try_new_with_symbolic(s.clone(), k).expect("LU");
            }),
            Symbolic::Llt(s) => bencher.bench_local(|| {
                Llt::try_new_with_symbolic(s.clone(), k, Side::Lower).expect("LLT");
            }),
        }
    });
}

/// Forward and back substitution with the factors of `factorization`, one right-hand side.
#[divan::bench(args = CASES, sample_count = 30, sample_size = 1, max_time = 3)]
fn triangular_solve(bencher: Bencher, case: &'static str) {
    with_fixture(case, |fx| {
        let k = fx.k.as_ref();
        let rhs = &fx.rhs;
        match &fx.symbolic {
            Symbolic::Lu(s) => {
                let lu = Lu::try_new_with_symbolic(s.clone(), k).expect("LU");
                bencher
                    .with_inputs(|| rhs.clone())
                    .bench_local_refs(|x| lu.solve_in_place(x.as_mut()));
            }
            Symbolic::Llt(s) => {
                let llt = Llt::try_new_with_symbolic(s.clone(), k, Side::Lower).expect("LLT");
                bencher
                    .with_inputs(|| rhs.clone())
                    .bench_local_refs(|x| llt.solve_in_place(x.as_mut()));
            }
        }
    });
}
