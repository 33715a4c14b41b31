//! The quasi-static limit of eq. 15 by mass scaling: the lumped mass of every degree of
//! freedom becomes `m_j = r · h² · K_jj`, `K = Bᵀ S⁻¹ B` the elastic stiffness, so that the
//! inertia `M/h²` of a step is the fraction `r` (the inertia ratio) of each node's elastic
//! stiffness whatever the density, the moduli, the mesh size and `h`
//! (`docs/derivations.md`, 'The quasi-static limit'). In 2D and 3D alike.
use nalgebra::{SMatrix, SVector};

use crate::dimension::{Dimension, Mandel};
use crate::model::Model;

impl<const D: usize> Model<D>
where
    Mandel<D>: Dimension,
{
    /// The quasi-static lumped masses `r h² K_jj` of the free and of the prescribed dofs,
    /// with `K_jj = Σ_p b_pjᵀ S_p⁻¹ b_pj` (`b_pj` point `p`'s rows of column `j` of `B`,
    /// and `S_p = V_p S₀` with the point's material); `None` if a dof strains nothing (no
    /// stiffness to scale by) or a compliance is singular.
    pub fn quasi_static_masses(&self, h: f64, inertia_ratio: f64) -> Option<(Vec<f64>, Vec<f64>)> {
        let per_material: Vec<SMatrix<f64, D, D>> = self
            .compliances
            .iter()
            .map(|c| c.try_inverse())
            .collect::<Option<_>>()?;
        let stiffness: Vec<&SMatrix<f64, D, D>> = self
            .point_material
            .iter()
            .map(|&m| &per_material[m])
            .collect();
        let assembly = &self.assembly;
        let (volumes, scale) = (&assembly.gauss_volumes, h * h * inertia_ratio);
        let (f, p) = (&assembly.b_free, &assembly.b_prescribed);
        Some((
            column_masses(
                (f.symbolic().col_ptr(), f.symbolic().row_idx(), f.val()),
                volumes,
                &stiffness,
                scale,
            )?,
            column_masses(
                (p.symbolic().col_ptr(), p.symbolic().row_idx(), p.val()),
                volumes,
                &stiffness,
                scale,
            )?,
        ))
    }
}

/// `scale · K_jj` per column of a column-major `B` (`cp`, `ri`, `val`) of `D` rows per point.
fn column_masses<const D: usize>(
    (cp, ri, val): (&[usize], &[usize], &[f64]),
    volumes: &[f64],
    stiffness: &[&SMatrix<f64, D, D>],
    scale: f64,
) -> Option<Vec<f64>> {
    (0..cp.len() - 1)
        .map(|j| {
            // A column's entries of one point are its (up to) D Mandel rows.
            let mut k_jj = 0.0;
            let mut point = usize::MAX;
            let mut bp = SVector::<f64, D>::zeros();
            let mut flush = |p: usize, bp: &SVector<f64, D>| {
                if p != usize::MAX {
                    k_jj += bp.dot(&(stiffness[p] * bp)) / volumes[p];
                }
            };
            for k in cp[j]..cp[j + 1] {
                let p = ri[k] / D;
                if p != point {
                    flush(point, &bp);
                    point = p;
                    bp = SVector::zeros();
                }
                bp[ri[k] % D] += val[k];
            }
            flush(point, &bp);
            (k_jj.is_finite() && k_jj > 0.0).then_some(scale * k_jj)
        })
        .collect()
}
