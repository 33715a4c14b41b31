//! GMRES (`talus_ssn::krylov`) and the Krylov-reuse Newton solve (`NewtonSolve::Krylov`,
//! `docs/krylov.md`): the same solutions as the direct path, fewer factorizations, and a
//! refactorization when the reused factorization is a bad preconditioner.
use crate::footing_like;

use footing_like::{krylov, solve, FootingLike};
use talus_ssn::{Krylov, NewtonSolve, Settings, Solver};

fn inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Steps of the footing with one solver per path; returns the largest relative difference
/// of σ and the summed reports (factorizations, Krylov solves, iterations).
fn footing_steps(dilatancy: f64, steps: usize, tolerance: f64) -> (f64, [usize; 4], [usize; 2]) {
    let footing = FootingLike::new(16, 12, dilatancy, 1e-2);
    let direct_settings = Settings {
        tolerance,
        ..Settings::fem()
    };
    let krylov_settings = Settings {
        tolerance,
        ..krylov()
    };
    let mut direct = Solver::new(footing.problem.clone(), direct_settings).unwrap();
    let mut reuse = Solver::new(footing.problem.clone(), krylov_settings).unwrap();
    let n = footing.problem.operator().size();
    let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
    let mut worst: f64 = 0.0;
    let (mut counts, mut its) = ([0usize; 4], [0usize; 2]);
    for step in 0..steps {
        direct.set_q(footing.q(&a, 0.05)).unwrap();
        reuse.set_q(footing.q(&b, 0.05)).unwrap();
        let ra = solve(&mut direct, &mut a);
        let rb = solve(&mut reuse, &mut b);
        assert!(ra.is_accepted() && rb.is_accepted(), "step {step}");
        let diff = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        worst = worst.max(diff / inf(&a).max(1.0));
        counts[0] += ra.factorizations;
        counts[1] += rb.factorizations;
        counts[2] += rb.krylov_solves;
        counts[3] += rb.krylov_iterations;
        its[0] += ra.iterations;
        its[1] += rb.iterations;
        assert_eq!(
            ra.krylov_solves + ra.krylov_iterations,
            0,
            "direct path untouched"
        );
    }
    (worst, counts, its)
}

/// At the FEM tolerance 1e-12 two solutions may differ by the tolerance times the inverse
/// Jacobian's norm (1.5e-11 measured here, as between two orderings of the direct solve,
/// `tests/ordering.rs`); solved to 1e-14 they agree to 1e-12.
#[test]
fn footing_krylov_reuse_matches_direct() {
    for (tolerance, agree) in [(1e-12, 1e-10), (1e-14, 1e-12)] {
        for dilatancy in [30.0, 10.0] {
            let (worst, counts, its) = footing_steps(dilatancy, 6, tolerance);
            eprintln!(
                "tol {tolerance:e}, θ = {dilatancy}: max |Δσ| / ‖σ‖ = {worst:.1e}; factorizations direct {} reuse {}, GMRES solves {} in {} iterations; Newton iterations {} / {}",
                counts[0], counts[1], counts[2], counts[3], its[0], its[1]
            );
            assert!(
                worst <= agree,
                "θ = {dilatancy}: solutions differ by {worst:e}"
            );
            assert!(counts[2] > 0, "θ = {dilatancy}: GMRES never used");
            assert!(
                counts[1] < counts[0],
                "θ = {dilatancy}: no factorization saved"
            );
        }
    }
}

/// A reused factorization of a much softer material's `K` is a bad preconditioner for the
/// stiff one's: GMRES misses its tolerance within the cap, the solver refactorizes, and the
/// answer is still the direct one.
#[test]
fn a_stale_bad_preconditioner_forces_a_refactorization() {
    let soft = FootingLike::with_young_modulus(16, 12, 10.0, 1e-2, 1e5);
    let stiff = FootingLike::with_young_modulus(16, 12, 10.0, 1e-2, 1e7);
    let n = soft.problem.operator().size();
    let mut reuse = Solver::new(soft.problem.clone(), krylov()).unwrap();
    let mut sigma = vec![0.0; n];
    reuse.set_q(soft.q(&sigma, 0.05)).unwrap();
    let first = solve(&mut reuse, &mut sigma);
    assert!(first.factorizations >= 1);
    // Same pattern: the analysis and the last (soft) factorization are kept.
    let mut problem = stiff.problem.clone();
    let zero = vec![0.0; n];
    problem.set_q(stiff.q(&zero, 0.05)).unwrap();
    assert!(reuse.replace_problem(problem.clone()).unwrap());
    let mut b = zero.clone();
    let r = solve(&mut reuse, &mut b);
    let mut direct = Solver::new(problem, Settings::fem()).unwrap();
    let mut a = zero.clone();
    let rd = solve(&mut direct, &mut a);
    eprintln!(
        "stiff after soft: {} Newton its, {} factorizations, {} GMRES solves in {} its, {} failures (direct: {} its)",
        r.iterations, r.factorizations, r.krylov_solves, r.krylov_iterations, r.krylov_failures,
        rd.iterations
    );
    assert!(
        r.krylov_failures >= 1,
        "the stale factorization was accepted: {r:?}"
    );
    assert!(r.factorizations >= 1, "no refactorization: {r:?}");
    // Every failure cost at most the cap of iterations, and was followed by a factorization.
    assert!(
        r.krylov_iterations
            <= r.krylov_solves * Krylov::DEFAULT.max_iterations
                + r.krylov_failures * Krylov::DEFAULT.max_iterations
    );
    let diff = a
        .iter()
        .zip(&b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(diff <= 1e-9 * inf(&a).max(1.0), "differ by {diff:e}");
}

/// The direct path reports one factorization per Newton iteration and no GMRES.
#[test]
fn direct_counts_one_factorization_per_iteration() {
    let footing = FootingLike::new(8, 6, 10.0, 1e-2);
    let n = footing.problem.operator().size();
    let mut direct = Solver::new(footing.problem.clone(), Settings::fem()).unwrap();
    let mut sigma = vec![0.0; n];
    direct.set_q(footing.q(&sigma, 0.05)).unwrap();
    let r = solve(&mut direct, &mut sigma);
    assert_eq!(r.factorizations, r.iterations + r.pivoting_fallbacks);
    assert_eq!(
        (r.krylov_solves, r.krylov_iterations, r.krylov_failures),
        (0, 0, 0)
    );
}

/// Out-of-range Krylov settings are refused by `Solver::new`.
#[test]
fn invalid_krylov_settings_are_refused() {
    let footing = FootingLike::new(4, 4, 10.0, 1e-2);
    for k in [
        Krylov {
            restart: 0,
            ..Krylov::DEFAULT
        },
        Krylov {
            max_iterations: 0,
            ..Krylov::DEFAULT
        },
        Krylov {
            forcing: talus_ssn::Forcing::Fixed(0.5),
            ..Krylov::DEFAULT
        },
    ] {
        let settings = Settings {
            newton_solve: NewtonSolve::Krylov(k),
            ..Settings::fem()
        };
        assert!(
            Solver::new(footing.problem.clone(), settings).is_err(),
            "{k:?} accepted"
        );
    }
}

/// Six load steps of the associative 16×12 footing by a direct solver and by one with
/// `settings`, each kept across the steps: σ equal to 1e-10 relative at every step. Both
/// solvers, and the second's summed counts `[iterations, factorizations, GMRES
/// iterations, GMRES directions, GMRES failures]`.
fn single_against_direct(settings: Settings) -> (Solver<4>, Solver<4>, [usize; 5]) {
    let footing = FootingLike::new(16, 12, 30.0, 1e-2);
    let n = footing.problem.operator().size();
    let mut direct = Solver::new(footing.problem.clone(), Settings::fem()).unwrap();
    let mut other = Solver::new(footing.problem.clone(), settings).unwrap();
    let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
    let mut counts = [0; 5];
    for step in 0..6 {
        direct.set_q(footing.q(&a, 0.05)).unwrap();
        other.set_q(footing.q(&b, 0.05)).unwrap();
        let ra = solve(&mut direct, &mut a);
        let rb = solve(&mut other, &mut b);
        assert!(ra.is_converged() && rb.is_converged(), "step {step}");
        let diff = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(diff <= 1e-10 * inf(&a).max(1.0), "step {step}: {diff:e}");
        let step_counts = [
            rb.iterations,
            rb.factorizations,
            rb.krylov_iterations,
            rb.krylov_solves,
            rb.krylov_failures,
        ];
        for (c, s) in counts.iter_mut().zip(step_counts) {
            *c += s;
        }
    }
    (direct, other, counts)
}

fn single(reuse: bool) -> Settings {
    Settings {
        newton_solve: NewtonSolve::Krylov(Krylov {
            precision: talus_ssn::Precision::Single,
            reuse,
            ..Krylov::DEFAULT
        }),
        ..Settings::fem()
    }
}

/// `Precision::Single`: the associative footing's Cholesky factor stored in f32 (half the
/// bytes), every direction from GMRES, the same solutions; refused for non-associative
/// flow (its LU has no f32 version).
#[test]
fn single_precision_factor_matches_direct() {
    let (direct, reuse, [its, _, gmres, solves, _]) = single_against_direct(single(true));
    let (f64_bytes, _) = direct.factor_memory().unwrap();
    let (f32_bytes, _) = reuse.factor_memory().unwrap();
    eprintln!(
        "f32 factor: {f32_bytes} bytes against {f64_bytes}; {its} Newton its, {solves} GMRES directions in {gmres} its"
    );
    // 4 bytes per stored entry of the same supernodal factor and no f64 storage beside
    // them: no f64 fallback was needed.
    assert_eq!(reuse.factor_nnz(), direct.factor_nnz());
    assert_eq!(
        f32_bytes,
        4 * reuse.factor_nnz().unwrap(),
        "an f64 fallback was needed"
    );
    assert_eq!(solves, its, "every direction from GMRES");
    let lu = FootingLike::new(8, 6, 10.0, 1e-2);
    assert!(Solver::new(lu.problem.clone(), single(true)).is_err());
}

/// `reuse: false` with `Precision::Single` (iterative refinement by GMRES on a fresh f32
/// factor, Carson & Higham 2018): one factorization per Newton iteration, no GMRES
/// failure, every direction from GMRES in a few iterations, the direct solutions.
#[test]
fn a_fresh_single_precision_factor_every_iteration_matches_direct() {
    let (_, _, [its, factorizations, gmres, solves, failures]) =
        single_against_direct(single(false));
    eprintln!("{its} Newton its, {factorizations} factorizations, {gmres} GMRES its");
    assert_eq!(failures, 0, "a GMRES failure");
    assert_eq!(
        factorizations, its,
        "one factorization per Newton iteration"
    );
    assert_eq!(solves, its, "every direction from GMRES");
    assert!(
        gmres <= 4 * its,
        "{gmres} GMRES iterations for {its} directions"
    );
}
