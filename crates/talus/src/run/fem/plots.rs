//! The PNG plots of a FEM run: force against displacement, Newton residuals, and in 2D
//! the plastic strain map (a map of a 3D body is a ParaView job, from the VTUs).
use std::path::Path;

use talus_fem::{Dimension, Mandel, Model, State};

use crate::output::{self, significant, FieldMap, MeshView};
use crate::run::RunError;
use crate::scene::{AnalysisKind, SceneOf, SceneVector};

use super::fields::element_fields;

/// The plastic strain map's colours stop at this percentile of the elements' values: the
/// footing's corners otherwise take the whole scale.
const CLIP_PERCENTILE: f64 = 99.0;
/// Plastic strains closer than this are not told apart: an elastic step leaves round-off
/// of about 1e-15, and a map of it is one colour reading 0.
const PLASTIC_STRAIN_RESOLUTION: f64 = 1e-10;

pub(super) fn write_plots<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
    model: &Model<D>,
    state: &State<D>,
    histories: &[(usize, Vec<f64>)],
    curve: &[(f64, f64)],
    out: &Path,
) -> Result<(), RunError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
    Model<D>: PlasticStrainMap<D>,
{
    let title = scene
        .spec
        .title
        .clone()
        .unwrap_or_else(|| "talus run".into());
    let force_unit = scene.spec.analysis.geometry.force_unit();
    if !model.reaction_dofs.is_empty() {
        output::plot_force_displacement_with_unit(
            &out.join("force_displacement.png"),
            curve,
            &title,
            force_unit,
        )?;
    }
    if !histories.is_empty() {
        output::plot_newton_residuals(
            &out.join("newton_residuals.png"),
            histories,
            scene.spec.solver.tolerance,
        )?;
    }
    let reported = (!model.reaction_dofs.is_empty())
        .then(|| curve.last().copied())
        .flatten();
    let subtitle = format!(
        "cumulative plastic strain {}",
        when(scene, state, reported, curve.len().saturating_sub(1))
    );
    model.plastic_strain_map(state, &out.join("plastic_strain.png"), &title, &subtitle)
}

/// The map of the cumulative plastic strain over the body: 2D only.
pub(super) trait PlasticStrainMap<const D: usize>
where
    Mandel<D>: Dimension,
{
    fn plastic_strain_map(
        &self,
        state: &State<D>,
        path: &Path,
        title: &str,
        subtitle: &str,
    ) -> Result<(), RunError>;
}

impl PlasticStrainMap<4> for Model<4> {
    fn plastic_strain_map(
        &self,
        state: &State<4>,
        path: &Path,
        title: &str,
        subtitle: &str,
    ) -> Result<(), RunError> {
        let (_, plastic) = element_fields(self, state);
        output::plot_field_map(
            path,
            &MeshView {
                nodes: &self.mesh.nodes,
                elements: &self.mesh.triangles,
            },
            None,
            &plastic,
            &FieldMap {
                title,
                subtitle: Some(subtitle),
                label: "∫‖ε̇ᵖ‖dt (-)",
                clip_percentile: Some(CLIP_PERCENTILE),
                resolution: PLASTIC_STRAIN_RESOLUTION,
            },
        )?;
        Ok(())
    }
}

/// A 3D body's map is a ParaView job, from the VTUs.
impl PlasticStrainMap<6> for Model<6> {
    fn plastic_strain_map(&self, _: &State<6>, _: &Path, _: &str, _: &str) -> Result<(), RunError> {
        Ok(())
    }
}

/// When the map is drawn, in the words of the scene: a quasi-static scene's time is a load
/// parameter, so its map is dated by the reported boundary's settlement and load (or the
/// load step without one); a dynamic scene's by its time, with the settlement and load.
fn when<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
    state: &State<D>,
    reported: Option<(f64, f64)>,
    step: usize,
) -> String
where
    Mandel<D>: Dimension,
    [f64; N]: SceneVector,
{
    let boundary = scene.spec.output.reaction.as_deref().unwrap_or("reported");
    let unit = scene.spec.analysis.geometry.force_unit();
    let loaded = reported.map(|(u, f)| {
        format!(
            "{boundary} settlement {} mm, load {} k{unit}",
            significant(u * 1e3, 4),
            significant(f * 1e-3, 4)
        )
    });
    match (scene.spec.analysis.kind, loaded) {
        (AnalysisKind::QuasiStatic, Some(loaded)) => format!("at {loaded}"),
        (AnalysisKind::QuasiStatic, None) => {
            format!("after load step {step} of {}", scene.spec.total_steps())
        }
        (AnalysisKind::Dynamic, Some(loaded)) => {
            format!("at t = {} s ({loaded})", significant(state.time, 4))
        }
        (AnalysisKind::Dynamic, None) => format!("at t = {} s", significant(state.time, 4)),
    }
}
