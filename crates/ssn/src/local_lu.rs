//! LU with partial pivoting for one point's D×D block (D ≤ 6), on the stack.
//! nalgebra's fixed-size LU needs typenum bounds that a generic `const D` cannot name, and
//! the Schur path must detect a singular block (`docs/derivations.md`, 'The Schur step')
//! rather than divide by ~0.
use nalgebra::{SMatrix, SVector};

/// Relative pivot size under which a block counts as singular.
const SINGULAR_PIVOT: f64 = 1e-13;

#[derive(Debug, Clone, Copy)]
pub(crate) struct LocalLu<const D: usize> {
    lu: SMatrix<f64, D, D>,
    perm: [usize; D],
}

impl<const D: usize> LocalLu<D> {
    /// `None` when a pivot falls below `1e-13 ‖A‖∞`, or on non-finite entries.
    pub(crate) fn factor(a: &SMatrix<f64, D, D>) -> Option<Self> {
        let scale = a.amax();
        if !scale.is_finite() || scale == 0.0 {
            return None;
        }
        let mut lu = *a;
        let mut perm = [0usize; D];
        for (k, p) in perm.iter_mut().enumerate() {
            *p = k;
        }
        for k in 0..D {
            let (mut piv, mut best) = (k, lu[(k, k)].abs());
            for r in k + 1..D {
                if lu[(r, k)].abs() > best {
                    (piv, best) = (r, lu[(r, k)].abs());
                }
            }
            if best <= SINGULAR_PIVOT * scale {
                return None;
            }
            if piv != k {
                lu.swap_rows(k, piv);
                perm.swap(k, piv);
            }
            let inv = 1.0 / lu[(k, k)];
            for r in k + 1..D {
                let l = lu[(r, k)] * inv;
                lu[(r, k)] = l;
                for c in k + 1..D {
                    lu[(r, c)] -= l * lu[(k, c)];
                }
            }
        }
        Some(Self { lu, perm })
    }

    pub(crate) fn solve(&self, b: &SVector<f64, D>) -> SVector<f64, D> {
        let mut x = SVector::<f64, D>::from_fn(|i, _| b[self.perm[i]]);
        for r in 0..D {
            for c in 0..r {
                x[r] -= self.lu[(r, c)] * x[c];
            }
        }
        for r in (0..D).rev() {
            for c in r + 1..D {
                x[r] -= self.lu[(r, c)] * x[c];
            }
            x[r] /= self.lu[(r, r)];
        }
        x
    }

    pub(crate) fn solve_matrix(&self, b: &SMatrix<f64, D, D>) -> SMatrix<f64, D, D> {
        let mut out = SMatrix::<f64, D, D>::zeros();
        for j in 0..D {
            out.set_column(j, &self.solve(&b.column(j).into_owned()));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_pivoting_system_and_flags_singular_blocks() {
        let a = SMatrix::<f64, 3, 3>::new(0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0);
        let x = SVector::<f64, 3>::new(1.0, -2.0, 0.5);
        let lu = LocalLu::factor(&a).expect("regular");
        assert!((lu.solve(&(a * x)) - x).amax() < 1e-14);
        let singular = SMatrix::<f64, 3, 3>::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0);
        assert!(LocalLu::factor(&singular).is_none());
        assert!(LocalLu::<3>::factor(&SMatrix::zeros()).is_none());
    }
}
