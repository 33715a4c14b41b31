use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, Lu, SymbolicLlt, SymbolicLu};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Mat, Side};
use nalgebra::{SMatrix, SVector};
use talus_bipotential::NaturalMapLinearization;

use crate::local_lu::LocalLu;
use crate::operator::{block, PointBlocks, Structured};

enum Factorization {
    /// Associative: `ρ A⁻¹ D` is symmetric positive semi-definite, K is SPD.
    Cholesky(SymbolicLlt<usize>),
    Lu(SymbolicLu<usize>),
}

/// The velocity-sized Newton system of the notes §5:
/// `(M + h² Bᵀ C B) u = Bᵀ A⁻¹ r`, `d = A⁻¹ r − h² C B u`,
/// with per point `A_i = I − D_i + ρ_i G_i S_i` and `C_i = ρ_i A_i⁻¹ G_i`.
/// The pattern of K is that of `Bᵀ B` plus the diagonal: fixed, factored symbolically once.
pub(crate) struct SchurSystem<const D: usize> {
    symmetric: bool,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    factorization: Factorization,
    values: Vec<f64>,
    local_a: Vec<LocalLu<D>>,
    local_c: Vec<SMatrix<f64, D, D>>,
    rhs: Mat<f64>,
    a_inv_r: Vec<f64>,
}

/// Why the Schur path could not give a direction this step.
pub(crate) enum SchurFailure {
    /// A local block `A_i` is singular: use the stress-sized system.
    SingularBlock(usize),
    Factorization(String),
}

impl<const D: usize> SchurSystem<D> {
    pub(crate) fn new(
        structured: &Structured<D>,
        blocks: &PointBlocks<D>,
        symmetric: bool,
    ) -> Result<Self, String> {
        let n_v = structured.lumped_mass.len();
        let n_points = structured.compliance.len();
        let mut pairs: Vec<Pair<usize, usize>> = (0..n_v).map(|j| Pair::new(j, j)).collect();
        for i in 0..n_points {
            let (dofs, _) = blocks.point(i);
            for &ra in dofs {
                for &cb in dofs {
                    if !symmetric || ra >= cb {
                        pairs.push(Pair::new(ra, cb));
                    }
                }
            }
        }
        let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n_v, n_v, &pairs)
            .map_err(|e| format!("{e:?}"))?;
        let factorization = if symmetric {
            Factorization::Cholesky(
                SymbolicLlt::try_new(symbolic.as_ref(), Side::Lower)
                    .map_err(|e| format!("{e:?}"))?,
            )
        } else {
            Factorization::Lu(SymbolicLu::try_new(symbolic.as_ref()).map_err(|e| format!("{e:?}"))?)
        };
        Ok(Self {
            symmetric,
            symbolic,
            argsort,
            factorization,
            values: vec![0.0; pairs.len()],
            local_a: Vec::with_capacity(n_points),
            local_c: Vec::with_capacity(n_points),
            rhs: Mat::zeros(n_v, 1),
            a_inv_r: vec![0.0; D * n_points],
        })
    }

    /// Writes the direction into `d`.
    pub(crate) fn solve(
        &mut self,
        structured: &Structured<D>,
        blocks: &PointBlocks<D>,
        lin: &[NaturalMapLinearization<D>],
        rho: &[f64],
        r: &[f64],
        d: &mut [f64],
    ) -> Result<(), SchurFailure> {
        let h2 = structured.h * structured.h;
        self.local_a.clear();
        self.local_c.clear();
        for (i, (l, &rho_i)) in lin.iter().zip(rho).enumerate() {
            let g = l.coupling * rho_i;
            let a = SMatrix::<f64, D, D>::identity() - l.projection_jacobian
                + g * structured.compliance[i];
            let lu = LocalLu::factor(&a).ok_or(SchurFailure::SingularBlock(i))?;
            let mut c = lu.solve_matrix(&g);
            if self.symmetric {
                c = (c + c.transpose()) * 0.5;
            }
            self.local_a.push(lu);
            self.local_c.push(c);
            let ar = lu.solve(&block::<D>(r, i));
            self.a_inv_r[D * i..D * i + D].copy_from_slice(ar.as_slice());
        }
        // Values in the order of `new`: masses, then h² Bᵢᵀ Cᵢ Bᵢ per point.
        let n_v = structured.lumped_mass.len();
        self.values[..n_v].copy_from_slice(&structured.lumped_mass);
        let mut pos = n_v;
        for (i, c) in self.local_c.iter().enumerate() {
            let (dofs, bv) = blocks.point(i);
            let m = dofs.len();
            for a in 0..m {
                // (C Bᵢ)[:, b] and Bᵢ[:, a]
                let ba = SVector::<f64, D>::from_fn(|k, _| bv[k * m + a]);
                let cta = c.transpose() * ba;
                for b in 0..m {
                    if self.symmetric && dofs[a] < dofs[b] {
                        continue;
                    }
                    let mut v = 0.0;
                    for k in 0..D {
                        v += cta[k] * bv[k * m + b];
                    }
                    self.values[pos] = h2 * v;
                    pos += 1;
                }
            }
        }
        let k = SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, &self.values)
            .map_err(|e| SchurFailure::Factorization(format!("{e:?}")))?;
        self.rhs.fill(0.0);
        {
            let mut tmp = vec![0.0; n_v];
            blocks.add_transpose(&self.a_inv_r, &mut tmp);
            for (j, v) in tmp.into_iter().enumerate() {
                self.rhs[(j, 0)] = v;
            }
        }
        match &self.factorization {
            Factorization::Cholesky(sym) => {
                let llt = Llt::try_new_with_symbolic(sym.clone(), k.as_ref(), Side::Lower)
                    .map_err(|e| SchurFailure::Factorization(format!("{e:?}")))?;
                llt.solve_in_place(self.rhs.as_mut());
            }
            Factorization::Lu(sym) => {
                let lu = Lu::try_new_with_symbolic(sym.clone(), k.as_ref())
                    .map_err(|e| SchurFailure::Factorization(format!("{e:?}")))?;
                lu.solve_in_place(self.rhs.as_mut());
            }
        }
        let u: Vec<f64> = (0..n_v).map(|j| self.rhs[(j, 0)]).collect();
        for (i, c) in self.local_c.iter().enumerate() {
            let di = block::<D>(&self.a_inv_r, i) - c * blocks.apply_point(i, &u) * h2;
            d[D * i..D * i + D].copy_from_slice(di.as_slice());
        }
        Ok(())
    }
}
