//! A 3D finite-element scene run by the run loop (`docs/3d.md`): the model of
//! `model::fem::build3`, and the outputs of 2D (`FemOutputs` at `N = 3`, `D = 6`):
//! `history.csv` with the reported boundary's reaction and settlement, each named
//! boundary's `fx, fy, fz` and each monitor's `ux, uy, uz, vx, vy, vz`, `summary.json`,
//! tetrahedral VTUs with `solution.pvd`, the force–displacement and Newton plots,
//! checkpoints, stages (`[[stage]]`, as in 2D). No PNG field map: a map of a 3D body is a ParaView job.
use std::time::Instant;

use super::{not_a_stability_scene, run_model, RunSummary};
use crate::model::fem::model_3d;
use crate::model::fem::stages::Stages;
use crate::run::checkpoint::Checkpoint;
use crate::run::{RunError, RunOptions};
use crate::scene::Scene3;

/// Runs the 3D `scene` to its end (or from `resumed`'s checkpoint).
pub fn run_scene_3d(
    scene: &Scene3,
    options: &RunOptions,
    resumed: Option<Checkpoint<serde_json::Value>>,
) -> Result<RunSummary<6>, RunError> {
    if let Some(stages) = Stages::<6>::of(scene)? {
        return super::stages::run(scene, stages, options, resumed);
    }
    not_a_stability_scene(scene)?;
    let start = Instant::now();
    let model = model_3d(scene)?;
    run_model(scene, &model, options, resumed, start)
}
