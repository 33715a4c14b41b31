//! A 3D finite-element scene run by the run loop (`docs/3d.md`): the model of
//! `model::fem::build3`, `history.csv` with the reported boundary's reaction and
//! settlement and each named boundary's `fx, fy, fz`, `summary.json`, tetrahedral VTUs
//! (`FieldSnapshot<3, 6>`) with `solution.pvd`, the force–displacement and Newton plots,
//! checkpoints. No PNG field map (a map of a 3D body is a ParaView job), no monitors and
//! no inertial share yet.
use std::path::Path;
use std::time::Instant;

use talus_engine::Stepper;

use super::fields::Vtus;
use super::{reaction_nodes, settlement, FemProgress, RunSummary, FEM_COLUMNS};
use crate::model::fem::{
    initial_state_3d, model_3d, prescribed_forces_at_rest, Model3, ReactionForce, ReactionGroups,
    State3, StepRecord,
};
use crate::output::{self, Results};
use crate::run::checkpoint::{self, Checkpoint, CheckpointError};
use crate::run::{RunError, RunOptions, RunOutputs, Span, HISTORY_COLUMNS};
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
    let mut outputs = Outputs3::new(scene, &model, options)?;
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

/// What a 3D FEM run adds to the run loop.
struct Outputs3<'a> {
    scene: &'a Scene3,
    model: &'a Model3,
    results: Results,
    groups: ReactionGroups,
    out: &'a Path,
    reaction_nodes: Vec<usize>,
    vtus: Vtus<'a, 3>,
    curve: Vec<(f64, f64)>,
    histories: Vec<(usize, Vec<f64>)>,
}

impl<'a> Outputs3<'a> {
    fn new(
        scene: &'a Scene3,
        model: &'a Model3,
        options: &'a RunOptions,
    ) -> Result<Self, RunError> {
        let names: Vec<Option<String>> =
            scene.spec.boundary.iter().map(|b| b.name.clone()).collect();
        let groups = ReactionGroups::of_model(model, &names);
        let mut results = Results::with_components(
            &format!("{HISTORY_COLUMNS},{}", FEM_COLUMNS.join(",")),
            &groups.names,
            &[],
            scene.spec.output.reaction.clone(),
            3,
        )
        .map_err(|e| scene.error(&e.field, e.message))?;
        results.set_force_unit(scene.spec.analysis.geometry.force_unit());
        Ok(Self {
            scene,
            model,
            results,
            groups,
            out: &options.out_dir,
            reaction_nodes: reaction_nodes(model),
            vtus: Vtus::new(&options.out_dir, options.write_fields, Vec::new()),
            curve: Vec::new(),
            histories: Vec::new(),
        })
    }
}

impl RunOutputs<&Model3, 6> for Outputs3<'_> {
    fn columns(&self) -> String {
        format!(",{}{}", FEM_COLUMNS.join(","), self.results.header())
    }

    fn row(&mut self, step: usize, state: &State3, report: Option<&StepRecord>) -> String {
        let displacement = settlement(&self.reaction_nodes, &state.displacement);
        if let Some(r) = report {
            self.histories.extend(
                (r.residual_histories.iter())
                    .filter(|h| !h.is_empty())
                    .map(|h| (step, h.clone())),
            );
        }
        let (reaction, forces) = match report {
            Some(r) => (
                r.reaction_force(),
                (r.stats.as_ref())
                    .map(|s| self.groups.sums_of::<3>(&s.prescribed_forces))
                    .unwrap_or_default(),
            ),
            None => (
                self.model.reaction(state),
                self.groups
                    .sums_of::<3>(&prescribed_forces_at_rest(self.model, state)),
            ),
        };
        let rest = self.results.record(
            step,
            state.time,
            &forces,
            &[],
            Some((displacement, reaction)),
        );
        self.curve.push((displacement, reaction));
        format!(",{reaction:.10e},{displacement:.10e}{rest}")
    }

    fn after_step(&mut self, step: usize, state: &State3) -> Result<(), RunError> {
        let spec = &self.scene.spec;
        let cadence = (spec.output.vtu_every, spec.time.steps);
        self.vtus.after_step(self.model, step, state, cadence)
    }

    fn message(&self, report: &StepRecord, _: &State3) -> String {
        format!(
            "{} Newton its, F = {:.4e} N",
            report.newton_iterations,
            report.reaction_force()
        )
    }

    fn finish(&mut self, state: &State3, step: usize) -> Result<(), RunError> {
        if !self.vtus.writes() {
            return Ok(());
        }
        self.vtus.finish(self.model, step, state)?;
        if self.scene.spec.output.plots && step > 0 {
            // The dimension-free plots; a 3D body has no PNG field map.
            let title = (self.scene.spec.title.clone()).unwrap_or_else(|| "talus run".into());
            if !self.model.reaction_dofs.is_empty() {
                output::plot_force_displacement_with_unit(
                    &self.out.join("force_displacement.png"),
                    &self.curve,
                    &title,
                    self.scene.spec.analysis.geometry.force_unit(),
                )?;
            }
            if !self.histories.is_empty() {
                output::plot_newton_residuals(
                    &self.out.join("newton_residuals.png"),
                    &self.histories,
                    self.scene.spec.solver.tolerance,
                )?;
            }
        }
        Ok(())
    }

    fn begin(&mut self, step: usize, state: &State3) {
        self.vtus.keep(step, state);
    }

    fn results(&self) -> &Results {
        &self.results
    }

    fn save(&self) -> serde_json::Value {
        serde_json::json!(FemProgress {
            results: self.results.progress(),
            pvd: self.vtus.pvd.clone(),
            curve: self.curve.clone(),
            histories: self.histories.clone(),
            stage: None,
        })
    }

    fn restore(&mut self, saved: serde_json::Value, _: usize) -> Result<(), RunError> {
        let path = checkpoint::path(self.out);
        let corrupt = |why: String| CheckpointError::Corrupt {
            path: path.clone(),
            why: format!("its FEM outputs: {why}"),
        };
        let p: FemProgress = serde_json::from_value(saved).map_err(|e| corrupt(e.to_string()))?;
        self.results.restore(p.results).map_err(corrupt)?;
        self.curve = p.curve;
        self.histories = p.histories;
        self.vtus.restore(p.pvd)
    }
}
