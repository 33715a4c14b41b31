//! `talus_ssn::krylov::Gmres` against a direct solve on nonsymmetric systems.
use talus_ssn::faer::Mat;
use talus_ssn::krylov::{Gmres, GmresError, GmresWorkspace, Verdict};

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

/// A nonsymmetric, non-normal matrix: a convection-diffusion-like band plus random
/// entries, shifted so that it is regular but far from its symmetric part.
fn matrix(n: usize, seed: u64) -> Mat<f64> {
    let mut rng = Rng(seed);
    Mat::from_fn(n, n, |i, j| {
        let band = match j as isize - i as isize {
            0 => 4.0,
            1 => -1.0 - 1.5,
            -1 => -1.0 + 1.5,
            _ => 0.0,
        };
        band + if rng.next() < 0.05 {
            0.5 * rng.signed()
        } else {
            0.0
        }
    })
}

fn product(a: &Mat<f64>, x: &[f64], y: &mut [f64]) {
    for (i, yi) in y.iter_mut().enumerate() {
        *yi = (0..a.ncols()).map(|j| a[(i, j)] * x[j]).sum();
    }
}

fn direct(a: &Mat<f64>, b: &[f64]) -> Vec<f64> {
    let n = b.len();
    let rhs = Mat::from_fn(n, 1, |i, _| b[i]);
    let x = a.partial_piv_lu().solve(&rhs);
    (0..n).map(|i| x[(i, 0)]).collect()
}

fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let d = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    d / b.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

use talus_ssn::faer::linalg::solvers::Solve;

#[test]
fn unpreconditioned_restarted_gmres_matches_the_direct_solve() {
    let n = 120;
    for seed in [3, 17, 99] {
        let a = matrix(n, seed);
        let mut rng = Rng(seed + 1);
        let b: Vec<f64> = (0..n).map(|_| rng.signed()).collect();
        let exact = direct(&a, &b);
        let mut x = vec![0.0; n];
        let gmres = Gmres {
            restart: 15,
            max_iterations: 2000,
            project_after: 0,
        };
        let mut ws = GmresWorkspace::new(n, 15);
        let solved = gmres
            .solve_relative(&mut ws, |x, y| product(&a, x, y), |_| {}, &b, &mut x, 1e-13)
            .expect("converges");
        let err = rel_diff(&x, &exact);
        eprintln!(
            "seed {seed}: {} iterations (restart 15), |x − x*|/|x*| = {err:.1e}",
            solved.iterations
        );
        assert!(solved.iterations > 15, "restarts must be exercised");
        assert!(err < 1e-10, "seed {seed}: {err:e}");
        let mut r = vec![0.0; n];
        product(&a, &x, &mut r);
        let res = r
            .iter()
            .zip(&b)
            .map(|(r, b)| (r - b) * (r - b))
            .sum::<f64>()
            .sqrt();
        let bn = b.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(res <= 1e-13 * bn, "true residual {res:e} above target");
    }
}

/// Preconditioned by the LU of a perturbed matrix (a stale factorization): a few
/// iterations, and the answer of the unperturbed system.
#[test]
fn a_stale_lu_preconditioner_converges_in_few_iterations() {
    let n = 200;
    let a = matrix(n, 5);
    let mut rng = Rng(77);
    let stale = Mat::from_fn(n, n, |i, j| a[(i, j)] * (1.0 + 0.02 * rng.signed()));
    let lu = stale.partial_piv_lu();
    let b: Vec<f64> = (0..n).map(|_| rng.signed()).collect();
    let exact = direct(&a, &b);
    let mut x = vec![0.0; n];
    let gmres = Gmres {
        restart: 20,
        max_iterations: 20,
        project_after: 0,
    };
    let mut ws = GmresWorkspace::new(n, 20);
    let solved = gmres
        .solve_relative(
            &mut ws,
            |x, y| product(&a, x, y),
            |v| {
                let mut m = Mat::from_fn(n, 1, |i, _| v[i]);
                lu.solve_in_place(m.as_mut());
                for (i, vi) in v.iter_mut().enumerate() {
                    *vi = m[(i, 0)];
                }
            },
            &b,
            &mut x,
            1e-14,
        )
        .expect("converges");
    let err = rel_diff(&x, &exact);
    eprintln!(
        "stale LU: {} iterations, error {err:.1e}",
        solved.iterations
    );
    assert!(solved.iterations <= 12, "{} iterations", solved.iterations);
    assert!(err < 1e-11, "{err:e}");
}

/// A cap too small is reported, not accepted; `x` holds the last iterate.
#[test]
fn not_converging_within_the_cap_is_an_error() {
    let n = 120;
    let a = matrix(n, 3);
    let b = vec![1.0; n];
    let mut x = vec![0.0; n];
    let gmres = Gmres {
        restart: 5,
        max_iterations: 7,
        project_after: 0,
    };
    let mut ws = GmresWorkspace::new(n, 5);
    let err = gmres
        .solve_relative(&mut ws, |x, y| product(&a, x, y), |_| {}, &b, &mut x, 1e-12)
        .unwrap_err();
    match err {
        GmresError::NotConverged {
            iterations,
            residual,
            target,
        } => {
            assert_eq!(iterations, 7);
            assert!(residual > target);
        }
        other => panic!("{other:?}"),
    }
}

/// The verdict can tighten the target: GMRES goes on to the smaller residual.
#[test]
fn the_verdict_tightens_the_target() {
    let n = 120;
    let a = matrix(n, 11);
    let b = vec![1.0; n];
    let bn = (n as f64).sqrt();
    let mut x = vec![0.0; n];
    let gmres = Gmres {
        restart: 30,
        max_iterations: 1000,
        project_after: 0,
    };
    let mut ws = GmresWorkspace::new(n, 30);
    let mut asked = 0;
    let solved = gmres
        .solve(
            &mut ws,
            |x, y| product(&a, x, y),
            |_| {},
            &b,
            &mut x,
            1e-3 * bn,
            |_, r| {
                asked += 1;
                let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
                if norm <= 1e-11 * bn {
                    Verdict::Accept
                } else {
                    Verdict::Continue { target: 1e-12 * bn }
                }
            },
        )
        .expect("converges");
    assert!(asked >= 2, "the verdict was asked {asked} times");
    assert!(solved.residual <= 1e-11 * bn);
    assert!(rel_diff(&x, &direct(&a, &b)) < 1e-9);
}

#[test]
fn a_workspace_of_another_size_is_refused() {
    let gmres = Gmres {
        restart: 10,
        max_iterations: 10,
        project_after: 0,
    };
    let mut ws = GmresWorkspace::new(5, 10);
    let mut x = vec![0.0; 6];
    let err = gmres
        .solve_relative(
            &mut ws,
            |x, y| y.copy_from_slice(x),
            |_| {},
            &[1.0; 6],
            &mut x,
            1e-12,
        )
        .unwrap_err();
    assert_eq!(err, GmresError::Settings);
}
