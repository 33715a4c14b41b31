//! The round-off floor of the stopping test (docs/solver.md, "The round-off floor"): a
//! tolerance below what floating point allows ends with `Status::RoundOffFloor` and the
//! floor reached, close to an estimate computed here independently of the solver; a
//! tolerance above the floor converges exactly as before.
use std::path::PathBuf;

use nalgebra::{SMatrix, SVector};
use talus_bipotential::FlowRule;
use talus_cone::SecondOrderCone;
use talus_ssn::faer::sparse::{SparseColMat, Triplet};
use talus_ssn::siconos::SiconosProblem;
use talus_ssn::{
    reduced_system_from_siconos, Operator, ReducedSystem, Report, Settings, SolveError, Solver,
    Status, Structured,
};

fn siconos(name: &str) -> SiconosProblem {
    let path = PathBuf::from(format!(
        "{}/../../data/siconos-plasticity/{name}.dat",
        env!("CARGO_MANIFEST_DIR")
    ));
    SiconosProblem::from_path(&path).unwrap()
}

fn solve<const D: usize>(
    problem: ReducedSystem<D>,
    tolerance: f64,
) -> (Report, Vec<f64>, Vec<f64>) {
    let n = problem.operator().size();
    let mut solver = Solver::new(
        problem,
        Settings {
            tolerance,
            ..Settings::default()
        },
    )
    .unwrap();
    let rho = solver.residual_rho().to_vec();
    let mut sigma = vec![0.0; n];
    let report = match solver.solve(&mut sigma) {
        Ok(r) => r,
        Err(SolveError::NotConverged(r)) => panic!("not accepted: {r:?}"),
        Err(e) => panic!("{e}"),
    };
    (report, sigma, rho)
}

/// `ε · max(‖σ‖∞, max_i ρ_i max_{k∈i} Σ_j |W_kj σ_j| + |q_k|)` from the entries of `W`: the
/// first-order rounding error of `z = Wσ + q`, scaled like the stopping test's `F`.
fn independent_floor(
    d: usize,
    entry: impl Fn(usize, usize) -> f64,
    q: &[f64],
    sigma: &[f64],
    rho: &[f64],
) -> f64 {
    let n = q.len();
    let mut worst = sigma.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for k in 0..n {
        let row: f64 = (0..n).map(|j| (entry(k, j) * sigma[j]).abs()).sum::<f64>() + q[k].abs();
        worst = worst.max(rho[k / d] * row);
    }
    f64::EPSILON * worst
}

fn check_floor(report: &Report, tolerance: f64, independent: f64) {
    assert_eq!(report.status, Status::RoundOffFloor, "{report:?}");
    assert!(report.is_accepted() && !report.is_converged());
    let floor = report.round_off_floor.expect("floor recorded");
    assert_eq!(floor.reached, report.residual);
    assert!(floor.reached > tolerance * report.scale);
    // The report's estimate is the same quantity (up to summation order) …
    assert!(
        (floor.estimate - independent).abs() <= 1e-6 * independent,
        "estimate {:e} vs independent {independent:e}",
        floor.estimate
    );
    // … and the floor reached is within a factor 10 of it (measured: 0.16 on footing_10,
    // 1.1 on footing_100, see docs/solver.md).
    assert!(
        floor.reached >= 0.01 * independent && floor.reached <= 10.0 * independent,
        "reached {:e}, independent estimate {independent:e}",
        floor.reached
    );
}

#[test]
fn tiny_tolerance_ends_at_the_floor_on_siconos_footings() {
    for name in ["plasticity_2d_footing_10", "plasticity_2d_footing_100"] {
        let p = siconos(name);
        let (report, sigma, rho) = solve(reduced_system_from_siconos::<3>(&p).unwrap(), 1e-18);
        let independent = independent_floor(3, |i, j| p.matrix_entry(i, j), &p.q, &sigma, &rho);
        check_floor(&report, 1e-18, independent);
        // Not a wandering failure: the floor is reached soon after the tolerance of 1e-12
        // (7 and 10 iterations, docs/solver.md), within the stagnation window and a few more.
        assert!(
            report.iterations <= 14,
            "{name}: {} iterations",
            report.iterations
        );
    }
}

#[test]
fn tolerance_above_the_floor_converges_as_before() {
    // Iteration counts of docs/solver.md's ρ table (per point, factor 10), measured before
    // the floor existed; the stopping test must not stop them early or late.
    for (name, iterations) in [
        ("plasticity_2d_footing_10", 7),
        ("plasticity_2d_footing_100", 10),
        ("plasticity_2d_footing_100_theta0.05", 10),
        ("plasticity_2d_vonmises_footing_100", 4),
    ] {
        let p = siconos(name);
        let (report, _, _) = solve(reduced_system_from_siconos::<3>(&p).unwrap(), 1e-12);
        assert_eq!(report.status, Status::Converged, "{name}");
        assert!(report.round_off_floor.is_none());
        assert_eq!(report.iterations, iterations, "{name}");
        assert!(report.residual <= 1e-12 * report.scale);
    }
}

/// xorshift64*, deterministic.
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

/// A structured `W = S + h² B M⁻¹ Bᵀ` in the quasi-static regime of a time step (h² B M⁻¹ Bᵀ
/// about 1e6 × S), with `q` built from a stress of order 1e5 so that `Wσ + q` cancels
/// like the footing's gravity and internal forces.
fn quasi_static(seed: u64) -> (ReducedSystem<4>, SparseColMat<usize, f64>, Structured<4>) {
    const D: usize = 4;
    let (n_points, n_v) = (40, 30);
    let mut rng = Rng(seed);
    let mut triplets = Vec::new();
    for p in 0..n_points {
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
    let compliance: Vec<SMatrix<f64, D, D>> = (0..n_points)
        .map(|_| {
            let a = SMatrix::<f64, D, D>::from_fn(|_, _| rng.signed());
            (a * a.transpose() * 0.1 + SMatrix::identity() * (0.5 + rng.next())) * 1e-6
        })
        .collect();
    let lumped_mass: Vec<f64> = (0..n_v).map(|_| 0.5 + rng.next()).collect();
    let s = Structured {
        compliance,
        b: b.clone(),
        lumped_mass,
        h: 1.0,
    };
    let axis = SVector::<f64, D>::from_fn(|i, _| if i == 0 { 1.0 } else { 0.0 });
    // σ* strictly inside every cone (x_n = 1e5, ‖x_t‖ ≤ η x_n / 2) and q = −W σ*: σ* is the
    // solution, with z = 0, and `Wσ + q` cancels terms of order ‖W‖ 1e5.
    let mut sigma_star = Vec::with_capacity(D * n_points);
    let rules = (0..n_points)
        .map(|_| {
            let apex = SVector::<f64, D>::from_fn(|_, _| 1e4 * rng.signed());
            let eta = 0.2 + rng.next();
            let cone = SecondOrderCone::try_new(axis, apex, eta).unwrap();
            let t = SVector::<f64, 3>::from_fn(|_, _| rng.signed());
            let t = t * (0.5 * eta * 1e5 * rng.next() / t.norm());
            sigma_star.extend_from_slice(&[
                apex[0] + 1e5,
                apex[1] + t[0],
                apex[2] + t[1],
                apex[3] + t[2],
            ]);
            FlowRule::cone(cone, 0.5 * rng.next())
        })
        .collect();
    let w = dense_w(&s);
    let n = D * n_points;
    let q: Vec<f64> = (0..n)
        .map(|i| -(0..n).map(|j| w[i * n + j] * sigma_star[j]).sum::<f64>())
        .collect();
    let problem = ReducedSystem::try_new(Operator::Structured(s.clone()), q, rules).unwrap();
    (problem, b, s)
}

/// `W` entry by entry, row-major.
fn dense_w(s: &Structured<4>) -> Vec<f64> {
    let n = s.b.nrows();
    let mut w = vec![0.0; n * n];
    for (p, c) in s.compliance.iter().enumerate() {
        for a in 0..4 {
            for b in 0..4 {
                w[(4 * p + a) * n + 4 * p + b] += c[(a, b)];
            }
        }
    }
    let (cp, ri, v) = (
        s.b.symbolic().col_ptr(),
        s.b.symbolic().row_idx(),
        s.b.val(),
    );
    for j in 0..s.b.ncols() {
        for k in cp[j]..cp[j + 1] {
            for l in cp[j]..cp[j + 1] {
                w[ri[k] * n + ri[l]] += s.h * s.h * v[k] * v[l] / s.lumped_mass[j];
            }
        }
    }
    w
}

/// `|S| + h² |B| M⁻¹ |B|ᵀ`, the absolute product as the structured form computes it.
fn dense_abs_w(s: &Structured<4>) -> Vec<f64> {
    let mut t = s.clone();
    t.compliance = s.compliance.iter().map(|c| c.abs()).collect();
    let abs_b: Vec<Triplet<usize, usize, f64>> = {
        let (cp, ri, v) = (
            s.b.symbolic().col_ptr(),
            s.b.symbolic().row_idx(),
            s.b.val(),
        );
        (0..s.b.ncols())
            .flat_map(|j| (cp[j]..cp[j + 1]).map(move |k| Triplet::new(ri[k], j, v[k].abs())))
            .collect()
    };
    t.b = SparseColMat::try_new_from_triplets(s.b.nrows(), s.b.ncols(), &abs_b).unwrap();
    dense_w(&t)
}

#[test]
fn structured_quasi_static_problem_ends_at_its_floor() {
    let (problem, _, s) = quasi_static(7);
    let q = problem.q().to_vec();
    let (report, sigma, rho) = solve(problem, 1e-18);
    let n = q.len();
    let abs_w = dense_abs_w(&s);
    let independent = independent_floor(4, |i, j| abs_w[i * n + j], &q, &sigma, &rho);
    check_floor(&report, 1e-18, independent);
    // The same problem at the default tolerance converges (its floor is below 1e-12).
    let (problem, _, _) = quasi_static(7);
    let (report, _, _) = solve(problem, 1e-12);
    assert_eq!(report.status, Status::Converged);
}
