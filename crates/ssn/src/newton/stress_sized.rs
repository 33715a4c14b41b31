use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Mat, MatMut};
use talus_bipotential::NaturalMapLinearization;

/// `J_F` assembled sparse, stress-sized, factored by sparse LU. Block row `i` of `J_F` has
/// the pattern `U_i` = union of the patterns of `W`'s rows in point `i` and of the diagonal
/// block; it is fixed, so the symbolic LU is computed once.
pub(crate) struct StressSizedSystem {
    n: usize,
    /// Per point: columns `U_i` and the D × |U_i| rows of W on them (row-major).
    col_ptr: Vec<usize>,
    cols: Vec<usize>,
    w_rows: Vec<f64>,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    lu: SymbolicLu<usize>,
    values: Vec<f64>,
    rhs: Mat<f64>,
    /// The last factorization, kept only for `NewtonSolve::Krylov` (`keep`).
    last: Option<Lu<usize, f64>>,
}

impl StressSizedSystem {
    pub(crate) fn new<const D: usize>(w: &SparseColMat<usize, f64>) -> Result<Self, String> {
        let n = w.nrows();
        let n_points = n / D;
        // Rows of W grouped by point: (column, local row, value).
        let mut per_point: Vec<Vec<(usize, usize, f64)>> = vec![Vec::new(); n_points];
        let (cp, ri, v) = (w.symbolic().col_ptr(), w.symbolic().row_idx(), w.val());
        for j in 0..w.ncols() {
            for k in cp[j]..cp[j + 1] {
                per_point[ri[k] / D].push((j, ri[k] % D, v[k]));
            }
        }
        let mut col_ptr = vec![0];
        let mut cols = Vec::new();
        let mut w_rows = Vec::new();
        let mut pairs = Vec::new();
        for (i, entries) in per_point.into_iter().enumerate() {
            let mut u: Vec<usize> = entries
                .iter()
                .map(|e| e.0)
                .chain(D * i..D * i + D)
                .collect();
            u.sort_unstable();
            u.dedup();
            let mut rows = vec![0.0; D * u.len()];
            for (j, a, val) in entries {
                let pos = u.binary_search(&j).unwrap_or(0);
                rows[a * u.len() + pos] += val;
            }
            for a in 0..D {
                for &c in &u {
                    pairs.push(Pair::new(D * i + a, c));
                }
            }
            cols.extend_from_slice(&u);
            w_rows.extend_from_slice(&rows);
            col_ptr.push(cols.len());
        }
        let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
            .map_err(|e| format!("{e:?}"))?;
        let lu = SymbolicLu::try_new(symbolic.as_ref()).map_err(|e| format!("{e:?}"))?;
        Ok(Self {
            n,
            col_ptr,
            cols,
            w_rows,
            symbolic,
            argsort,
            lu,
            values: vec![0.0; pairs.len()],
            rhs: Mat::zeros(n, 1),
            last: None,
        })
    }

    /// Writes the direction into `d`; `Err` when the numeric LU fails.
    pub(crate) fn solve<const D: usize>(
        &mut self,
        lin: &[NaturalMapLinearization<D>],
        rho: &[f64],
        r: &[f64],
        d: &mut [f64],
        keep: bool,
    ) -> Result<(), String> {
        self.last = None;
        let mut pos = 0;
        for (i, (l, &rho_i)) in lin.iter().zip(rho).enumerate() {
            let (a0, a1) = (self.col_ptr[i], self.col_ptr[i + 1]);
            let u = &self.cols[a0..a1];
            let m = u.len();
            let rows = &self.w_rows[D * a0..D * a1];
            for a in 0..D {
                for (k, &c) in u.iter().enumerate() {
                    let mut v = 0.0;
                    for b in 0..D {
                        v += l.coupling[(a, b)] * rows[b * m + k];
                    }
                    v *= rho_i;
                    if c >= D * i && c < D * i + D {
                        let b = c - D * i;
                        v += if a == b { 1.0 } else { 0.0 } - l.projection_jacobian[(a, b)];
                    }
                    self.values[pos] = v;
                    pos += 1;
                }
            }
        }
        let mat =
            SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, &self.values)
                .map_err(|e| format!("{e:?}"))?;
        let lu = Lu::try_new_with_symbolic(self.lu.clone(), mat.as_ref())
            .map_err(|e| format!("{e:?}"))?;
        for (k, v) in r.iter().enumerate() {
            self.rhs[(k, 0)] = *v;
        }
        lu.solve_in_place(self.rhs.as_mut());
        for (k, out) in d.iter_mut().enumerate().take(self.n) {
            *out = self.rhs[(k, 0)];
        }
        if keep {
            self.last = Some(lu);
        }
        Ok(())
    }

    /// `x ← J_old⁻¹ x` with the kept factorization; false without one.
    pub(crate) fn precondition(&self, x: &mut [f64]) -> bool {
        let Some(lu) = &self.last else {
            return false;
        };
        let n = x.len();
        lu.solve_in_place(MatMut::from_column_major_slice_mut(x, n, 1));
        true
    }

    pub(crate) fn has_factorization(&self) -> bool {
        self.last.is_some()
    }
}
