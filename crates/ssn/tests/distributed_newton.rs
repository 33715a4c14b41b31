//! The Newton solve over MPI ranks (`LinearSolver::Distributed`, `docs/distributed.md`)
//! against one process' own factorization, on a small plane-strain footing pushed into
//! plasticity: each rank evaluates and linearizes its own points, `K` is factorized by
//! MUMPS over the ranks. Outside `mpirun` this program relaunches itself under `mpirun -np
//! 1`, `-np 2` and `-np 3` (3 ranks: uneven velocity slices, a rank owning few points) and
//! fails if any fails.
//!
//! Checked on every rank, at every step: the σ of the distributed solve within 1e-10 (of
//! its largest entry) of the one-process solve from the same state (two independent linear
//! solvers), the same iteration count within one, and every rank holding the same bits of σ and z
//! after the solve (the final all-gather, and the rank-order reductions that keep the
//! ranks' decisions alike). The elastic predictor likewise. With MUMPS on rank 0 alone
//! (`FactorRanks::Host`), a second solver of the same problem repeats every step's σ bit
//! for bit (`docs/distributed.md`, 'Reproducibility').
use std::process::ExitCode;

use mpi::traits::CommunicatorCollectives;

#[path = "common/footing_like.rs"]
mod footing_like;

use footing_like::{FootingLike, D};
use talus_ssn::{FactorRanks, LinearSolver, Settings, Solver};

/// The largest difference over the largest magnitude of `a`.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// A hash of the bits of `v`.
fn bits(v: &[f64]) -> u64 {
    v.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, x| {
        (h ^ x.to_bits()).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Whether every rank holds the same `hash`.
fn same_on_every_rank(world: &impl CommunicatorCollectives, hash: u64) -> bool {
    let mut all = vec![0u64; world.size() as usize];
    world.all_gather_into(&hash, &mut all[..]);
    all.iter().all(|&h| h == all[0])
}

/// Runs the cases on this rank; returns the number of failed checks.
fn under_mpirun(world: &impl CommunicatorCollectives) -> usize {
    let rank = world.rank();
    let mut failures = 0;
    let mut check = |ok: bool, what: String| {
        if !ok {
            eprintln!("rank {rank}: FAILED {what}");
            failures += 1;
        }
    };
    // Non-associative (ψ = 10°: LU, determinant sign) and associative (ψ = φ: LDLᵀ), each
    // factorized over all ranks and on rank 0 alone.
    let cases = [10.0, 30.0].into_iter().flat_map(|dilatancy| {
        [FactorRanks::All, FactorRanks::Host].map(|ranks| (dilatancy, ranks))
    });
    for (dilatancy, ranks) in cases {
        let footing = FootingLike::new(12, 8, dilatancy, 1e-2);
        // A tight tolerance: two converged solves then agree to about 1e-12 of σ.
        let own = Settings {
            tolerance: 1e-13,
            ..Settings::fem()
        };
        let distributed = Settings {
            linear_solver: LinearSolver::Distributed(ranks),
            ..own
        };
        let mut reference = Solver::new(footing.problem.clone(), own).expect("own solver");
        let mut solver = Solver::new(footing.problem.clone(), distributed).expect("MUMPS solver");
        // On rank 0 alone: a second solver, which must repeat the first's bits.
        let mut again = (ranks == FactorRanks::Host).then(|| {
            Solver::new(footing.problem.clone(), distributed).expect("second MUMPS solver")
        });
        let n = D * footing.problem.n_points();

        // The elastic predictor from rest.
        let q = footing.q(&vec![0.0; n], 0.05);
        reference.set_q(q.clone()).expect("q");
        solver.set_q(q).expect("q");
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        reference.elastic_predictor(&mut a).expect("own predictor");
        solver
            .elastic_predictor(&mut b)
            .expect("distributed predictor");
        let d = relative_difference(&a, &b);
        check(
            d <= 1e-10,
            format!("ψ = {dilatancy}: predictor differs by {d:e}"),
        );
        check(
            same_on_every_rank(world, bits(&b)),
            format!("ψ = {dilatancy}: predictor's σ differs between ranks"),
        );

        // Steps, each from the distributed run's state (so that both solve one problem).
        let mut sigma = vec![0.0; n];
        let (mut plastic_iterations, mut worst) = (0, 0.0f64);
        for step in 0..12 {
            let q = footing.q(&sigma, 0.05);
            reference.set_q(q.clone()).expect("q");
            solver.set_q(q).expect("q");
            let mut a = sigma.clone();
            let own = reference.solve(&mut a).expect("own solve converges");
            let mut b = sigma.clone();
            let report = solver.solve(&mut b).expect("distributed solve converges");
            if let Some(again) = again.as_mut() {
                let mut c = sigma.clone();
                again.set_q(footing.q(&sigma, 0.05)).expect("q");
                let repeated = again.solve(&mut c).expect("second solve converges");
                check(
                    bits(&c) == bits(&b) && repeated.iterations == report.iterations,
                    format!("ψ = {dilatancy}, step {step}: rank 0's factorization not repeated"),
                );
            }
            let d = relative_difference(&a, &b);
            worst = worst.max(d);
            check(
                d <= 1e-10,
                format!("ψ = {dilatancy}, {ranks:?}, step {step}: σ differs by {d:e}"),
            );
            // Within one: the last iteration may land on either side of the tolerance.
            check(
                report.iterations.abs_diff(own.iterations) <= 1,
                format!(
                    "ψ = {dilatancy}, step {step}: {} iterations against {}",
                    report.iterations, own.iterations
                ),
            );
            check(
                same_on_every_rank(world, bits(&b)) && same_on_every_rank(world, bits(solver.z())),
                format!("ψ = {dilatancy}, step {step}: σ or z differs between ranks"),
            );
            plastic_iterations += report.iterations;
            sigma = b;
        }
        if rank == 0 {
            eprintln!(
                "{} ranks, ψ = {dilatancy}, {ranks:?}: {plastic_iterations} iterations in 12 \
                 steps, largest difference {worst:e}",
                world.size()
            );
        }
        // The footing must have yielded for the test to mean anything: elastic steps take
        // one or two iterations.
        check(
            plastic_iterations > 12 * 2,
            format!("ψ = {dilatancy}: only {plastic_iterations} iterations in 12 steps"),
        );
    }
    failures
}

fn main() -> ExitCode {
    if let Some(code) = talus_mumps::relaunch_under_mpirun("distributed_newton", &[1, 2, 3]) {
        return code;
    }
    let universe = mpi::initialize().expect("MPI initializes once");
    if under_mpirun(&universe.world()) == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
