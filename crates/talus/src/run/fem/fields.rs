//! The element fields of a FEM state in a VTU file (`docs/scenes.md`, 'Outputs').
use std::path::Path;

use crate::model::fem::{Model, State};
use crate::output::{self, FieldSnapshot, MeshView, OutputError};
use crate::run::RunError;

/// Per-element averages of the Gauss-point stress and plastic strain.
pub(super) fn element_fields(model: &Model, state: &State) -> (Vec<[f64; 4]>, Vec<f64>) {
    let n_el = model.mesh.triangles.len();
    let mut stress = vec![[0.0; 4]; n_el];
    let mut plastic = vec![0.0; n_el];
    let mut count = vec![0usize; n_el];
    for (p, &e) in model.assembly.gauss_element.iter().enumerate() {
        for (s, v) in stress[e].iter_mut().zip(&state.sigma[4 * p..4 * p + 4]) {
            *s += v;
        }
        plastic[e] += state.plastic_strain[p];
        count[e] += 1;
    }
    for e in 0..n_el {
        let c = count[e].max(1) as f64;
        stress[e].iter_mut().for_each(|s| *s /= c);
        plastic[e] /= c;
    }
    (stress, plastic)
}

pub(super) fn write_snapshot(model: &Model, state: &State, path: &Path) -> Result<(), RunError> {
    let (stress, plastic) = element_fields(model, state);
    let material = model.element_materials();
    // The pore pressure at the state's time, per element (its points' mean).
    let pore_pressure = model.pore_pressure.iter().any(|p| *p != 0.0).then(|| {
        let f = model
            .pore_pressure_ramp
            .as_ref()
            .map_or(1.0, |r| r.at(state.time));
        let mut sum = vec![0.0; model.mesh.triangles.len()];
        let mut count = vec![0usize; sum.len()];
        for (p, &e) in model.assembly.gauss_element.iter().enumerate() {
            sum[e] += f * model.pore_pressure[p];
            count[e] += 1;
        }
        sum.iter()
            .zip(&count)
            .map(|(s, &c)| s / c.max(1) as f64)
            .collect::<Vec<f64>>()
    });
    let velocity = model
        .assembly
        .dofs()
        .scatter(&state.velocity_free, &state.velocity_prescribed)
        .map_err(|e| {
            RunError::Output(OutputError::Invalid {
                field: "velocity",
                message: e.to_string(),
            })
        })?;
    output::write_vtu(
        path,
        &FieldSnapshot {
            mesh: MeshView {
                nodes: &model.mesh.nodes,
                triangles: &model.mesh.triangles,
            },
            time: state.time,
            displacement: &state.displacement,
            velocity: &velocity,
            stress: &stress,
            plastic_strain: &plastic,
            material: Some(&material),
            pore_pressure: pore_pressure.as_deref(),
        },
    )?;
    Ok(())
}

