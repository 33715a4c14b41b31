//! `Solver::replace_problem`: a solver that keeps its Schur analysis for a new problem on
//! the same `B` pattern gives the same σ, bit for bit, as a solver built afresh for that
//! problem; a changed pattern, a changed number of velocities or a change of symmetry is
//! detected and the solver rebuilt.
use nalgebra::{SMatrix, SVector};
use talus_bipotential::FlowRule;
use talus_cone::SecondOrderCone;
use talus_ssn::faer::sparse::{SparseColMat, Triplet};
use talus_ssn::{Operator, ReducedSystem, Report, Settings, SolveError, Solver, Structured};

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
const POINTS: usize = 40;

/// How the pattern of `B` is laid out.
#[derive(Clone, Copy)]
struct Pattern {
    velocities: usize,
    /// Point 0 touches one more velocity column than the others.
    extra_entry: bool,
}

const BASE: Pattern = Pattern {
    velocities: 30,
    extra_entry: false,
};

/// A structured problem whose `B` pattern depends on `pattern` only and whose values
/// (B, compliance, masses, h, q, cones) on `seed`. Some entries of `B` are stored zeros,
/// as the MPM's stuck friction velocities are.
fn problem(seed: u64, pattern: Pattern, associative: bool) -> ReducedSystem<D> {
    let mut rng = Rng(seed);
    let n_v = pattern.velocities;
    let mut triplets = Vec::new();
    for p in 0..POINTS {
        let first = (p * 5) % (n_v - 7);
        let width = if pattern.extra_entry && p == 0 { 7 } else { 6 };
        for r in 0..D {
            for c in first..first + width {
                let v = if (p + c) % 7 == 0 { 0.0 } else { rng.signed() };
                triplets.push(Triplet::new(D * p + r, c, v));
            }
        }
    }
    let b = SparseColMat::try_new_from_triplets(D * POINTS, n_v, &triplets).unwrap();
    let compliance = (0..POINTS)
        .map(|_| {
            let a = SMatrix::<f64, D, D>::from_fn(|_, _| rng.signed());
            (a * a.transpose() * 0.1 + SMatrix::identity() * (0.5 + rng.next())) * 0.5
        })
        .collect();
    let lumped_mass = (0..n_v).map(|_| 0.5 + rng.next()).collect();
    let op = Operator::Structured(Structured {
        compliance,
        b,
        lumped_mass,
        h: 0.2 + 0.2 * rng.next(),
    });
    let axis = SVector::<f64, D>::from_fn(|i, _| if i == 0 { 1.0 } else { 0.0 });
    let rules = (0..POINTS)
        .map(|_| {
            let cone = SecondOrderCone::try_new(axis, SVector::zeros(), 0.3 + rng.next()).unwrap();
            FlowRule::cone(cone, if associative { 0.0 } else { 0.2 * rng.next() })
        })
        .collect();
    let q: Vec<f64> = (0..D * POINTS).map(|_| 2.0 * rng.signed()).collect();
    ReducedSystem::try_new(op, q, rules).unwrap()
}

fn settings() -> Settings {
    Settings {
        max_iterations: 40,
        ..Settings::default()
    }
}

/// Solves from σ = 0.01 (a fixed start); the report whether or not it converged.
fn solve(solver: &mut Solver<D>) -> (Vec<f64>, Report) {
    let mut sigma = vec![0.01; D * POINTS];
    let report = match solver.solve(&mut sigma) {
        Ok(r) => r,
        Err(SolveError::NotConverged(r)) => *r,
        Err(e) => panic!("{e}"),
    };
    (sigma, report)
}

/// Solves `first`, replaces it by `second` and solves again; compares with a fresh solver
/// on `second`. Returns whether the analysis was reused and whether the solve converged.
fn reuse_then_compare(first: ReducedSystem<D>, second: ReducedSystem<D>) -> (bool, bool) {
    let mut reused = Solver::new(first, settings()).unwrap();
    let _ = solve(&mut reused);
    let kept = reused.replace_problem(second.clone()).unwrap();
    let (a, report_a) = solve(&mut reused);
    let mut fresh = Solver::new(second, settings()).unwrap();
    let (b, report_b) = solve(&mut fresh);
    assert_eq!(
        reused.rho(),
        fresh.rho(),
        "ρ must be chosen for the new problem"
    );
    assert_eq!(report_a.iterations, report_b.iterations);
    assert_eq!(report_a.residual_history, report_b.residual_history);
    let differ = a
        .iter()
        .zip(&b)
        .position(|(x, y)| x.to_bits() != y.to_bits());
    assert!(
        differ.is_none(),
        "reused and fresh solvers differ at σ[{}]: {:e} vs {:e}",
        differ.unwrap(),
        a[differ.unwrap()],
        b[differ.unwrap()]
    );
    (kept, report_b.is_converged())
}

#[test]
fn same_pattern_reuses_the_analysis_and_gives_the_same_sigma_bit_for_bit() {
    for associative in [true, false] {
        let mut converged = 0;
        for seed in 1..=6u64 {
            let (kept, ok) = reuse_then_compare(
                problem(seed, BASE, associative),
                problem(seed + 100, BASE, associative),
            );
            assert!(kept, "seed {seed}: same pattern, the analysis must be kept");
            converged += ok as usize;
        }
        // The comparison must be between solutions, not only between iterates.
        assert!(converged >= 4, "only {converged}/6 solves converged");
    }
}

#[test]
fn changed_pattern_size_or_symmetry_is_detected_and_rebuilt() {
    let extra = Pattern {
        extra_entry: true,
        ..BASE
    };
    let wider = Pattern {
        velocities: 31,
        ..BASE
    };
    for (what, first, second) in [
        (
            "extra entry",
            problem(1, BASE, false),
            problem(2, extra, false),
        ),
        (
            "one more velocity",
            problem(1, BASE, false),
            problem(2, wider, false),
        ),
        (
            "associative to not",
            problem(1, BASE, true),
            problem(2, BASE, false),
        ),
        (
            "not to associative",
            problem(1, BASE, false),
            problem(2, BASE, true),
        ),
    ] {
        let (kept, _) = reuse_then_compare(first, second);
        assert!(!kept, "{what}: the analysis must be rebuilt");
    }
}

#[test]
fn replacing_keeps_working_over_several_problems() {
    // A chain of replacements on one pattern (friction passes, then steps at rest).
    let mut solver = Solver::new(problem(7, BASE, false), settings()).unwrap();
    for seed in 8..12u64 {
        let next = problem(seed, BASE, false);
        assert!(solver.replace_problem(next.clone()).unwrap());
        let (a, _) = solve(&mut solver);
        let (b, _) = solve(&mut Solver::new(next, settings()).unwrap());
        assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()));
    }
}
