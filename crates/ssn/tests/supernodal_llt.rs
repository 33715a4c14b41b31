//! The supernodal Cholesky on the no-pivot LU's structure (`SymmetricPatternLlt`, the f64
//! factor of `SupernodalCholesky`) against the no-pivot LU of the full symmetric matrix
//! (an independent factorization of the same matrix), its residual, its bits on 1, 2 and
//! 4 threads, and its refusal of an indefinite matrix.
use std::sync::Arc;

use talus_ssn::factorization::{
    SupernodalCholesky, SymbolicSymmetricPatternLu, SymmetricPatternLlt, SymmetricPatternLu,
    DEFAULT_PIVOT_TOLERANCE,
};
use talus_ssn::faer::sparse::{SparseColMat, Triplet};
use talus_ssn::faer::Mat;

use crate::grid_matrix;
use grid_matrix::grid_matrix;

/// `(A + Aᵀ)/2` of the grid matrix whose diagonal is twice its row's off-diagonal sum
/// (diagonally dominant with a positive diagonal as long as a column's sum stays below
/// three times its row's: positive definite), whole and as its lower triangle.
fn spd(nx: usize, ny: usize, seed: u64) -> (SparseColMat<usize, f64>, SparseColMat<usize, f64>) {
    let a = grid_matrix(nx, ny, 2.0, seed);
    let mut whole = Vec::new();
    let mut lower = Vec::new();
    for c in 0..a.ncols() {
        let col = a.col_ptr()[c]..a.col_ptr()[c + 1];
        for (&r, &v) in a.row_idx()[col.clone()].iter().zip(&a.val()[col]) {
            whole.push(Triplet::new(r, c, 0.5 * v));
            whole.push(Triplet::new(c, r, 0.5 * v));
            if r >= c {
                lower.push(Triplet::new(r, c, 0.5 * v));
            }
            if r <= c {
                lower.push(Triplet::new(c, r, 0.5 * v));
            }
        }
    }
    let n = a.nrows();
    (
        SparseColMat::try_new_from_triplets(n, n, &whole).unwrap(),
        SparseColMat::try_new_from_triplets(n, n, &lower).unwrap(),
    )
}

fn residual(a: &SparseColMat<usize, f64>, x: &[f64], b: &[f64]) -> f64 {
    let xm = Mat::from_fn(x.len(), 1, |i, _| x[i]);
    let ax = a * &xm;
    let bn = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    (0..b.len()).fold(0.0f64, |m, i| m.max((ax[(i, 0)] - b[i]).abs())) / bn
}

/// `f` on a rayon pool of `threads` threads.
fn on_threads<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

fn rhs(n: usize) -> Vec<f64> {
    (0..n).map(|i| 1.0 + (i % 11) as f64).collect()
}

/// Small and mid-sized grids (one supernode to hundreds): the same solution as the LU of
/// the whole matrix to 1e-12, through `SupernodalCholesky` too.
#[test]
fn cholesky_agrees_with_the_lu_of_the_whole_matrix() {
    for (nx, ny) in [(1, 1), (3, 2), (17, 9), (60, 40)] {
        let (whole, lower) = spd(nx, ny, 5);
        let b = rhs(whole.nrows());
        let lu_symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(whole.symbolic()).unwrap());
        let mut lu = SymmetricPatternLu::new(lu_symbolic);
        lu.factorize(whole.val(), DEFAULT_PIVOT_TOLERANCE).unwrap();
        let mut x_lu = b.clone();
        lu.solve_in_place(&mut x_lu);

        let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(lower.symbolic()).unwrap());
        let mut llt = SymmetricPatternLlt::<f64>::new(symbolic);
        llt.factorize(lower.val()).expect("positive definite");
        let mut x = b.clone();
        llt.solve_in_place(&mut x);
        let mut cholesky = SupernodalCholesky::try_new(lower.symbolic()).unwrap();
        cholesky
            .factorize(lower.as_ref())
            .expect("positive definite");
        let mut y = b.clone();
        cholesky.solve_in_place(&mut y);

        assert!(
            residual(&whole, &x, &b) < 1e-13,
            "{nx}×{ny}: {}",
            residual(&whole, &x, &b)
        );
        let scale = x_lu.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (name, sol) in [("llt", &x), ("SupernodalCholesky", &y)] {
            let diff = sol
                .iter()
                .zip(&x_lu)
                .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
            assert!(diff < 1e-12 * scale, "{nx}×{ny} {name}: {diff:e}");
        }
    }
}

/// A 24k grid whose elimination tree splits into subtrees: the solution to the bit on 1,
/// 2 and 4 threads; with a negative diagonal in two subtrees far apart, the same refusal
/// (the column the one-thread order meets first).
#[test]
fn the_factor_does_not_depend_on_the_thread_count() {
    let (whole, lower) = spd(120, 100, 7);
    let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(lower.symbolic()).unwrap());
    assert!(
        symbolic.parallel_subtrees() >= 2,
        "{} subtrees: the test needs a split tree",
        symbolic.parallel_subtrees()
    );
    let b = rhs(whole.nrows());
    let run = |threads: usize, values: &[f64]| {
        on_threads(threads, || {
            let mut llt = SymmetricPatternLlt::<f64>::new(Arc::clone(&symbolic));
            llt.factorize(values).map(|()| {
                let mut x = b.clone();
                llt.solve_in_place(&mut x);
                x.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
            })
        })
    };
    let one = run(1, lower.val()).expect("positive definite");
    let x: Vec<f64> = one.iter().map(|&b| f64::from_bits(b)).collect();
    assert!(residual(&whole, &x, &b) < 1e-12);
    for threads in [2, 4] {
        assert_eq!(
            run(threads, lower.val()),
            Ok(one.clone()),
            "{threads} threads"
        );
    }
    // Node (5, 5) and node (114, 94): opposite corners of the grid.
    let mut values = lower.val().to_vec();
    for node in [5 + 120 * 5, 114 + 120 * 94] {
        let j = 2 * node;
        let col = lower.col_ptr()[j]..lower.col_ptr()[j + 1];
        let k = lower.row_idx()[col.clone()]
            .iter()
            .position(|&r| r == j)
            .unwrap();
        values[col.start + k] = -1.0;
    }
    let refused = run(1, &values).expect_err("indefinite");
    for threads in [2, 4] {
        assert_eq!(run(threads, &values), Err(refused), "{threads} threads");
    }
}

/// No unknown (a body whose every dof is prescribed): an empty factorization and solve,
/// by the Cholesky and by the LU (faer's own analysis of an empty pattern is simplicial).
#[test]
fn an_empty_matrix_factorizes_and_solves() {
    let empty = SparseColMat::<usize, f64>::try_new_from_triplets(0, 0, &[]).unwrap();
    let mut cholesky = SupernodalCholesky::try_new(empty.symbolic()).unwrap();
    cholesky.factorize(empty.as_ref()).unwrap();
    cholesky.solve_in_place(&mut []);
    let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(empty.symbolic()).unwrap());
    let mut lu = SymmetricPatternLu::new(symbolic);
    lu.factorize(empty.val(), DEFAULT_PIVOT_TOLERANCE).unwrap();
    lu.solve_in_place(&mut []);
}

/// The f32 factor (`SymmetricPatternLlt<f32>`, the Krylov path's preconditioner, and
/// `SupernodalCholesky::try_new_single`): on these well-conditioned matrices (diagonal
/// twice the off-diagonal sum: condition number below 10) its solution is within a few
/// hundred f32 roundings of the f64 one (Higham 2002, 'Accuracy and Stability of
/// Numerical Algorithms', Thm 10.4: backward error `O(n_L ε)` with `n_L` the columns'
/// lengths), and not closer than f32 allows (it is computed in f32); the same bits on 1,
/// 2 and 4 threads; the f64 factorization of a single-precision solver is the f64 one.
#[test]
fn the_single_precision_factor_solves_to_f32_accuracy() {
    for (nx, ny) in [(3, 2), (60, 40), (120, 100)] {
        let (whole, lower) = spd(nx, ny, 11);
        let b = rhs(whole.nrows());
        let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(lower.symbolic()).unwrap());
        let mut double = SymmetricPatternLlt::<f64>::new(Arc::clone(&symbolic));
        double.factorize(lower.val()).expect("positive definite");
        let mut x = b.clone();
        double.solve_in_place(&mut x);
        let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let run = |threads: usize| {
            on_threads(threads, || {
                let mut single = SymmetricPatternLlt::<f32>::new(Arc::clone(&symbolic));
                single.factorize(lower.val()).expect("positive definite");
                let mut y = b.clone();
                single.solve_in_place(&mut y);
                y
            })
        };
        let y = run(1);
        let diff = y
            .iter()
            .zip(&x)
            .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
            / scale;
        assert!(
            diff < 300.0 * f32::EPSILON as f64 && diff > 0.1 * f32::EPSILON as f64,
            "{nx}×{ny}: f32 against f64 {diff:e}"
        );
        for threads in [2, 4] {
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&run(threads)),
                bits(&y),
                "{nx}×{ny}, {threads} threads"
            );
        }

        let mut cholesky =
            SupernodalCholesky::try_new_single(lower.symbolic(), Default::default()).unwrap();
        cholesky.factorize_single(lower.as_ref()).unwrap();
        let mut z = b.clone();
        cholesky.solve_in_place_single(&mut z);
        assert_eq!(z, y, "{nx}×{ny}: SupernodalCholesky's f32 factor");
        cholesky.factorize(lower.as_ref()).unwrap();
        let mut z = b.clone();
        cholesky.solve_in_place(&mut z);
        assert_eq!(z, x, "{nx}×{ny}: SupernodalCholesky's f64 factor");
    }
}
