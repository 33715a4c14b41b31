//! Siconos footing problems (300×300 dense W, 100 cones): talus-ssn vs Clarabel.
//!
//! Each file is read once, outside the timed closures. The ssn benchmarks build the
//! `Solver` inside the timed closure (ρ choice and Newton-system analysis count) and solve
//! from σ = 0 at the default tolerance 1e-12. Clarabel solves the associative problem
//! `footing_100_theta0` as the QP `min ½σᵀWσ + qᵀσ, (η_i σ_i0, σ_i1, σ_i2) ∈ SOC`, setup
//! (equilibration, KKT factorization) included, at its default tolerances (1e-8) and at 1e-12.
//!
//! Run with `cargo bench -p talus-ssn --bench footing`.

use std::path::PathBuf;

use clarabel::solver::{DefaultSolver, IPSolver, SolverStatus};
use divan::Bencher;
use talus_ssn::siconos::SiconosProblem;
use talus_ssn::{reduced_system_from_siconos, Settings, Solver};

const THETA0: &str = "plasticity_2d_footing_100_theta0.dat";
const FOOTING: &str = "plasticity_2d_footing_100.dat";
const VONMISES: &str = "plasticity_2d_vonmises_footing_100.dat";

#[path = "../tests/common/clarabel_qp.rs"]
mod clarabel_qp;
use clarabel_qp::{clarabel_settings, qp};

/// On a worker of rayon's pool, as `talus run` solves (`talus_ssn::on_pool`).
fn main() {
    talus_ssn::on_pool(bench);
}

fn bench() {
    divan::main();
}

fn load(name: &str) -> SiconosProblem {
    let path = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/siconos-plasticity/"
    ))
    .join(name);
    SiconosProblem::from_path(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// ssn from σ = 0 at default settings (tolerance 1e-12); Solver::new is timed.
#[divan::bench(args = [THETA0, FOOTING, VONMISES], sample_count = 40, sample_size = 1)]
fn ssn(bencher: Bencher, file: &str) {
    let p = load(file);
    let system = reduced_system_from_siconos::<3>(&p).unwrap();
    let n = p.n();
    bencher
        .with_inputs(|| (system.clone(), vec![0.0; n]))
        .bench_local_values(|(system, mut sigma)| {
            let mut solver = Solver::new(system, Settings::default()).unwrap();
            let report = solver
                .solve(&mut sigma)
                .unwrap_or_else(|e| panic!("{file}: {e}"));
            (solver, sigma, report)
        });
}

fn bench_clarabel(bencher: Bencher, tol: Option<f64>) {
    let data = qp(&load(THETA0));
    let settings = clarabel_settings(tol);
    bencher
        .with_inputs(|| settings.clone())
        .bench_local_values(|settings| {
            let mut solver =
                DefaultSolver::new(&data.p, &data.q, &data.a, &data.b, &data.cones, settings)
                    .unwrap();
            solver.solve();
            assert_eq!(solver.solution.status, SolverStatus::Solved);
            solver
        });
}

/// Clarabel on footing_100_theta0 at its default tolerances (1e-8).
#[divan::bench(sample_count = 40, sample_size = 1)]
fn clarabel_theta0_tol_1e8(bencher: Bencher) {
    bench_clarabel(bencher, None);
}

/// Clarabel on footing_100_theta0 at tol_gap_abs = tol_gap_rel = tol_feas = 1e-12.
#[divan::bench(sample_count = 40, sample_size = 1)]
fn clarabel_theta0_tol_1e12(bencher: Bencher) {
    bench_clarabel(bencher, Some(1e-12));
}
