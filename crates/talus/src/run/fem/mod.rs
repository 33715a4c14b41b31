//! A finite-element scene run by the run loop: the reported boundary's reaction and
//! settlement, element VTUs and the PNG plots.
mod fields;
mod plots;
mod results;
mod stages;
mod three_d;

use std::path::Path;
use std::time::Instant;

use talus_engine::Stepper;

use talus_fem::{Dimension, ElementMesh, Mandel};

use super::checkpoint::{self, Checkpoint, CheckpointError};
use super::{RunError, RunOptions, RunOutputs, Shape, Span, HISTORY_COLUMNS};
use crate::model::fem::stages::Stages;
use crate::model::fem::{FromScene, Model, ReactionForce, State, StepRecord};
use crate::output::{Results, ResultsProgress};
use crate::scene::{Scene, SceneOf, SceneVector};
use plots::{write_plots, PlasticStrainMap};
pub use results::{FemResults, INERTIAL_SHARE, INERTIAL_SHARE_WARNING};
pub use three_d::run_scene_3d;

/// What a finished run measured (`D`: 4 in 2D, 6 in 3D).
#[derive(Debug, Clone)]
pub struct RunSummary<const D: usize = 4>
where
    talus_fem::Mandel<D>: talus_fem::Dimension,
{
    pub records: Vec<StepRecord>,
    /// The reported boundary's displacement (m, along `Model::reaction_direction`:
    /// downward positive for a footing) after each step.
    pub displacements: Vec<f64>,
    pub seconds: f64,
    pub final_state: State<D>,
}

impl<const D: usize> Shape for State<D>
where
    talus_fem::Mandel<D>: talus_fem::Dimension,
{
    const SIZES: &'static str = "stress, plastic strain, free and prescribed velocities, nodes";
    fn sizes(&self) -> Vec<usize> {
        vec![
            self.sigma.len(),
            self.plastic_strain.len(),
            self.velocity_free.len(),
            self.velocity_prescribed.len(),
            self.displacement.len(),
        ]
    }
}

/// Newton settings of a FEM scene (`SolverSpec::fem`).
pub fn solver_settings(scene: &Scene) -> talus_ssn::Settings {
    scene.spec.solver.fem().solver
}

pub fn run_scene(scene: &Scene, options: &RunOptions) -> Result<RunSummary, RunError> {
    run_scene_from(scene, options, None)
}

/// Continues `scene` from `checkpoint` (read from `options.out_dir`, its scene checked by
/// [`Checkpoint::current_scene`]), checkpointing as often as the run it continues.
pub fn resume_scene(
    scene: &Scene,
    checkpoint: Checkpoint<serde_json::Value>,
    options: &RunOptions,
) -> Result<RunSummary, RunError> {
    run_scene_from(scene, options, Some(checkpoint))
}

fn run_scene_from(
    scene: &Scene,
    options: &RunOptions,
    resumed: Option<Checkpoint<serde_json::Value>>,
) -> Result<RunSummary, RunError> {
    if let Some(stages) = Stages::<4>::of(scene)? {
        return stages::run(scene, stages, options, resumed);
    }
    not_a_stability_scene(scene)?;
    let start = Instant::now();
    let model = Model::from_scene(scene)?;
    run_model(scene, &model, options, resumed, start)
}

/// A `[stability]` scene runs by `analysis::stability::run`, not as a loading.
fn not_a_stability_scene<const N: usize>(scene: &SceneOf<N>) -> Result<(), RunError>
where
    [f64; N]: SceneVector,
{
    if scene.spec.stability.is_some() {
        return Err(scene
            .error(
                "stability",
                "a factor-of-safety scene runs by talus::analysis::stability::run",
            )
            .into());
    }
    Ok(())
}

/// Runs `model`, built from the unstaged `scene` (2D or 3D) since `start`, from its
/// initial state or `resumed`'s checkpoint, to the scene's end.
fn run_model<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
    model: &Model<D>,
    options: &RunOptions,
    resumed: Option<Checkpoint<serde_json::Value>>,
    start: Instant,
) -> Result<RunSummary<D>, RunError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
    Model<D>: PlasticStrainMap<D>,
{
    let state = crate::model::fem::initial_state(scene, model)?;
    let mut stepper = Stepper::new(model, scene.spec.solver.fem());
    tracing::info!(
        dimension = N,
        points = model.n_points(),
        free_dofs = model.assembly.dofs().n_free(),
        elements = model.mesh.elements().len(),
        materials = model.materials.len(),
        "model built"
    );
    let mut outputs = FemOutputs::new(scene, model, options, None)?;
    let stepped = super::execute(
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

/// The columns a FEM run adds after [`HISTORY_COLUMNS`], before the named boundaries'
/// and monitors'.
pub const FEM_COLUMNS: [&str; 2] = ["reaction_force", "footing_displacement"];

/// What a FEM run adds to the run loop, in 2D (`N = 2`, Mandel size `D = 4`) and 3D
/// (3, 6): the reported boundary's reaction and settlement, the named boundaries and
/// monitors (`FemResults`), element VTUs and the PNG plots.
struct FemOutputs<'a, const N: usize = 2, const D: usize = 4>
where
    Mandel<D>: Dimension,
    [f64; N]: SceneVector,
{
    scene: &'a SceneOf<N>,
    results: FemResults,
    model: &'a Model<D>,
    out: &'a Path,
    /// The nodes of the reported boundary's prescribed dofs.
    reaction_nodes: Vec<usize>,
    /// The VTUs and `solution.pvd`.
    vtus: fields::Vtus<'a, N>,
    /// (settlement, reaction) after every step, from step 0.
    curve: Vec<(f64, f64)>,
    /// `(step, ‖F‖∞ / max(1, ‖σ‖∞) per iteration)` of every solve, for the Newton plot.
    histories: Vec<(usize, Vec<f64>)>,
    /// A staged run's stage: history.csv's `stage` column, the VTU at its end, and the
    /// force it releases (saved in a checkpoint).
    stage: Option<StageOutputs>,
}

/// What [`FemOutputs`] knows of the stage it writes.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
struct StageOutputs {
    /// Its index in `[[stage]]` (history.csv's `stage`) and its name.
    index: usize,
    name: String,
    last_step: usize,
    /// The out-of-balance force the stage releases, and its ramp's start and end times.
    release: Option<stages::Release>,
}

impl<'a, const N: usize, const D: usize> FemOutputs<'a, N, D>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    fn new(
        scene: &'a SceneOf<N>,
        model: &'a Model<D>,
        options: &'a RunOptions,
        stage: Option<StageOutputs>,
    ) -> Result<Self, RunError> {
        let stage_column = if stage.is_some() { ",stage" } else { "" };
        let results = FemResults::new(
            scene,
            model,
            &format!("{HISTORY_COLUMNS},{}{stage_column}", FEM_COLUMNS.join(",")),
        )?;
        let carried = Carried {
            results,
            pvd: Vec::new(),
            curve: Vec::new(),
            histories: Vec::new(),
        };
        Ok(Self::on(scene, carried, model, options, stage))
    }

    /// The outputs on `model` that go on from what `carried` recorded.
    fn on(
        scene: &'a SceneOf<N>,
        carried: Carried,
        model: &'a Model<D>,
        options: &'a RunOptions,
        stage: Option<StageOutputs>,
    ) -> Self {
        Self {
            scene,
            results: carried.results,
            model,
            out: &options.out_dir,
            reaction_nodes: reaction_nodes(model),
            vtus: fields::Vtus::new(&options.out_dir, options.write_fields, carried.pvd),
            curve: carried.curve,
            histories: carried.histories,
            stage,
        }
    }

    /// What carries on to the next stage of a staged run.
    fn into_carried(self) -> Carried {
        Carried {
            results: self.results,
            pvd: self.vtus.pvd,
            curve: self.curve,
            histories: self.histories,
        }
    }

    /// The outputs of a staged run's next stage, on its model: what was recorded carries on.
    fn next_stage(
        scene: &'a SceneOf<N>,
        carried: Carried,
        model: &'a Model<D>,
        options: &'a RunOptions,
        stage: StageOutputs,
    ) -> Result<Self, RunError> {
        let carried = Carried {
            results: carried.results.rebind(scene, model)?,
            ..carried
        };
        Ok(Self::on(scene, carried, model, options, Some(stage)))
    }
}

/// What [`FemOutputs`] recorded, from one stage to the next.
struct Carried {
    results: FemResults,
    pvd: Vec<(f64, String)>,
    curve: Vec<(f64, f64)>,
    histories: Vec<(usize, Vec<f64>)>,
}

/// The reported boundary's settlement (m, along `(axis, sign)`, the model's
/// `reaction_direction`: downward positive by default): the mean of `sign · u_axis` over
/// `nodes` (0 without nodes), in 2D and 3D.
fn settlement<P: AsRef<[f64]>>(
    nodes: &[usize],
    displacement: &[P],
    (axis, sign): (usize, f64),
) -> f64 {
    let displacement = if nodes.is_empty() {
        0.0
    } else {
        sign * nodes
            .iter()
            .map(|&n| displacement[n].as_ref()[axis])
            .sum::<f64>()
            / nodes.len() as f64
    };
    // + 0.0: a settlement of −0 (no motion yet) is written as 0.
    displacement + 0.0
}

/// The nodes of the reported boundary's prescribed dofs.
fn reaction_nodes<const D: usize>(model: &Model<D>) -> Vec<usize>
where
    talus_fem::Mandel<D>: talus_fem::Dimension,
{
    let dofs = model.assembly.dofs();
    model
        .reaction_dofs
        .iter()
        .map(|&(j, _)| dofs.prescribed_dofs()[j].0)
        .collect()
}

/// What [`FemOutputs`] saves in a checkpoint.
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct FemProgress {
    results: ResultsProgress,
    pvd: Vec<(f64, String)>,
    curve: Vec<(f64, f64)>,
    histories: Vec<(usize, Vec<f64>)>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    stage: Option<StageOutputs>,
}

impl<const N: usize, const D: usize> RunOutputs<&Model<D>, D> for FemOutputs<'_, N, D>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
    Model<D>: PlasticStrainMap<D>,
{
    fn columns(&self) -> String {
        format!(
            ",{}{}{}",
            FEM_COLUMNS.join(","),
            if self.stage.is_some() { ",stage" } else { "" },
            self.results.results.header()
        )
    }

    fn row(&mut self, step: usize, state: &State<D>, report: Option<&StepRecord>) -> String {
        let displacement = settlement(
            &self.reaction_nodes,
            &state.displacement,
            self.model.reaction_direction,
        );
        if let Some(r) = report {
            self.histories.extend(
                r.residual_histories
                    .iter()
                    .filter(|h| !h.is_empty())
                    .map(|h| (step, h.clone())),
            );
        }
        let (reaction, rest) = match report {
            Some(r) => (
                r.reaction_force(),
                self.results.step(self.model, state, step, r, displacement),
            ),
            None => {
                let reaction = self.model.reaction(state);
                (reaction, self.results.initial(self.model, state, reaction))
            }
        };
        self.curve.push((displacement, reaction));
        let stage = self
            .stage
            .as_ref()
            .map_or(String::new(), |s| format!(",{}", s.index));
        format!(",{reaction:.10e},{displacement:.10e}{stage}{rest}")
    }

    /// VTUs at step 0, every `vtu_every` steps and the last.
    fn after_step(&mut self, step: usize, state: &State<D>) -> Result<(), RunError> {
        let every = self.scene.spec.output.vtu_every;
        let last = match &self.stage {
            Some(s) => s.last_step,
            None => self.scene.spec.time.steps,
        };
        self.vtus.after_step(self.model, step, state, (every, last))
    }

    fn message(&self, report: &StepRecord, _: &State<D>) -> String {
        format!(
            "{} Newton its, F = {:.4e} {}",
            report.newton_iterations,
            report.reaction_force(),
            self.scene.spec.analysis.geometry.force_unit()
        )
    }

    fn finish(&mut self, state: &State<D>, step: usize) -> Result<(), RunError> {
        if !self.vtus.writes() {
            return Ok(());
        }
        self.vtus.finish(self.model, step, state)?;
        // Pictures are rank 0's alone; every rank writes its piece of the VTUs.
        if self.scene.spec.output.plots && step > 0 && crate::ranks::ranks().is_root() {
            write_plots(
                self.scene,
                self.model,
                state,
                &self.histories,
                &self.curve,
                self.out,
            )?;
        }
        Ok(())
    }

    /// A resumed run's checkpoint state, or a stage's carried one: where the next step's
    /// plastic strain increment starts.
    fn begin(&mut self, step: usize, state: &State<D>) {
        self.vtus.keep(step, state);
    }

    fn results(&self) -> &Results {
        &self.results.results
    }

    fn save(&self) -> serde_json::Value {
        serde_json::json!(FemProgress {
            results: self.results.results.progress(),
            pvd: self.vtus.pvd.clone(),
            curve: self.curve.clone(),
            histories: self.histories.clone(),
            stage: self.stage.clone(),
        })
    }

    fn restore(&mut self, saved: serde_json::Value, _: usize) -> Result<(), RunError> {
        let path = checkpoint::path(self.out);
        let corrupt = |why: String| CheckpointError::Corrupt {
            path: path.clone(),
            why: format!("its FEM outputs: {why}"),
        };
        let p: FemProgress = serde_json::from_value(saved).map_err(|e| corrupt(e.to_string()))?;
        self.results.results.restore(p.results).map_err(corrupt)?;
        self.curve = p.curve;
        self.histories = p.histories;
        self.stage = p.stage;
        self.vtus.restore(p.pvd)
    }
}
