//! The PNG plots of a FEM run: force against displacement, Newton residuals, the plastic
//! strain map.
use std::path::Path;

use crate::model::fem::{Model, State};
use crate::output::{self, MeshView};
use crate::run::RunError;
use crate::scene::Scene;

use super::fields::element_fields;

pub(super) fn write_plots(
    scene: &Scene,
    model: &Model,
    state: &State,
    histories: &[(usize, Vec<f64>)],
    curve: &[(f64, f64)],
    out: &Path,
) -> Result<(), RunError> {
    let title = scene
        .spec
        .title
        .clone()
        .unwrap_or_else(|| "talus run".into());
    if !model.reaction_dofs.is_empty() {
        output::plot_force_displacement(&out.join("force_displacement.png"), curve, &title)?;
    }
    if !histories.is_empty() {
        output::plot_newton_residuals(
            &out.join("newton_residuals.png"),
            histories,
            scene.spec.solver.tolerance,
        )?;
    }
    let (_, plastic) = element_fields(model, state);
    output::plot_field_on_mesh(
        &out.join("plastic_strain.png"),
        &MeshView {
            nodes: &model.mesh.nodes,
            triangles: &model.mesh.triangles,
        },
        None,
        &plastic,
        &format!("cumulative plastic strain at t = {:.4} s", state.time),
        "∫‖ε̇ᵖ‖dt (-)",
    )?;
    Ok(())
}
