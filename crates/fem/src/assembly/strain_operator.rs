//! The discrete strain operator `B` (eq. 12, 15): row block `p` (4 rows, Mandel plane
//! strain `(xx, yy, zz, √2 xy)`, tension positive) maps nodal velocities to
//! `V_p · ε̇(x_p)`, with `ε̇ = sym ∇v`. So `B v` is the volume-weighted strain rate,
//! `Bᵀσ` the internal force (N per metre of thickness), and `W = S + h² B M⁻¹ Bᵀ` of
//! eq. 16 is symmetric when `S` carries `V_p` too. The zz row is structurally empty
//! (plane strain: `ε̇zz = 0`) but kept, because `σzz` enters the yield cone.
use faer::sparse::{SparseColMat, Triplet};

use super::gauss::GaussData;
use crate::dofs::{Dof, DofMap};
use crate::error::FemError;

/// Mandel rows per Gauss point.
pub const MANDEL: usize = 4;

type Sparse = SparseColMat<usize, f64>;

/// `(B_free, B_prescribed)`.
pub(crate) fn strain_operator(
    gauss: &GaussData,
    dofs: &DofMap,
) -> Result<(Sparse, Sparse), FemError> {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let mut free = Vec::new();
    let mut prescribed = Vec::new();
    for p in 0..gauss.len() {
        let v = gauss.volumes[p];
        let r = MANDEL * p;
        for (node, _, g) in gauss.point(p) {
            // ε̇xx = ∂vx/∂x, ε̇yy = ∂vy/∂y, √2 ε̇xy = (∂vx/∂y + ∂vy/∂x)/√2
            let entries = [
                (0, [(r, g[0]), (r + 3, s * g[1])]),
                (1, [(r + 1, g[1]), (r + 3, s * g[0])]),
            ];
            for (comp, rows) in entries {
                let dof = dofs.dof(node, comp).ok_or_else(|| {
                    FemError::invalid("dofs", format!("node {node} is not in the dof map"))
                })?;
                for (row, value) in rows {
                    match dof {
                        Dof::Free(j) => free.push(Triplet::new(row, j, v * value)),
                        Dof::Prescribed(j) => prescribed.push(Triplet::new(row, j, v * value)),
                    }
                }
            }
        }
    }
    let rows = MANDEL * gauss.len();
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
