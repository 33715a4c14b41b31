//! The reused-storage Cholesky against the residual `‖A x − b‖` and the no-pivot LU (an
//! independent factorization of the same matrix).
use std::sync::Arc;

use talus_ssn::factorization::{
    SupernodalCholesky, SymbolicSymmetricPatternLu, SymmetricPatternLu, DEFAULT_PIVOT_TOLERANCE,
};
use talus_ssn::faer::sparse::{SparseColMat, Triplet};

/// The 5-point Laplacian of an `nx × ny` grid plus `shift` on the diagonal: SPD for
/// `shift > 0`, indefinite for `shift` below −(smallest eigenvalue). Full or lower triangle.
fn laplacian(nx: usize, ny: usize, shift: f64, lower: bool) -> SparseColMat<usize, f64> {
    let n = nx * ny;
    let mut t = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let a = i + nx * j;
            t.push(Triplet::new(a, a, 4.0 + shift));
            let mut link = |b: usize| {
                t.push(Triplet::new(b.max(a), b.min(a), -1.0));
                if !lower {
                    t.push(Triplet::new(b.min(a), b.max(a), -1.0));
                }
            };
            if i + 1 < nx {
                link(a + 1);
            }
            if j + 1 < ny {
                link(a + nx);
            }
        }
    }
    SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
}

fn residual(a: &SparseColMat<usize, f64>, x: &[f64], b: &[f64]) -> f64 {
    let mut r = b.to_vec();
    for (j, xj) in x.iter().enumerate().take(a.ncols()) {
        for (i, v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
            r[i] -= v * xj;
        }
    }
    r.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

#[test]
fn solves_a_grid_laplacian_like_the_no_pivot_lu() {
    let (lower, full) = (laplacian(40, 30, 0.1, true), laplacian(40, 30, 0.1, false));
    let n = full.nrows();
    let b: Vec<f64> = (0..n).map(|i| 1.0 + (i % 7) as f64).collect();
    let mut cholesky = SupernodalCholesky::try_new(lower.symbolic()).unwrap();
    cholesky.factorize(lower.as_ref()).unwrap();
    let mut x = b.clone();
    cholesky.solve_in_place(&mut x);
    assert!(
        residual(&full, &x, &b) < 1e-12,
        "{}",
        residual(&full, &x, &b)
    );

    let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(full.symbolic()).unwrap());
    let mut lu = SymmetricPatternLu::new(symbolic);
    lu.factorize(full.val(), DEFAULT_PIVOT_TOLERANCE).unwrap();
    let mut y = b.clone();
    lu.solve_in_place(&mut y);
    let diff = x
        .iter()
        .zip(&y)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(diff < 1e-12 * scale, "{diff} vs {scale}");

    // Refactorized with other values on the same pattern: 2A x = b gives x / 2.
    let twice = SparseColMat::<usize, f64>::new(
        lower.symbolic().to_owned().unwrap(),
        lower.val().iter().map(|v| 2.0 * v).collect(),
    );
    cholesky.factorize(twice.as_ref()).unwrap();
    let mut z = b.clone();
    cholesky.solve_in_place(&mut z);
    let diff = x
        .iter()
        .zip(&z)
        .fold(0.0f64, |m, (a, b)| m.max((a - 2.0 * b).abs()));
    assert!(diff < 1e-12 * scale, "{diff}");
}

#[test]
fn an_indefinite_matrix_is_refused() {
    // Eigenvalues of the 10 × 10 Laplacian lie in (0, 8): a shift of −6 makes it indefinite.
    let lower = laplacian(10, 10, -6.0, true);
    let mut cholesky = SupernodalCholesky::try_new(lower.symbolic()).unwrap();
    assert!(cholesky.factorize(lower.as_ref()).is_err());
}
