use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{Mat, MatMut};
use talus_bipotential::NaturalMapLinearization;

/// `J_F` assembled dense and factored by partial-pivoting LU: for small problems.
pub(crate) struct DenseSystem {
    jacobian: Mat<f64>,
    rhs: Mat<f64>,
    /// The last factorization: a preconditioner for `NewtonSolve::Krylov`.
    lu: Option<PartialPivLu<f64>>,
}

impl DenseSystem {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            jacobian: Mat::zeros(n, n),
            rhs: Mat::zeros(n, 1),
            lu: None,
        }
    }

    /// Writes the direction into `d`.
    pub(crate) fn solve<const D: usize>(
        &mut self,
        w: &Mat<f64>,
        lin: &[NaturalMapLinearization<D>],
        rho: &[f64],
        r: &[f64],
        d: &mut [f64],
    ) {
        let n = w.nrows();
        for (i, (l, &rho_i)) in lin.iter().zip(rho).enumerate() {
            for a in 0..D {
                let row = D * i + a;
                for c in 0..n {
                    let mut v = 0.0;
                    for b in 0..D {
                        v += l.coupling[(a, b)] * w[(D * i + b, c)];
                    }
                    self.jacobian[(row, c)] = rho_i * v;
                }
                for b in 0..D {
                    let delta = if a == b { 1.0 } else { 0.0 };
                    self.jacobian[(row, D * i + b)] += delta - l.projection_jacobian[(a, b)];
                }
            }
        }
        for (k, v) in r.iter().enumerate() {
            self.rhs[(k, 0)] = *v;
        }
        let lu = self.jacobian.partial_piv_lu();
        lu.solve_in_place(self.rhs.as_mut());
        for (k, out) in d.iter_mut().enumerate() {
            *out = self.rhs[(k, 0)];
        }
        self.lu = Some(lu);
    }

    /// `x ← J_old⁻¹ x` with the last factorization; false before one.
    pub(crate) fn precondition(&self, x: &mut [f64]) -> bool {
        let Some(lu) = &self.lu else {
            return false;
        };
        let n = x.len();
        lu.solve_in_place(MatMut::from_column_major_slice_mut(x, n, 1));
        true
    }

    pub(crate) fn has_factorization(&self) -> bool {
        self.lu.is_some()
    }
}
