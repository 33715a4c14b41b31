//! A 3D finite-element scene run by the run loop (`docs/3d.md`): the model of
//! `model::fem::build3`, and the outputs of 2D (`FemOutputs` at `N = 3`, `D = 6`):
//! `history.csv` with the reported boundary's reaction and settlement, each named
//! boundary's `fx, fy, fz` and each monitor's `ux, uy, uz, vx, vy, vz`, `summary.json`,
//! tetrahedral VTUs with `solution.pvd`, the force–displacement and Newton plots,
//! checkpoints. No PNG field map: a map of a 3D body is a ParaView job.
use std::time::Instant;

use talus_engine::Stepper;

use super::{FemOutputs, RunSummary};
use crate::model::fem::{initial_state_3d, model_3d};
use crate::run::checkpoint::Checkpoint;
use crate::run::{RunError, RunOptions, Span};
use crate::scene::Scene3;

/// Runs the 3D `scene` to its end (or from `resumed`'s checkpoint).
pub fn run_scene_3d(
    scene: &Scene3,
    options: &RunOptions,
    resumed: Option<Checkpoint<serde_json::Value>>,
) -> Result<RunSummary<6>, RunError> {
    if scene.spec.stability.is_some() {
        return Err(scene
            .error(
                "stability",
                "a factor-of-safety scene runs by talus::analysis::stability::run",
            )
            .into());
    }
    let start = Instant::now();
    let model = model_3d(scene)?;
    let state = initial_state_3d(scene, &model)?;
    let mut stepper = Stepper::new(&model, scene.spec.solver.fem());
    tracing::info!(
        points = model.n_points(),
        free_dofs = model.assembly.dofs().n_free(),
        elements = crate::model::fem::element_count(&model),
        materials = model.materials.len(),
        "3D model built"
    );
    let mut outputs = FemOutputs::new(scene, &model, options, None)?;
    let stepped = super::super::execute(
        &mut stepper,
        state,
        resumed,
        &mut outputs,
        Span::whole(scene.spec.time.steps),
        scene.spec.time.step,
        options,
        (scene.path.as_deref(), &scene.source),
    )?;
    if let Some((step, source)) = stepped.failure {
        return Err(RunError::Step { step, source });
    }
    Ok(RunSummary {
        displacements: outputs.curve[1..].iter().map(|c| c.0).collect(),
        records: stepped.reports,
        seconds: start.elapsed().as_secs_f64(),
        final_state: stepped.state,
    })
}
