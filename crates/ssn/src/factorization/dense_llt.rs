//! Dense Cholesky `A = L Lᵀ` in place (lower triangle read and written), blocked by
//! recursion so that the bulk of the work is faer's products: the diagonal blocks of the
//! supernodal Cholesky (`SymmetricPatternLlt`). faer splits a product over its
//! output's tiles, never over the sum, so the bits do not depend on `par`.
use faer::linalg::matmul::triangular::{matmul, BlockStructure};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, Par};

use super::dense_lu::par_for;
use super::real::Real;

/// Below this order the unblocked loop beats the recursion's calls into faer.
const UNBLOCKED: usize = 24;

/// The first column `j` whose pivot `a_jj − Σ l_jk²` is not positive (or not finite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct NonPositivePivot {
    pub column: usize,
}

/// `A = L Lᵀ` in place: `L` overwrites the lower triangle, the strict upper triangle is
/// neither read nor written; the large blocks' products use `par`.
pub(crate) fn llt_in_place<T: Real>(a: MatMut<'_, T>, par: Par) -> Result<(), NonPositivePivot> {
    let n = a.nrows();
    debug_assert_eq!(n, a.ncols());
    if n <= UNBLOCKED {
        return unblocked(a);
    }
    let k = n / 2;
    let (mut a11, _, mut a21, mut a22) = a.split_at_mut(k, k);
    llt_in_place(a11.rb_mut(), par)?;
    let par = par_for(k * k * (n - k), par);
    // L21 = A21 L11⁻ᵀ, then A22 ← A22 − L21 L21ᵀ on its lower triangle.
    solve_lower_triangular_in_place(a11.rb(), a21.rb_mut().transpose_mut(), par);
    matmul(
        a22.rb_mut(),
        BlockStructure::TriangularLower,
        Accum::Add,
        a21.rb(),
        BlockStructure::Rectangular,
        a21.rb().transpose(),
        BlockStructure::Rectangular,
        -T::ONE,
        par,
    );
    llt_in_place(a22, par).map_err(|p| NonPositivePivot {
        column: p.column + k,
    })
}

fn unblocked<T: Real>(mut a: MatMut<'_, T>) -> Result<(), NonPositivePivot> {
    let n = a.nrows();
    for j in 0..n {
        let pivot = a[(j, j)];
        if !(pivot.is_finite() && pivot > T::ZERO) {
            return Err(NonPositivePivot { column: j });
        }
        let d = pivot.sqrt();
        a[(j, j)] = d;
        let inv = T::ONE / d;
        for i in j + 1..n {
            a[(i, j)] *= inv;
        }
        for c in j + 1..n {
            let l = a[(c, j)];
            if l != T::ZERO {
                for i in c..n {
                    let v = a[(i, j)];
                    a[(i, c)] -= v * l;
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

    /// Symmetric, strictly diagonally dominant with a positive diagonal: positive definite.
    fn spd(n: usize) -> Mat<f64> {
        Mat::from_fn(n, n, |i, j| {
            if i == j {
                4.0 * n as f64
            } else {
                ((i * 7 + j * 7 + i * j) % 11) as f64 - 5.0
            }
        })
    }

    /// The strict upper triangle is poisoned: it must be neither read nor written.
    fn factor(a: &Mat<f64>, par: Par) -> Mat<f64> {
        let n = a.nrows();
        let mut f = Mat::from_fn(n, n, |i, j| if i >= j { a[(i, j)] } else { f64::NAN });
        llt_in_place(f.as_mut(), par).expect("positive definite");
        for j in 0..n {
            for i in 0..j {
                assert!(f[(i, j)].is_nan(), "upper ({i}, {j}) written");
            }
        }
        f
    }

    #[test]
    fn product_of_factors_reproduces_the_matrix() {
        for n in [1, 5, 24, 25, 70, 130] {
            let a = spd(n);
            let f = factor(&a, Par::Seq);
            let l = Mat::from_fn(n, n, |i, j| if i >= j { f[(i, j)] } else { 0.0 });
            let err = (&l * l.transpose() - &a).norm_max() / a.norm_max();
            assert!(err < 1e-14, "n = {n}: ‖LLᵀ − A‖/‖A‖ = {err:e}");
        }
    }

    /// A block large enough for faer's threads (`PARALLEL_FLOPS`) factors to the same bits
    /// on 1, 2 and 4 of them.
    #[test]
    fn threads_give_the_same_bits() {
        let n = 400;
        let a = spd(n);
        let bits = |f: Mat<f64>| {
            (0..n * n)
                .filter(|k| k % n >= k / n)
                .map(|k| f[(k % n, k / n)].to_bits())
                .collect::<Vec<_>>()
        };
        let one = bits(factor(&a, Par::Seq));
        for threads in [2, 4] {
            assert!(
                bits(factor(&a, Par::rayon(threads))) == one,
                "{threads} threads"
            );
        }
    }

    #[test]
    fn an_indefinite_matrix_is_refused_at_its_first_non_positive_pivot() {
        // [[1, 1, 0], [1, 1, 1], [0, 1, 1]]: the second pivot is 1 − 1 = 0.
        let mut a = Mat::from_fn(3, 3, |i, j| if i.abs_diff(j) <= 1 { 1.0 } else { 0.0 });
        assert_eq!(
            llt_in_place(a.as_mut(), Par::Seq),
            Err(NonPositivePivot { column: 1 })
        );
        // Past the unblocked size, in the second half.
        let n = 60;
        let mut a = spd(n);
        a[(45, 45)] = -1.0;
        let column = llt_in_place(a.as_mut(), Par::Seq).unwrap_err().column;
        assert_eq!(column, 45);
    }
}
