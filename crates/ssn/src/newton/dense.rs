use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{Conj, Mat, MatMut, Par};
use talus_bipotential::NaturalMapLinearization;

/// `J_F` assembled dense and factored by partial-pivoting LU in place: for small problems.
///
/// On one thread whatever rayon's pool: below `DENSE_LIMIT` (600) faer's threads cost more
/// than they give. The Siconos footing's 300 unknowns took 8.2 ms before faer's rayon feature
/// was on, then 21–27 ms on two threads (12 ms on one) with faer's global parallelism, and
/// 7.3 ms here (`cargo bench -p talus-ssn --bench footing`, 2026-11-28).
pub(crate) struct DenseSystem {
    /// `J_F`, then its factors `L` (unit, strictly lower) and `U` in place: after a solve,
    /// the preconditioner of `NewtonSolve::Krylov`.
    jacobian: Mat<f64>,
    row_perm: Vec<usize>,
    row_perm_inverse: Vec<usize>,
    factored: bool,
    scratch: MemBuffer,
}

impl DenseSystem {
    pub(crate) fn new(n: usize) -> Self {
        let req = factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default())
            .or(solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq));
        Self {
            jacobian: Mat::zeros(n, n),
            row_perm: vec![0; n],
            row_perm_inverse: vec![0; n],
            factored: false,
            scratch: MemBuffer::new(req),
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
        factor::lu_in_place(
            self.jacobian.as_mut(),
            &mut self.row_perm,
            &mut self.row_perm_inverse,
            Par::Seq,
            MemStack::new(&mut self.scratch),
            Default::default(),
        );
        self.factored = true;
        d.copy_from_slice(r);
        self.precondition(d);
    }

    /// `x ← J_old⁻¹ x` with the last factorization; false before one.
    pub(crate) fn precondition(&mut self, x: &mut [f64]) -> bool {
        if !self.factored {
            return false;
        }
        let n = x.len();
        let lu = self.jacobian.as_ref();
        solve::solve_in_place_with_conj(
            lu,
            lu,
            PermRef::new_checked(&self.row_perm, &self.row_perm_inverse, n),
            Conj::No,
            MatMut::from_column_major_slice_mut(x, n, 1),
            Par::Seq,
            MemStack::new(&mut self.scratch),
        );
        true
    }

    pub(crate) fn has_factorization(&self) -> bool {
        self.factored
    }
}
