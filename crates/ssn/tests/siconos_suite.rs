//! Every Siconos plasticity problem (Drucker-Prager, non-associative and associative, and
//! von Mises) converges to `‖F‖∞ ≤ 1e-12 · max(1, ‖σ‖∞)` from σ = 0 with ρ chosen by the
//! solver. The residual is recomputed here independently of the solver's code paths:
//! `z = Wσ + q` from the file's entries and eq. 23's projection written out in closed form.
use std::path::PathBuf;

use talus_ssn::siconos::{SiconosModel, SiconosProblem};
use talus_ssn::{reduced_system_from_siconos, Settings, Solver};

fn data(name: &str) -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/siconos-plasticity"
    ))
    .join(name)
}

/// Files and the iterations measured with the default settings (a regression guard: more
/// than two extra iterations means the solver got worse).
const SUITE: &[(&str, usize)] = &[
    ("plasticity_2d_example1.dat", 1),
    ("plasticity_2d_example1_theta0.dat", 1),
    ("plasticity_2d_footing_1.dat", 3),
    ("plasticity_2d_footing_10.dat", 7),
    ("plasticity_2d_footing_100.dat", 10),
    ("plasticity_2d_footing_100_theta0.05.dat", 10),
    ("plasticity_2d_footing_100_theta0.dat", 9),
    ("plasticity_2d_vonmises_example1.dat", 1),
    ("plasticity_2d_vonmises_footing_100.dat", 4),
];

/// Eq. 23 for the cone `‖x_t‖ ≤ η x_0` (axis e_0, apex 0), as printed in the paper.
fn project_cone(x: [f64; 3], eta: f64) -> [f64; 3] {
    let r = (x[1] * x[1] + x[2] * x[2]).sqrt();
    if r <= eta * x[0] {
        x
    } else if eta * r <= -x[0] {
        [0.0; 3]
    } else {
        let s = eta / (1.0 + eta * eta) * (eta + x[0] / r);
        [s * r / eta, s * x[1], s * x[2]]
    }
}

fn project_cylinder(x: [f64; 3], radius: f64) -> [f64; 3] {
    let r = (x[1] * x[1] + x[2] * x[2]).sqrt();
    if r <= radius {
        x
    } else {
        [x[0], x[1] * radius / r, x[2] * radius / r]
    }
}

fn independent_residual(p: &SiconosProblem, sigma: &[f64], rho: &[f64]) -> f64 {
    let n = p.n();
    let z: Vec<f64> = (0..n)
        .map(|i| p.q[i] + (0..n).map(|j| p.matrix_entry(i, j) * sigma[j]).sum::<f64>())
        .collect();
    let mut worst: f64 = 0.0;
    for c in 0..p.n_cones {
        let s = [sigma[3 * c], sigma[3 * c + 1], sigma[3 * c + 2]];
        let zc = [z[3 * c], z[3 * c + 1], z[3 * c + 2]];
        let projected = match &p.model {
            SiconosModel::DruckerPrager { eta, theta } => {
                let y0 = zc[0] + theta[c] * (zc[1] * zc[1] + zc[2] * zc[2]).sqrt();
                let x = [
                    s[0] - rho[c] * y0,
                    s[1] - rho[c] * zc[1],
                    s[2] - rho[c] * zc[2],
                ];
                project_cone(x, eta[c])
            }
            SiconosModel::VonMises { sigma_y } => {
                let x = [
                    s[0] - rho[c] * zc[0],
                    s[1] - rho[c] * zc[1],
                    s[2] - rho[c] * zc[2],
                ];
                project_cylinder(x, sigma_y[c])
            }
        };
        for k in 0..3 {
            worst = worst.max((s[k] - projected[k]).abs());
        }
    }
    worst
}

#[test]
fn siconos_suite_converges_to_1e_12() {
    for &(name, measured) in SUITE {
        let problem = SiconosProblem::from_path(&data(name)).unwrap();
        let system = reduced_system_from_siconos::<3>(&problem).unwrap();
        let mut solver = Solver::new(system, Settings::default()).unwrap();
        let mut sigma = vec![0.0; problem.n()];
        let report = solver
            .solve(&mut sigma)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let scale = sigma.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let residual = independent_residual(&problem, &sigma, solver.residual_rho());
        assert!(
            residual <= 1e-12 * scale,
            "{name}: independent ‖F‖∞ = {residual:e}, scale {scale:e}"
        );
        assert!(
            report.iterations <= measured + 2,
            "{name}: {} iterations, measured {measured}",
            report.iterations
        );
        assert!(sigma.iter().any(|v| *v != 0.0), "{name}: trivial solution");
        // The residual history ends where the report says, below tolerance.
        assert_eq!(report.residual_history.len(), report.iterations + 1);
        assert_eq!(*report.residual_history.last().unwrap(), report.residual);
    }
}

#[test]
fn same_bits_whatever_the_thread_count() {
    let problem = SiconosProblem::from_path(&data("plasticity_2d_footing_100.dat")).unwrap();
    let run = |threads: usize, parallel: bool| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let system = reduced_system_from_siconos::<3>(&problem).unwrap();
            let mut solver = Solver::new(
                system,
                Settings {
                    parallel,
                    ..Settings::default()
                },
            )
            .unwrap();
            let mut sigma = vec![0.0; problem.n()];
            solver.solve(&mut sigma).unwrap();
            sigma.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        })
    };
    let reference = run(1, false);
    for threads in [1, 2, 4] {
        assert_eq!(run(threads, true), reference, "{threads} threads");
    }
}
