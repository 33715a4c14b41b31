//! The quasi-static limit of eq. 15 by mass scaling: the lumped mass of every degree of
//! freedom becomes `m_j = r · h² · K_jj`, `K = Bᵀ S⁻¹ B` the elastic stiffness, so that the
//! inertia `M/h²` of a step is the fraction `r` (`inertia_ratio`) of each node's elastic
//! stiffness whatever the density, the moduli, the mesh size and `h`
//! (`docs/derivations.md`, 'The quasi-static limit').
use nalgebra::{SMatrix, SVector};
use talus_fem::assembly::MANDEL;
use talus_fem::Model;

use crate::scene::{AnalysisKind, Scene, SceneError};

/// `inertia_ratio` when the scene gives none: inertia a millionth of the stiffness. The
/// paper footing's Newton iterations are those of its dynamic run at 1e-4 to 1e-8, and fail
/// to converge at 1e-12 below about 1e-10 (`docs/derivations.md`, 'The quasi-static limit').
pub const DEFAULT_INERTIA_RATIO: f64 = 1e-7;

/// The quasi-static lumped masses `r h² K_jj` of the free and of the prescribed dofs, with
/// `K_jj = Σ_p b_pjᵀ S_p⁻¹ b_pj` (`b_pj` point `p`'s rows of column `j` of `B`, and
/// `S_p = V_p S₀` with the point's material); `None` if a dof strains nothing (no
/// stiffness to scale by).
pub fn quasi_static_masses(
    model: &Model,
    h: f64,
    inertia_ratio: f64,
) -> Option<(Vec<f64>, Vec<f64>)> {
    let per_material: Vec<SMatrix<f64, 4, 4>> = model
        .compliances
        .iter()
        .map(|c| c.try_inverse())
        .collect::<Option<_>>()?;
    let stiffness: Vec<&SMatrix<f64, 4, 4>> = model
        .point_material
        .iter()
        .map(|&m| &per_material[m])
        .collect();
    let assembly = &model.assembly;
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

/// `scale · K_jj` per column of a column-major `B` (`cp`, `ri`, `val`).
fn column_masses(
    (cp, ri, val): (&[usize], &[usize], &[f64]),
    volumes: &[f64],
    stiffness: &[&SMatrix<f64, 4, 4>],
    scale: f64,
) -> Option<Vec<f64>> {
    (0..cp.len() - 1)
        .map(|j| {
            // A column's entries of one point are its (up to) 4 Mandel rows.
            let mut k_jj = 0.0;
            let mut point = usize::MAX;
            let mut bp = SVector::<f64, 4>::zeros();
            let mut flush = |p: usize, bp: &SVector<f64, 4>| {
                if p != usize::MAX {
                    k_jj += bp.dot(&(stiffness[p] * bp)) / volumes[p];
                }
            };
            for k in cp[j]..cp[j + 1] {
                let p = ri[k] / MANDEL;
                if p != point {
                    flush(point, &bp);
                    point = p;
                    bp = SVector::zeros();
                }
                bp[ri[k] % MANDEL] += val[k];
            }
            flush(point, &bp);
            (k_jj.is_finite() && k_jj > 0.0).then_some(scale * k_jj)
        })
        .collect()
}

/// For a quasi-static scene, replaces the assembly's lumped masses by the scaled ones of
/// [`quasi_static_masses`] (the weight keeps the material's density: it was assembled
/// before). A dynamic scene keeps its masses; `inertia_ratio` is then refused.
pub fn scale_masses(scene: &Scene, model: &mut Model) -> Result<(), SceneError> {
    let analysis = &scene.spec.analysis;
    if analysis.kind == AnalysisKind::Dynamic {
        if let Some(r) = analysis.inertia_ratio {
            return Err(scene.error(
                "analysis.inertia_ratio",
                format!("{r} applies to kind = \"quasi_static\" only"),
            ));
        }
        return Ok(());
    }
    let r = analysis.inertia_ratio.unwrap_or(DEFAULT_INERTIA_RATIO);
    if !(r.is_finite() && r > 0.0 && r <= 1.0) {
        return Err(scene.error(
            "analysis.inertia_ratio",
            format!("{r} must be finite, > 0 and <= 1 (inertia as a fraction of the stiffness)"),
        ));
    }
    let h = scene.spec.time.step;
    let (free, prescribed) = quasi_static_masses(model, h, r).ok_or_else(|| {
        scene.error(
            "analysis.kind",
            "a degree of freedom strains no Gauss point: no stiffness to scale its mass by",
        )
    })?;
    model.assembly.lumped_mass_free = free;
    model.assembly.lumped_mass_prescribed = prescribed;
    Ok(())
}
