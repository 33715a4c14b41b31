//! Dense LU without pivoting, in place, blocked by recursion so that the bulk of the work is
//! faer's matrix product: the diagonal blocks of the supernodal LU
//! (`SymmetricPatternLu`).
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_unit_lower_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, Par};

/// Below this order the unblocked loop beats the recursion's calls into faer.
const UNBLOCKED: usize = 24;

/// Below this many multiply-adds a dense block stays on one thread: faer's threads cost
/// more than they give on the many thin blocks of a sparse factor (measured on the 3D
/// slope's Cholesky, `docs/performance.md`).
const PARALLEL_FLOPS: usize = 1 << 21;

/// `par` for a dense operation of `flops` multiply-adds, else one thread. faer splits a
/// product over its output's tiles, never over the sum: the bits are the same.
pub(crate) fn par_for(flops: usize, par: Par) -> Par {
    if flops >= PARALLEL_FLOPS {
        par
    } else {
        Par::Seq
    }
}

/// A pivot that the guard refuses: `|u_jj| ≤ tolerance · |a_jj|` or not finite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SmallPivot {
    /// Column within the block.
    pub column: usize,
    pub pivot: f64,
}

/// `A = L U` in place (`L` unit lower, `U` upper, both stored in `a`), with no row exchange.
/// `reference[j]` is the scale the pivot `u_jj` is compared with (the original `|a_jj|`);
/// the large blocks' products use `par`.
pub(crate) fn lu_in_place(
    a: MatMut<'_, f64>,
    reference: &[f64],
    tolerance: f64,
    par: Par,
) -> Result<(), SmallPivot> {
    let n = a.nrows();
    debug_assert_eq!(n, a.ncols());
    if n <= UNBLOCKED {
        return unblocked(a, reference, tolerance);
    }
    let k = n / 2;
    let (mut a11, mut a12, mut a21, mut a22) = a.split_at_mut(k, k);
    lu_in_place(a11.rb_mut(), &reference[..k], tolerance, par)?;
    let par = par_for(k * k * (n - k), par);
    // A21 ← A21 U11⁻¹  (Uᵀ is lower with its own diagonal), A12 ← L11⁻¹ A12.
    solve_lower_triangular_in_place(a11.rb().transpose(), a21.rb_mut().transpose_mut(), par);
    solve_unit_lower_triangular_in_place(a11.rb(), a12.rb_mut(), par);
    matmul(a22.rb_mut(), Accum::Add, a21.rb(), a12.rb(), -1.0, par);
    lu_in_place(a22, &reference[k..], tolerance, par).map_err(|p| SmallPivot {
        column: p.column + k,
        ..p
    })
}

fn unblocked(mut a: MatMut<'_, f64>, reference: &[f64], tolerance: f64) -> Result<(), SmallPivot> {
    let n = a.nrows();
    for j in 0..n {
        let pivot = a[(j, j)];
        if !(pivot.is_finite() && pivot.abs() > tolerance * reference[j].abs()) {
            return Err(SmallPivot { column: j, pivot });
        }
        let inv = 1.0 / pivot;
        for i in j + 1..n {
            a[(i, j)] *= inv;
        }
        for c in j + 1..n {
            let u = a[(j, c)];
            if u != 0.0 {
                for i in j + 1..n {
                    let l = a[(i, j)];
                    a[(i, c)] -= l * u;
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    fn diagonally_dominant(n: usize) -> Mat<f64> {
        // Deterministic, unsymmetric, strictly diagonally dominant: no pivoting needed.
        Mat::from_fn(n, n, |i, j| {
            if i == j {
                4.0 * n as f64
            } else {
                ((i * 7 + j * 13) % 11) as f64 - 5.0 + 0.5 * (i > j) as u8 as f64
            }
        })
    }

    #[test]
    fn product_of_factors_reproduces_the_matrix() {
        for n in [1, 5, 24, 25, 70, 130] {
            let a = diagonally_dominant(n);
            let mut f = a.clone();
            let reference: Vec<f64> = (0..n).map(|j| a[(j, j)]).collect();
            lu_in_place(f.as_mut(), &reference, 1e-12, Par::Seq).expect("dominant matrix");
            let l = Mat::from_fn(n, n, |i, j| match i.cmp(&j) {
                std::cmp::Ordering::Greater => f[(i, j)],
                std::cmp::Ordering::Equal => 1.0,
                std::cmp::Ordering::Less => 0.0,
            });
            let u = Mat::from_fn(n, n, |i, j| if i <= j { f[(i, j)] } else { 0.0 });
            let err = (&l * &u - &a).norm_max() / a.norm_max();
            assert!(err < 1e-14, "n = {n}: ‖LU − A‖/‖A‖ = {err:e}");
        }
    }

    /// A block large enough for faer's threads (`PARALLEL_FLOPS`) factors to the same bits
    /// on 1, 2 and 4 of them.
    #[test]
    fn threads_give_the_same_bits() {
        let n = 400;
        assert!((n / 2) * (n / 2) * (n / 2) >= PARALLEL_FLOPS);
        let a = diagonally_dominant(n);
        let reference: Vec<f64> = (0..n).map(|j| a[(j, j)]).collect();
        let factor = |par: Par| {
            let mut f = a.clone();
            lu_in_place(f.as_mut(), &reference, 1e-12, par).expect("dominant matrix");
            (0..n * n)
                .map(|k| f[(k % n, k / n)].to_bits())
                .collect::<Vec<_>>()
        };
        let one = factor(Par::Seq);
        for threads in [2, 4] {
            assert!(factor(Par::rayon(threads)) == one, "{threads} threads");
        }
    }

    #[test]
    fn a_zero_pivot_is_refused_with_its_column() {
        // [[1, 1, 0], [1, 1, 1], [0, 1, 1]]: the second pivot is 1 − 1 = 0.
        let mut a = Mat::from_fn(3, 3, |i, j| if i.abs_diff(j) <= 1 { 1.0 } else { 0.0 });
        let err = lu_in_place(a.as_mut(), &[1.0; 3], 1e-12, Par::Seq).unwrap_err();
        assert_eq!(err.column, 1);
        assert_eq!(err.pivot, 0.0);
    }
}
