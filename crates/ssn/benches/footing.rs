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

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use divan::Bencher;
use talus_ssn::siconos::{SiconosModel, SiconosProblem};
use talus_ssn::{reduced_system_from_siconos, Settings, Solver};

const THETA0: &str = "plasticity_2d_footing_100_theta0.dat";
const FOOTING: &str = "plasticity_2d_footing_100.dat";
const VONMISES: &str = "plasticity_2d_vonmises_footing_100.dat";

fn main() {
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

/// The QP data of an associative Drucker-Prager problem in Clarabel's form.
struct Qp {
    p: CscMatrix<f64>,
    q: Vec<f64>,
    a: CscMatrix<f64>,
    b: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
}

fn qp(p: &SiconosProblem) -> Qp {
    let n = p.n();
    let d = p.cone_dimension;
    let eta = match &p.model {
        SiconosModel::DruckerPrager { eta, theta } => {
            assert!(
                theta.iter().all(|&t| t == 0.0),
                "associative problem expected"
            );
            eta.clone()
        }
        other => panic!("Drucker-Prager expected, found {other:?}"),
    };
    // upper triangle of the symmetric part of W, column by column
    let mut colptr = vec![0usize];
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    for j in 0..n {
        for i in 0..=j {
            let v = 0.5 * (p.matrix_entry(i, j) + p.matrix_entry(j, i));
            if v != 0.0 {
                rowval.push(i);
                nzval.push(v);
            }
        }
        colptr.push(rowval.len());
    }
    // A_i = −diag(η_i, 1, 1), b = 0: s_i = (η_i σ_i0, σ_i1, σ_i2)
    let a_diag: Vec<f64> = (0..n)
        .map(|k| if k % d == 0 { -eta[k / d] } else { -1.0 })
        .collect();
    Qp {
        p: CscMatrix::new(n, n, colptr, rowval, nzval),
        q: p.q.clone(),
        a: CscMatrix::new(n, n, (0..=n).collect(), (0..n).collect(), a_diag),
        b: vec![0.0; n],
        cones: vec![SupportedConeT::SecondOrderConeT(d); p.n_cones],
    }
}

fn clarabel_settings(tol: Option<f64>) -> DefaultSettings<f64> {
    let mut b = DefaultSettingsBuilder::default();
    b.verbose(false);
    if let Some(t) = tol {
        b.tol_gap_abs(t)
            .tol_gap_rel(t)
            .tol_feas(t)
            .tol_ktratio(1e-10)
            .max_iter(200);
    }
    b.build().unwrap()
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
