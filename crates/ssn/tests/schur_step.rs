//! The velocity-sized Schur-complement Newton step (`docs/derivations.md`, 'The Schur step')
//! equals the stress-sized step `J_F d = −F` on random structured problems, associative
//! (Cholesky) and not (LU).
use nalgebra::{SMatrix, SVector};
use talus_bipotential::FlowRule;
use talus_cone::SecondOrderCone;
use talus_ssn::faer::sparse::{SparseColMat, Triplet};
use talus_ssn::{
    LinearSolver, Operator, ReducedSystem, Report, Settings, SolveError, Solver, Status, Structured,
};

/// Tiny deterministic generator (no dependency): xorshift64*.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn signed(&mut self) -> f64 {
        2.0 * self.next() - 1.0
    }
}

const D: usize = 4;

fn random_problem(seed: u64, associative: bool) -> (ReducedSystem<D>, Vec<f64>) {
    sized_random_problem(seed, associative, 30, 24)
}

fn sized_random_problem(
    seed: u64,
    associative: bool,
    n_points: usize,
    n_v: usize,
) -> (ReducedSystem<D>, Vec<f64>) {
    massed_random_problem(seed, associative, n_points, n_v, 1.0)
}

/// As [`sized_random_problem`] with the lumped masses scaled by `mass`.
fn massed_random_problem(
    seed: u64,
    associative: bool,
    n_points: usize,
    n_v: usize,
    mass: f64,
) -> (ReducedSystem<D>, Vec<f64>) {
    let mut rng = Rng(seed);
    let mut triplets = Vec::new();
    for p in 0..n_points {
        // Each point touches 6 velocity columns, like a linear triangle in 2D.
        let first = (p * 5) % (n_v - 6);
        for r in 0..D {
            for c in first..first + 6 {
                if r < 3 || rng.next() < 0.5 {
                    triplets.push(Triplet::new(D * p + r, c, rng.signed()));
                }
            }
        }
    }
    let b = SparseColMat::try_new_from_triplets(D * n_points, n_v, &triplets).unwrap();
    let compliance = (0..n_points)
        .map(|_| {
            let a = SMatrix::<f64, D, D>::from_fn(|_, _| rng.signed());
            a * a.transpose() * 0.1 + SMatrix::identity() * (0.5 + rng.next())
        })
        .collect();
    let lumped_mass = (0..n_v).map(|_| mass * (0.5 + rng.next())).collect();
    let op = Operator::Structured(Structured {
        compliance,
        b,
        lumped_mass,
        h: 0.3,
    });
    let axis = SVector::<f64, D>::from_fn(|i, _| if i == 0 { 1.0 } else { 0.0 });
    let rules = (0..n_points)
        .map(|_| {
            let apex = SVector::<f64, D>::from_fn(|_, _| 0.2 * rng.signed());
            let cone = SecondOrderCone::try_new(axis, apex, 0.2 + rng.next()).unwrap();
            FlowRule::cone(cone, if associative { 0.0 } else { 0.5 * rng.next() })
        })
        .collect();
    let q: Vec<f64> = (0..D * n_points).map(|_| 2.0 * rng.signed()).collect();
    let sigma0: Vec<f64> = (0..D * n_points).map(|_| rng.signed()).collect();
    (ReducedSystem::try_new(op, q, rules).unwrap(), sigma0)
}

/// σ after at most one full Newton step from `sigma0` (none if its direction is refused),
/// and the solve's report.
fn one_step_report(
    problem: ReducedSystem<D>,
    sigma0: &[f64],
    linear_solver: LinearSolver,
) -> (Vec<f64>, Report) {
    let settings = Settings {
        max_iterations: 1,
        line_search: None,
        linear_solver,
        ..Settings::default()
    };
    let mut solver = Solver::new(problem, settings).unwrap();
    let mut sigma = sigma0.to_vec();
    let report = match solver.solve(&mut sigma) {
        Ok(r) => r,
        Err(SolveError::NotConverged(r)) => *r,
        Err(e) => panic!("{e}"),
    };
    (sigma, report)
}

/// σ after exactly one full Newton step from `sigma0`.
fn one_step(
    problem: ReducedSystem<D>,
    sigma0: &[f64],
    linear_solver: LinearSolver,
) -> (Vec<f64>, usize, usize) {
    let (sigma, report) = one_step_report(problem, sigma0, linear_solver);
    assert_eq!(report.iterations, 1);
    (sigma, report.schur_steps, report.stress_sized_steps)
}

fn compare(associative: bool) {
    let mut schur_steps = 0;
    for seed in 1..=20u64 {
        let (problem, sigma0) = random_problem(seed * 7919, associative);
        let (a, schur, _) = one_step(problem.clone(), &sigma0, LinearSolver::Auto);
        let (b, s2, stress) = one_step(problem, &sigma0, LinearSolver::StressSized);
        assert_eq!((s2, stress), (0, 1));
        schur_steps += schur;
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(
            diff <= 1e-12 * scale,
            "seed {seed}: Schur and stress-sized steps differ by {diff:e} (scale {scale:e})"
        );
    }
    assert!(
        schur_steps >= 18,
        "the Schur path must be the one exercised ({schur_steps}/20)"
    );
}

#[test]
fn schur_step_equals_stress_sized_step_associative() {
    compare(true);
}

#[test]
fn schur_step_equals_stress_sized_step_non_associative() {
    compare(false);
}

#[test]
fn structured_and_assembled_operators_give_the_same_solution() {
    for associative in [true, false] {
        let (problem, sigma0) = random_problem(4242, associative);
        let solve = |ls: LinearSolver| {
            let mut solver = Solver::new(
                problem.clone(),
                Settings {
                    linear_solver: ls,
                    ..Settings::default()
                },
            )
            .unwrap();
            let mut s = sigma0.clone();
            solver.solve(&mut s).expect("converges");
            s
        };
        let (a, b) = (solve(LinearSolver::Auto), solve(LinearSolver::StressSized));
        let scale = b.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let diff = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(diff <= 1e-10 * scale, "associative {associative}: {diff:e}");
    }
}

#[test]
fn same_bits_whatever_the_thread_count_on_a_problem_the_pool_splits() {
    // 3000 points, 2400 velocities: the per-point loops (chunks of 256 points at least),
    // the gather of Bᵀσ (1024 velocities) and of the Schur values (4096) are all split.
    let (problem, sigma0) = sized_random_problem(77, false, 3000, 2400);
    let run = |threads: usize, parallel: bool| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let settings = Settings {
                parallel,
                max_iterations: 8,
                ..Settings::default()
            };
            let mut solver = Solver::new(problem.clone(), settings).unwrap();
            let mut s = sigma0.clone();
            let report = match solver.solve(&mut s) {
                Ok(r) => r,
                Err(SolveError::NotConverged(r)) => *r,
                Err(e) => panic!("{e}"),
            };
            assert!(report.iterations >= 2, "the solve must iterate");
            // σ and every merit value: a reduction whose order followed the threads would show
            // in the last bits of the merit even where it does not change σ.
            s.iter()
                .chain(&report.merit_history)
                .map(|v| v.to_bits())
                .collect::<Vec<_>>()
        })
    };
    let reference = run(1, false);
    for threads in [2, 4] {
        assert_eq!(run(threads, true), reference, "{threads} threads");
    }
}

/// The report of one Newton step of a non-associative `massed_random_problem`.
fn first_step_report(seed: u64, mass: f64, linear_solver: LinearSolver) -> Report {
    let (problem, sigma0) = massed_random_problem(seed, false, 30, 24, mass);
    one_step_report(problem, &sigma0, linear_solver).1
}

/// Masses 1e-14 of the stiffness: `M⁻¹` amplifies the velocity solve's round-off into the
/// stresses beyond the accuracy check (`docs/solver.md`, 'The factorization'). For these
/// seeds the no-pivot LU is backward stable, so the direction is refused at once, without
/// building the pivoting LU; the pivoting LU alone fails the same check (the control).
#[test]
fn an_inaccurate_direction_from_a_backward_stable_lu_is_refused_without_pivoting() {
    for seed in [7919, 4 * 7919] {
        let auto = first_step_report(seed, 1e-14, LinearSolver::Auto);
        assert_eq!(auto.status, Status::SingularJacobian, "seed {seed}");
        assert_eq!(
            (
                auto.pivoting_skipped,
                auto.pivoting_fallbacks,
                auto.factorizations
            ),
            (1, 0, 1),
            "seed {seed}: {auto:?}"
        );
        let pivoting = first_step_report(seed, 1e-14, LinearSolver::SchurPivoting);
        assert_eq!(pivoting.status, Status::SingularJacobian, "seed {seed}");
    }
}
