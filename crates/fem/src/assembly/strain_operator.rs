//! The discrete strain operator `B` (eq. 12, 15): row block `p` (`D` rows, Mandel; plane
//! strain `(xx, yy, zz, √2 xy)`, 3D `(xx, yy, zz, √2 yz, √2 xz, √2 xy)`, tension positive)
//! maps nodal velocities to `V_p · ε̇(x_p)`, with `ε̇ = sym ∇v`. So `B v` is the
//! volume-weighted strain rate, `Bᵀσ` the internal force (N per metre of thickness in
//! plane strain), and `W = S + h² B M⁻¹ Bᵀ` of eq. 16 is symmetric when `S` carries `V_p`
//! too. In plane strain the zz row is structurally empty (`ε̇zz = 0`) but kept, because
//! `σzz` enters the yield cone. In axisymmetry (`x = r`, `y` the axis,
//! `docs/axisymmetry.md`) the third row is the hoop strain rate `ε̇θθ = v_r / r`, and `V_p`
//! carries `r_p`: the row's entries `V_p N_a(x_p) / r_p` are those of `∫ ε̇θθ r dr dy`.
//! Each dimension's rows are [`Dimension::strain_rows`].
use faer::sparse::{SparseColMat, Triplet};

use super::gauss::GaussData;
use crate::dimension::{Dimension, Mandel};
use crate::dofs::{Dof, DofMap};
use crate::error::FemError;

/// Mandel rows per Gauss point in plane strain and axisymmetry.
pub const MANDEL: usize = 4;

type Sparse = SparseColMat<usize, f64>;

/// `(B_free, B_prescribed)` with `D` rows per point.
pub(crate) fn strain_operator<const D: usize>(
    gauss: &GaussData,
    dofs: &DofMap,
) -> Result<(Sparse, Sparse), FemError>
where
    Mandel<D>: Dimension,
{
    let mut free = Vec::new();
    let mut prescribed = Vec::new();
    for p in 0..gauss.len() {
        let v = gauss.volumes[p];
        let r = D * p;
        for (node, n, g) in gauss.point(p) {
            for comp in 0..<Mandel<D> as Dimension>::COMPONENTS {
                let rows = <Mandel<D> as Dimension>::strain_rows(
                    gauss.geometry,
                    n,
                    g,
                    gauss.positions[p],
                    comp,
                );
                let dof = dofs.dof(node, comp).ok_or_else(|| {
                    FemError::invalid("dofs", format!("node {node} is not in the dof map"))
                })?;
                for (row, value) in rows.into_iter().flatten() {
                    match dof {
                        Dof::Free(j) => free.push(Triplet::new(r + row, j, v * value)),
                        Dof::Prescribed(j) => prescribed.push(Triplet::new(r + row, j, v * value)),
                    }
                }
            }
        }
    }
    let rows = D * gauss.len();
    let build = |n: usize, t: &[Triplet<usize, usize, f64>]| {
        SparseColMat::try_new_from_triplets(rows, n, t)
            .map_err(|e| FemError::invalid("B", format!("sparse assembly failed: {e:?}")))
    };
    Ok((
        build(dofs.n_free(), &free)?,
        build(dofs.n_prescribed(), &prescribed)?,
    ))
}

/// `y += A x` for a column-major sparse `A`.
pub fn add_mul(a: &SparseColMat<usize, f64>, x: &[f64], y: &mut [f64]) {
    let (cp, ri, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    for (j, xj) in x.iter().enumerate() {
        for k in cp[j]..cp[j + 1] {
            y[ri[k]] += val[k] * xj;
        }
    }
}

/// `y += Aᵀ x` for a column-major sparse `A`.
pub fn add_mul_transpose(a: &SparseColMat<usize, f64>, x: &[f64], y: &mut [f64]) {
    let (cp, ri, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    for (j, yj) in y.iter_mut().enumerate() {
        *yj += (cp[j]..cp[j + 1]).map(|k| val[k] * x[ri[k]]).sum::<f64>();
    }
}
