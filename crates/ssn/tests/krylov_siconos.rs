//! `NewtonSolve::Krylov` on the Siconos suite (dense `W`: GMRES on the stress-sized
//! `J_F`, preconditioned by the LU of an earlier iteration's `J_F`): the same solutions as
//! the direct solve, each checked against an independent residual.
use std::path::PathBuf;

use talus_ssn::siconos::SiconosProblem;
use talus_ssn::{reduced_system_from_siconos, Krylov, NewtonSolve, Settings, Solver};

fn data(name: &str) -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/siconos-plasticity"
    ))
    .join(name)
}

/// The files of `siconos_suite.rs`.
const SUITE: &[&str] = &[
    "plasticity_2d_example1.dat",
    "plasticity_2d_example1_theta0.dat",
    "plasticity_2d_footing_1.dat",
    "plasticity_2d_footing_10.dat",
    "plasticity_2d_footing_100.dat",
    "plasticity_2d_footing_100_theta0.05.dat",
    "plasticity_2d_footing_100_theta0.dat",
    "plasticity_2d_vonmises_example1.dat",
    "plasticity_2d_vonmises_footing_100.dat",
];

#[test]
fn krylov_reuse_matches_direct_on_the_siconos_suite() {
    let krylov = Settings {
        newton_solve: NewtonSolve::Krylov(Krylov::DEFAULT),
        ..Settings::default()
    };
    let (mut reused, mut saved) = (0, 0);
    for name in SUITE {
        let problem = SiconosProblem::from_path(&data(name)).unwrap();
        let run = |settings: Settings| {
            let system = reduced_system_from_siconos::<3>(&problem).unwrap();
            let mut solver = Solver::new(system, settings).unwrap();
            let mut sigma = vec![0.0; problem.n()];
            let report = solver
                .solve(&mut sigma)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            (sigma, report)
        };
        let (a, ra) = run(Settings::default());
        let (b, rb) = run(krylov);
        assert!(ra.is_converged() && rb.is_converged(), "{name}");
        let scale = a.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let diff = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        eprintln!(
            "{name}: Newton its {} / {}, factorizations {} / {}, GMRES solves {} in {} its ({} failed), |Δσ|/‖σ‖ = {:.1e}",
            ra.iterations, rb.iterations, ra.factorizations, rb.factorizations,
            rb.krylov_solves, rb.krylov_iterations, rb.krylov_failures, diff / scale
        );
        // Both meet ‖F‖∞ ≤ 1e-12 · scale; their difference is that times the inverse
        // Jacobian's norm, measured below 1e-10 on this suite.
        assert!(diff <= 1e-9 * scale, "{name}: differ by {:e}", diff / scale);
        // Every direction is a factorization's or a reuse's (a failed GMRES attempt is
        // followed by the factorization that gives the direction).
        assert_eq!(
            rb.factorizations + rb.krylov_solves,
            rb.iterations,
            "{name}"
        );
        assert_eq!(ra.factorizations, ra.iterations, "{name}");
        reused += rb.krylov_solves;
        saved += ra.factorizations - rb.factorizations;
    }
    assert!(
        reused > 0 && saved > 0,
        "GMRES never used ({reused}) or nothing saved ({saved})"
    );
}
