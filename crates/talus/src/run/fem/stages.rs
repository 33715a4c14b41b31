//! A staged FEM run (`[[stage]]`, `docs/scenes.md`, 'Stages'): each stage's model from
//! `model::fem::stages`, the state carried over, the out-of-balance force released over
//! the stage's steps, one run loop per stage writing one history, one VTU series and one
//! summary, and the factor of safety where a stage asks for it.
use std::time::Instant;

use talus_engine::Stepper;
use talus_fem::{Dimension, ElementMesh, Mandel};

use super::plots::PlasticStrainMap;
use super::{Carried, FemOutputs, RunSummary, StageOutputs};
use crate::analysis::stability::{self, StabilityScene};
use crate::model::fem::stages::{add_release, carry, out_of_balance, StageModel, Stages};
use crate::model::fem::{Model, State};
use crate::output::{RunStatus, StageSummary};
use crate::run::checkpoint::{self, Checkpoint, CheckpointError};
use crate::run::{RunError, RunOptions, RunOutputs, Span};
use crate::scene::{SceneOf, SceneVector};

/// The force a stage releases (`model::fem::stages::out_of_balance`, free dofs, N/m) from
/// 1 at `t0` to 0 at `t1` (s).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Release {
    pub force: Vec<f64>,
    pub t0: f64,
    pub t1: f64,
}

/// Runs every stage of `stages` (from the checkpoint's when `resumed`), in 2D or 3D.
pub fn run<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
    stages: Stages<D>,
    options: &RunOptions,
    resumed: Option<Checkpoint<serde_json::Value>>,
) -> Result<RunSummary<D>, RunError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
    Model<D>: PlasticStrainMap<D>,
    SceneOf<N>: StabilityScene<D>,
    crate::model::fem::MeshOf<D>: crate::model::fem::SceneMesh<D>,
{
    let start = Instant::now();
    let h = scene.spec.time.step;
    let total = scene.spec.total_steps();
    // A resumed run starts in the checkpoint's stage, with the force it was releasing.
    let (first, saved) = match &resumed {
        None => (0, None),
        Some(c) => {
            let saved: Option<StageOutputs> = c
                .outputs
                .get("stage")
                .cloned()
                .and_then(|v| serde_json::from_value(v).ok());
            let k = saved
                .as_ref()
                .and_then(|s| stages.plans.iter().position(|p| p.spec.name == s.name))
                .ok_or_else(|| CheckpointError::Corrupt {
                    path: checkpoint::path(&options.out_dir),
                    why: "it names no stage of this scene".into(),
                })?;
            (k, saved)
        }
    };
    let mut resumed = resumed;
    let mut previous: Option<(StageModel<D>, State<D>)> = None;
    let mut carried: Option<Carried> = None;
    let mut records = Vec::new();
    for (k, plan) in stages.plans.iter().enumerate().skip(first) {
        let mut stage = stages.model(scene, k)?;
        let (state, release) = match &previous {
            // Resumed: the checkpoint holds the state (`execute` reads it); this one only
            // gives its shape (no K₀ check: the stage may hold ground above the surface).
            None if resumed.is_some() => {
                let dofs = stage.model.assembly.dofs();
                (
                    State::at_rest(
                        stage.model.n_points(),
                        dofs.n_free(),
                        dofs.n_prescribed(),
                        stage.model.mesh.node_positions().len(),
                    ),
                    saved.as_ref().and_then(|s| s.release.clone()),
                )
            }
            None => (crate::model::fem::initial_state(scene, &stage.model)?, None),
            Some((prev, prev_state)) => {
                let state = carry(prev, prev_state, &stage, plan.spec.reset_displacements)
                    .map_err(|e| scene.error(&format!("stage[{k}]"), e))?;
                let force = out_of_balance(&stage.model, &state)
                    .map_err(|e| scene.error(&format!("stage[{k}]"), e))?;
                let t0 = state.time;
                let release = Release {
                    force,
                    t0,
                    t1: t0 + h * plan.spec.steps as f64,
                };
                (state, Some(release))
            }
        };
        if let Some(r) = &release {
            add_release(&mut stage.model, r.force.clone(), r.t0, r.t1)
                .map_err(|e| scene.error(&format!("stage[{k}].steps"), e))?;
        }
        tracing::info!(
            stage = plan.spec.name.as_str(),
            elements = stage.elements.len(),
            free_dofs = stage.model.assembly.dofs().n_free(),
            steps = plan.spec.steps,
            "stage"
        );
        let column = StageOutputs {
            index: k,
            name: plan.spec.name.clone(),
            last_step: plan.last_step(),
            release,
        };
        let model = &stage.model;
        let mut outputs = match carried.take() {
            None => FemOutputs::new(scene, model, options, Some(column))?,
            Some(c) => FemOutputs::next_stage(scene, c, model, options, column)?,
        };
        let mut stepper = Stepper::new(model, scene.spec.solver.fem());
        let span = Span {
            from: plan.first_step,
            to: plan.last_step(),
            total,
            stage: true,
        };
        let stepped = crate::run::execute(
            &mut stepper,
            state,
            resumed.take(),
            &mut outputs,
            span,
            h,
            options,
            (scene.path.as_deref(), &scene.source),
        )?;
        let crate::run::Stepped {
            reports,
            state: end,
            failure,
        } = stepped;
        if let Some((step, source)) = failure {
            return Err(RunError::Step { step, source });
        }
        records.extend(reports);
        let mut entry = StageSummary {
            name: plan.spec.name.clone(),
            first_step: plan.first_step + 1,
            last_step: plan.last_step(),
            time: end.time,
            elements: stage.elements.len(),
            deactivated: plan.spec.deactivate.clone(),
            activated: plan.spec.activate.clone(),
            reaction: scene
                .spec
                .output
                .reaction
                .as_ref()
                .and_then(|_| outputs.curve.last().map(|c| c.1)),
            factor_of_safety: None,
        };
        let summary_path = options.out_dir.join("summary.json");
        let last = k + 1 == stages.plans.len();
        let mut interrupted = false;
        if plan.spec.factor_of_safety {
            let found = factor_of_safety(
                scene,
                model,
                &end,
                &plan.spec.name,
                plan.spec.steps,
                options,
            );
            let found = match found {
                Ok(found) => found,
                // The run ends here: the files a stage's end wrote before the search.
                Err(e) => {
                    outputs.finish(&end, plan.last_step())?;
                    (outputs.results())
                        .summary(RunStatus::Finished, None, total)
                        .write(&summary_path)?;
                    return Err(e);
                }
            };
            // SIGINT/SIGTERM (or a Python callback) stopped the trials: the run stops as
            // interrupted, and a resume goes on from the last checkpoint.
            interrupted = found.interrupted;
            entry.factor_of_safety = Some(found.factor_of_safety);
        }
        outputs.results.results.push_stage(entry);
        // The plots once, at the run's end.
        if last || interrupted {
            outputs.finish(&end, plan.last_step())?;
        }
        let status = match interrupted {
            true => RunStatus::Interrupted,
            false => RunStatus::Finished,
        };
        let summary = outputs.results().summary(status, None, total);
        summary.write(&summary_path)?;
        tracing::info!("{}", summary.sentence());
        if interrupted {
            return Err(RunError::Interrupted {
                step: plan.last_step(),
                time: end.time,
            });
        }
        carried = Some(outputs.into_carried());
        drop(stepper);
        previous = Some((stage, end));
    }
    let curve = carried.map(|c| c.curve).unwrap_or_default();
    let final_state = previous
        .map(|(_, s)| s)
        .ok_or_else(|| scene.error("stage", "no stage ran"))?;
    Ok(RunSummary {
        displacements: curve.iter().skip(1).map(|c| c.0).collect(),
        records,
        seconds: start.elapsed().as_secs_f64(),
        final_state,
    })
}

/// The factor-of-safety search on `state` at the end of stage `name` (`[stability]`), its
/// trials in `trials_<name>.csv`.
fn factor_of_safety<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
    model: &Model<D>,
    state: &State<D>,
    name: &str,
    steps: usize,
    options: &RunOptions,
) -> Result<stability::StabilityRun<D>, RunError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
    SceneOf<N>: StabilityScene<D>,
{
    let trials = options
        .out_dir
        .join(format!("trials_{}.csv", file_name(name)));
    let mut analysis = stability::Analysis::from_model(scene, model.clone(), state.time)?
        .ok_or_else(|| scene.error("stability", "is required by factor_of_safety"))?;
    let equilibrium = stability::Equilibrium {
        state: state.clone(),
        steps,
        newton_iterations: 0,
        seconds: 0.0,
        last_increment: 0.0,
    };
    let found = stability::search(&mut analysis, equilibrium, &trials, options)?;
    tracing::info!(
        stage = name,
        factor = ?found.factor_of_safety.value,
        "factor of safety"
    );
    Ok(found)
}

/// A stage's name as a file name: letters, digits, `-` and `_` kept, the rest `_`.
fn file_name(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}
