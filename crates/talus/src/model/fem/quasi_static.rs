//! The quasi-static limit of eq. 15 by mass scaling: the lumped mass of every degree of
//! freedom becomes `m_j = r · h² · K_jj`, `K = Bᵀ S⁻¹ B` the elastic stiffness, so that the
//! inertia `M/h²` of a step is the fraction `r` (`inertia_ratio`) of each node's elastic
//! stiffness whatever the density, the moduli, the mesh size and `h`
//! (`docs/derivations.md`, 'The quasi-static limit'). The masses are talus-fem's
//! `Model::quasi_static_masses`; here, the scene's choice and its bounds.
use talus_fem::{Dimension, Mandel, Model};

use crate::scene::{AnalysisKind, SceneDocument, SceneError, SceneSpec, SceneVector};

/// `inertia_ratio` when the scene gives none: inertia a ten-millionth of the stiffness. The
/// paper footing's Newton iterations are those of its dynamic run at 1e-4 to 1e-8, and fail
/// to converge at 1e-12 below about 1e-10 (`docs/derivations.md`, 'The quasi-static limit').
pub const DEFAULT_INERTIA_RATIO: f64 = 1e-7;

/// The largest `inertia_ratio`: where inertia starts to matter. Measured on
/// `scenes/footing.toml` made quasi-static (300 steps, `docs/scenes.md`, 'Analysis'), the
/// reaction against the run at 1e-7, relative to the limit load: up to `r = 1.5e-4` the
/// error is the start's transient, proportional to `r` (5.7 r at step 1, 6.4 r at 0.5 mm)
/// and at most 3e-6 over the plateau; from `r = 2e-4` the mechanism oscillates and the
/// plateau is off by 4e-4 (2e-4), 3.6e-3 (1e-3), 3.2e-2 (1e-2), and the reaction by 2 to
/// 4.5 times at `r = 1` (no limit load found).
pub const MAX_INERTIA_RATIO: f64 = 1e-4;

/// The smallest `inertia_ratio`: the velocity is recovered from the force imbalance over
/// the mass, a rounding of about `1e-16 / r` relative per step (`docs/derivations.md`,
/// 'Why r cannot be taken to 0'). The same footing at 1e-12 stops at step 111 (Newton);
/// at 1e-14 its reaction stays at the surcharge's for 59 steps before failing, at 1e-16 it
/// "collapses" at step 57; 1e-300 gave NaN at the first step.
pub const MIN_INERTIA_RATIO: f64 = 1e-12;

/// For a quasi-static scene, replaces the assembly's lumped masses by the scaled ones of
/// `Model::quasi_static_masses` (the weight keeps the material's density: it was assembled
/// before). A dynamic scene keeps its masses; `inertia_ratio` is then refused.
pub fn scale_masses<V: SceneVector, const D: usize>(
    scene: &SceneDocument<SceneSpec<V>>,
    model: &mut Model<D>,
) -> Result<(), SceneError>
where
    Mandel<D>: Dimension,
{
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
    if !(r.is_finite() && (MIN_INERTIA_RATIO..=MAX_INERTIA_RATIO).contains(&r)) {
        return Err(scene.error(
            "analysis.inertia_ratio",
            format!(
                "{r:e} must be within [{MIN_INERTIA_RATIO:e}, {MAX_INERTIA_RATIO:e}] \
                 (inertia as a fraction of the stiffness): above, inertia changes the \
                 quasi-static answer (the footing's limit load oscillates from 2e-4 and \
                 doubles near 1); below, the round-off of the velocity, about 1e-16/r, does"
            ),
        ));
    }
    let h = scene.spec.time.step;
    // The masses `r h² K_jj` and the step's `h² M⁻¹` must be numbers: h² neither
    // underflows (h = 1e-300 s gave masses of 0) nor overflows.
    if !(h * h).is_normal() || !(1.0 / (h * h)).is_normal() {
        return Err(scene.error(
            "time.step",
            format!(
                "{h:e} s: a quasi-static step's masses are inertia_ratio · h² · K_jj, and h² = \
                 {:e} s² is not a normal f64; give a step within [1e-150, 1e150] s (time is \
                 only a load parameter here: scale the velocities and ramps with it)",
                h * h
            ),
        ));
    }
    let (free, prescribed) = model.quasi_static_masses(h, r).ok_or_else(|| {
        scene.error(
            "analysis.kind",
            "a degree of freedom strains no Gauss point: no stiffness to scale its mass by",
        )
    })?;
    if let Some(m) = free
        .iter()
        .chain(&prescribed)
        .find(|m| !(m.is_normal() && (1.0 / **m).is_normal()))
    {
        return Err(scene.error(
            "time.step",
            format!(
                "{h:e} s with inertia_ratio = {r:e} makes a quasi-static mass r h² K_jj of \
                 {m:e} kg/m, beyond the range of f64; give a step nearer 1 s (time is only a \
                 load parameter here: scale the velocities and ramps with it)"
            ),
        ));
    }
    model.assembly.lumped_mass_free = free;
    model.assembly.lumped_mass_prescribed = prescribed;
    Ok(())
}
