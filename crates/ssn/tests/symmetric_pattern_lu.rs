//! The no-pivot LU on the symmetric pattern's Cholesky structure against faer's partial
//! pivoting LU (an independent factorization) and the residual `‖A x − b‖`.
use std::sync::Arc;

use talus_ssn::factorization::{
    SymbolicSymmetricPatternLu, SymmetricPatternLu, DEFAULT_PIVOT_TOLERANCE,
};
use talus_ssn::faer::linalg::solvers::Solve;
use talus_ssn::faer::sparse::{SparseColMat, Triplet};
use talus_ssn::faer::Mat;

use crate::grid_matrix;
use grid_matrix::grid_matrix;

fn residual(a: &SparseColMat<usize, f64>, x: &[f64], b: &[f64]) -> f64 {
    let xm = Mat::from_fn(x.len(), 1, |i, _| x[i]);
    let ax = a * &xm;
    let bn = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    (0..b.len()).fold(0.0f64, |m, i| m.max((ax[(i, 0)] - b[i]).abs())) / bn
}

#[test]
fn solves_like_partial_pivoting_lu_on_a_grid_matrix() {
    // Dominance 0.6: the diagonal is below the off-diagonal row sum, yet no row exchange is
    // needed. (At 0.3 these random matrices do need pivoting: 1e-10 without it.)
    for (nx, ny, dominance) in [
        (1, 1, 1.0),
        (3, 2, 1.0),
        (30, 20, 1.0),
        (60, 45, 1.0),
        (60, 45, 0.6),
    ] {
        let a = grid_matrix(nx, ny, dominance, 7 + nx as u64);
        let n = a.nrows();
        let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(a.symbolic()).unwrap());
        let mut lu = SymmetricPatternLu::new(symbolic);
        lu.factorize(a.val(), DEFAULT_PIVOT_TOLERANCE)
            .expect("no small pivot");
        let b: Vec<f64> = (0..n).map(|i| ((i * 37) % 17) as f64 - 8.0).collect();
        let mut x = b.clone();
        lu.solve_in_place(&mut x);
        let r = residual(&a, &x, &b);
        assert!(r < 1e-13, "{nx}×{ny}: relative residual {r:e}");

        let reference = a.sp_lu().expect("faer's LU");
        let bm = Mat::from_fn(n, 1, |i, _| b[i]);
        let xr = reference.solve(&bm);
        let scale = (0..n).fold(0.0f64, |m, i| m.max(xr[(i, 0)].abs()));
        let diff = (0..n).fold(0.0f64, |m, i| m.max((x[i] - xr[(i, 0)]).abs())) / scale;
        assert!(
            diff < 1e-12,
            "{nx}×{ny}: differs from faer's LU by {diff:e}"
        );
    }
}

#[test]
fn refactorization_reuses_the_analysis() {
    let a1 = grid_matrix(20, 15, 1.0, 1);
    let a2 = grid_matrix(20, 15, 0.8, 2);
    let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(a1.symbolic()).unwrap());
    let mut lu = SymmetricPatternLu::new(Arc::clone(&symbolic));
    let b: Vec<f64> = (0..a1.nrows()).map(|i| (i % 5) as f64).collect();
    for a in [&a1, &a2, &a1] {
        lu.factorize(a.val(), DEFAULT_PIVOT_TOLERANCE).unwrap();
        let mut x = b.clone();
        lu.solve_in_place(&mut x);
        assert!(residual(a, &x, &b) < 1e-13);
    }
}

#[test]
fn an_unsymmetric_pattern_is_factorized_on_its_symmetric_closure() {
    // Lower bidiagonal plus a full last column: (i, n−1) stored, (n−1, i) not.
    let n = 40;
    let mut t = Vec::new();
    for i in 0..n {
        t.push(Triplet::new(i, i, 3.0 + i as f64 * 0.1));
        if i + 1 < n {
            t.push(Triplet::new(i + 1, i, -1.0));
            t.push(Triplet::new(i, n - 1, 0.5));
        }
    }
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
    let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(a.symbolic()).unwrap());
    let mut lu = SymmetricPatternLu::new(symbolic);
    lu.factorize(a.val(), DEFAULT_PIVOT_TOLERANCE).unwrap();
    let b: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
    let mut x = b.clone();
    lu.solve_in_place(&mut x);
    assert!(residual(&a, &x, &b) < 1e-14);
}

#[test]
fn a_matrix_that_needs_row_exchanges_is_refused_at_its_zero_pivot() {
    // [[0, 1], [1, 0]] coupled to a dominant block: the zero diagonal survives any ordering
    // of this pattern (no fill reaches it), so the guard must name column 5 or 6.
    let mut t = Vec::new();
    for i in 0..5 {
        t.push(Triplet::new(i, i, 4.0));
        if i + 1 < 5 {
            t.push(Triplet::new(i, i + 1, 1.0));
            t.push(Triplet::new(i + 1, i, 1.0));
        }
    }
    t.push(Triplet::new(5, 5, 0.0));
    t.push(Triplet::new(6, 6, 0.0));
    t.push(Triplet::new(5, 6, 1.0));
    t.push(Triplet::new(6, 5, 1.0));
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(7, 7, &t).unwrap();
    let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(a.symbolic()).unwrap());
    let mut lu = SymmetricPatternLu::new(symbolic);
    let err = lu.factorize(a.val(), DEFAULT_PIVOT_TOLERANCE).unwrap_err();
    assert!(err.column == 5 || err.column == 6, "{err}");
    assert_eq!(err.pivot, 0.0);
}

/// For a full 2 × 2 matrix the second pivot is `det A / a_kk` whichever column the ordering
/// takes first, so the smallest ratio `|u_jj| / |a_jj|` is `det A / (a_11 a_22)`.
#[test]
fn smallest_pivot_ratio_of_a_two_by_two_matrix_is_det_over_diagonal_product() {
    // [[4, 1], [2, 3]]: det 10, ratio 10 / 12.
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(
        2,
        2,
        &[
            Triplet::new(0, 0, 4.0),
            Triplet::new(1, 0, 2.0),
            Triplet::new(0, 1, 1.0),
            Triplet::new(1, 1, 3.0),
        ],
    )
    .unwrap();
    let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(a.symbolic()).unwrap());
    let mut lu = SymmetricPatternLu::new(symbolic);
    assert_eq!(lu.smallest_pivot_ratio(), None);
    lu.factorize(a.val(), DEFAULT_PIVOT_TOLERANCE).unwrap();
    let ratio = lu.smallest_pivot_ratio().unwrap();
    assert!((ratio - 10.0 / 12.0).abs() < 1e-15, "{ratio}");
}

/// The number of negative pivots gives the sign of `det A`: [[1, 2], [2, 1]] (det −3) has
/// one whichever column the ordering takes first (pivots 1 and −3), [[4, 1], [2, 3]]
/// (det 10) none.
#[test]
fn negative_pivots_count_the_sign_of_the_determinant() {
    let count = |a: [[f64; 2]; 2]| {
        let triplets: Vec<_> = (0..2)
            .flat_map(|i| (0..2).map(move |j| Triplet::new(i, j, a[i][j])))
            .collect();
        let m = SparseColMat::<usize, f64>::try_new_from_triplets(2, 2, &triplets).unwrap();
        let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(m.symbolic()).unwrap());
        let mut lu = SymmetricPatternLu::new(symbolic);
        assert_eq!(lu.negative_pivots(), None, "before a factorization");
        lu.factorize(m.val(), DEFAULT_PIVOT_TOLERANCE).unwrap();
        lu.negative_pivots().unwrap()
    };
    assert_eq!(count([[1.0, 2.0], [2.0, 1.0]]), 1);
    assert_eq!(count([[4.0, 1.0], [2.0, 3.0]]), 0);
    assert_eq!(
        count([[-1.0, 0.5], [0.5, -2.0]]),
        2,
        "det > 0, two negative pivots"
    );
}

/// `values` with the rows and columns `zero` set to 0 (kept in the pattern).
fn with_zero_lines(a: &SparseColMat<usize, f64>, zero: &[usize]) -> Vec<f64> {
    let mut values = a.val().to_vec();
    for c in 0..a.ncols() {
        let range = a.col_ptr()[c]..a.col_ptr()[c + 1];
        for (p, &r) in range.clone().zip(&a.row_idx()[range]) {
            if zero.contains(&r) || zero.contains(&c) {
                values[p] = 0.0;
            }
        }
    }
    values
}

/// Subtrees factorized on 2 and 4 threads give the one-thread solution bit for bit, and a
/// matrix with two zero lines far apart (in different subtrees) the same breakdown: the
/// one the one-thread order meets first.
#[test]
fn the_factors_do_not_depend_on_the_thread_count() {
    let a = grid_matrix(120, 100, 1.0, 7);
    let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(a.symbolic()).unwrap());
    assert!(
        symbolic.parallel_subtrees() >= 2,
        "{} subtrees: the test needs a split tree",
        symbolic.parallel_subtrees()
    );
    let b: Vec<f64> = (0..a.nrows()).map(|i| 1.0 + (i % 11) as f64).collect();
    let run = |threads: usize, values: &[f64]| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut lu = SymmetricPatternLu::new(Arc::clone(&symbolic));
            lu.factorize(values, DEFAULT_PIVOT_TOLERANCE).map(|()| {
                let mut x = b.clone();
                lu.solve_in_place(&mut x);
                x
            })
        })
    };
    let bits =
        |r: Result<Vec<f64>, _>| r.map(|x| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
    let one = run(1, a.val()).expect("dominant matrix");
    assert!(residual(&a, &one, &b) < 1e-12, "{}", residual(&a, &one, &b));
    for threads in [2, 4] {
        assert_eq!(
            bits(run(threads, a.val())),
            bits(Ok(one.clone())),
            "{threads} threads"
        );
    }
    // Node (5, 5) and node (114, 94): opposite corners of the grid.
    let zeroed = with_zero_lines(&a, &[2 * (5 + 120 * 5), 2 * (114 + 120 * 94)]);
    let one = run(1, &zeroed).expect_err("zero pivots");
    assert_eq!(one.pivot, 0.0);
    for threads in [2, 4] {
        assert_eq!(
            run(threads, &zeroed).expect_err("zero pivots"),
            one,
            "{threads} threads"
        );
    }
}
