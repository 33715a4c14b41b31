use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use nalgebra::{SMatrix, SVector};
use rayon::prelude::*;
use talus_bipotential::NaturalMapLinearization;

use super::schur_factor::{Factorized, LuChoice, SchurFactor};
use super::schur_pattern::{schur_pattern, SchurPattern};
use crate::local_lu::LocalLu;
use crate::operator::{block, PointBlocks, Structured};

/// The velocity-sized Newton system of the notes §5:
/// `(M + h² Bᵀ C B) u = Bᵀ A⁻¹ r`, `d = A⁻¹ r − h² C B u`,
/// with per point `A_i = I − D_i + ρ_i G_i S_i` and `C_i = ρ_i A_i⁻¹ G_i`.
/// The pattern of K is that of `Bᵀ B` plus the diagonal: fixed, factored symbolically once.
pub(crate) struct SchurSystem<const D: usize> {
    symmetric: bool,
    symbolic: SymbolicSparseColMat<usize>,
    /// Where each (row, column) pair of `new`'s enumeration lands in the CSC values:
    /// the matrix is refilled in place every iteration (duplicates add up).
    positions: Vec<usize>,
    csc_values: Vec<f64>,
    factorization: SchurFactor,
    local_c: Vec<SMatrix<f64, D, D>>,
    rhs: Vec<f64>,
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
        let SchurPattern {
            symbolic,
            positions,
        } = schur_pattern(n_v, blocks, symmetric)?;
        let row_idx = symbolic.row_idx();
        let nnz = row_idx.len();
        let factorization = SchurFactor::analyse(symbolic.as_ref(), symmetric)?;
        Ok(Self {
            symmetric,
            symbolic,
            positions,
            csc_values: vec![0.0; nnz],
            factorization,
            local_c: vec![SMatrix::zeros(); n_points],
            rhs: vec![0.0; n_v],
            a_inv_r: vec![0.0; D * n_points],
        })
    }

    /// Writes the direction into `d`, factorizing K with `choice` (Cholesky if symmetric).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn solve(
        &mut self,
        structured: &Structured<D>,
        blocks: &PointBlocks<D>,
        lin: &[NaturalMapLinearization<D>],
        rho: &[f64],
        r: &[f64],
        d: &mut [f64],
        choice: LuChoice,
        parallel: bool,
    ) -> Result<Factorized, SchurFailure> {
        let h2 = structured.h * structured.h;
        // Per point and independent: spread over threads when `parallel` (the results do
        // not depend on it); the first singular block in point order is reported.
        let symmetric = self.symmetric;
        let one = |i: usize, c: &mut SMatrix<f64, D, D>, ar: &mut [f64]| -> bool {
            let g = lin[i].coupling * rho[i];
            let a = SMatrix::<f64, D, D>::identity() - lin[i].projection_jacobian
                + g * structured.compliance[i];
            let Some(lu) = LocalLu::factor(&a) else {
                return false;
            };
            *c = lu.solve_matrix(&g);
            if symmetric {
                *c = (*c + c.transpose()) * 0.5;
            }
            ar.copy_from_slice(lu.solve(&block::<D>(r, i)).as_slice());
            true
        };
        let regular: Vec<bool> = if parallel {
            self.local_c
                .par_iter_mut()
                .zip(self.a_inv_r.par_chunks_mut(D))
                .enumerate()
                .with_min_len(256)
                .map(|(i, (c, ar))| one(i, c, ar))
                .collect()
        } else {
            self.local_c
                .iter_mut()
                .zip(self.a_inv_r.chunks_mut(D))
                .enumerate()
                .map(|(i, (c, ar))| one(i, c, ar))
                .collect()
        };
        if let Some(i) = regular.iter().position(|ok| !ok) {
            return Err(SchurFailure::SingularBlock(i));
        }
        // Values in the order of `new`: masses, then h² Bᵢᵀ Cᵢ Bᵢ per point, summed in
        // place into the CSC values.
        let n_v = structured.lumped_mass.len();
        self.csc_values.fill(0.0);
        for (p, m) in self.positions[..n_v].iter().zip(&structured.lumped_mass) {
            self.csc_values[*p] += m;
        }
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
                    self.csc_values[self.positions[pos]] += h2 * v;
                    pos += 1;
                }
            }
        }
        let k = SparseColMatRef::new(self.symbolic.as_ref(), &self.csc_values);
        self.rhs.fill(0.0);
        blocks.add_transpose(&self.a_inv_r, &mut self.rhs);
        let used = self
            .factorization
            .solve(k, &mut self.rhs, choice)
            .map_err(SchurFailure::Factorization)?;
        let u = &self.rhs;
        let (local_c, a_inv_r) = (&self.local_c, &self.a_inv_r);
        let back = |(i, di): (usize, &mut [f64])| {
            let v = block::<D>(a_inv_r, i) - local_c[i] * blocks.apply_point(i, u) * h2;
            di.copy_from_slice(v.as_slice());
        };
        if parallel {
            d.par_chunks_mut(D)
                .enumerate()
                .with_min_len(256)
                .for_each(back);
        } else {
            d.chunks_mut(D).enumerate().for_each(back);
        }
        Ok(used)
    }
}
