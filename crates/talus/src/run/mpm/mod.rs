//! A material-point scene (`[grid]`) run by the run loop: the particles stepped to the
//! end, writing `history.csv`, particle VTUs with a `.pvd` collection, and PNG maps of the
//! plastic strain, as the FEM run does.
mod fields;
mod results;

use std::path::Path;
use std::time::Instant;

use talus_engine::Stepper;
use talus_mpm::{
    kinetic_energy, Dimension, GroupForces, Mandel, MpmState, MpmStepReport, Particles,
    ProgrammedMpm,
};

use super::checkpoint::{self, Checkpoint, CheckpointError};
use super::{RunError, RunOptions, RunOutputs, Shape, HISTORY_COLUMNS};
use crate::model::mpm::{MpmDocument, MpmModel, MpmSpace};
use crate::output;
use crate::output::Results;
use crate::output::ResultsProgress;
use crate::scene::{MpmScene, MpmScene3, SceneVector};
use fields::FieldWriter;
use results::MpmResults;

/// The columns an MPM run adds after [`HISTORY_COLUMNS`], before the named walls', boxes'
/// and monitors'.
pub const MPM_COLUMNS: [&str; 6] = [
    "contact_passes",
    "reaction_force_x",
    "reaction_force_y",
    "front",
    "runout_normalized",
    "kinetic_energy",
];

/// [`MPM_COLUMNS`] of a 3D run: the reported box's force has a z component, and `front`
/// is the radial front of a cylinder (`docs/3d-mpm.md`, 'Scenes').
pub const MPM_COLUMNS_3D: [&str; 7] = [
    "contact_passes",
    "reaction_force_x",
    "reaction_force_y",
    "reaction_force_z",
    "front",
    "runout_normalized",
    "kinetic_energy",
];

/// The MPM columns of a run of `axes` dimensions.
fn mpm_columns(axes: usize) -> String {
    if axes == 3 {
        MPM_COLUMNS_3D.join(",")
    } else {
        MPM_COLUMNS.join(",")
    }
}

impl<const D: usize> Shape for MpmState<D>
where
    Mandel<D>: Dimension,
{
    const SIZES: &'static str = "particle positions, velocities, masses, volumes, stresses, \
                                 plastic strains, external forces";
    fn sizes(&self) -> Vec<usize> {
        let p = &self.particles;
        vec![
            p.position.len(),
            p.velocity.len(),
            p.mass.len(),
            p.volume.len(),
            p.stress.len(),
            p.plastic_strain.len(),
            p.external_force.len(),
        ]
    }
}

/// What a finished MPM run measured.
#[derive(Debug, Clone)]
pub struct MpmRunSummary<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    /// One report per step.
    pub reports: Vec<MpmStepReport<D>>,
    /// `(L − L₀)/L₀` after the last step (see [`RunoutReference`]).
    pub runout_normalized: f64,
    /// Whether the scene asked for the runout (`output.runout`).
    pub runout_reported: bool,
    /// How the runout is measured (x front or radial).
    pub runout: crate::model::mpm::Runout,
    pub seconds: f64,
    pub particles: Particles<D>,
}

impl<const D: usize> MpmRunSummary<D>
where
    Mandel<D>: Dimension,
{
    /// Newton iterations of the run, failed attempts included: its cost.
    pub fn total_newton_iterations(&self) -> usize {
        self.reports
            .iter()
            .map(|r| r.total_newton_iterations())
            .sum()
    }

    /// The most Newton iterations one step took (all its sub-steps, failed attempts
    /// included).
    pub fn max_newton_iterations(&self) -> usize {
        self.reports
            .iter()
            .map(|r| r.total_newton_iterations())
            .max()
            .unwrap_or(0)
    }

    /// The largest `‖F‖∞ / max(1, ‖σ‖∞)` a step ended with.
    pub fn max_residual(&self) -> f64 {
        self.reports
            .iter()
            .map(|r| r.relative_residual)
            .fold(0.0, f64::max)
    }
}

pub fn run_mpm_scene(scene: &MpmScene, options: &RunOptions) -> Result<MpmRunSummary, RunError> {
    run_mpm_scene_from(scene, options, None)
}

/// A 3D MPM scene (`docs/3d-mpm.md`), fresh or continued from `checkpoint`.
pub fn run_mpm_scene_3d(
    scene: &MpmScene3,
    options: &RunOptions,
    checkpoint: Option<Checkpoint<serde_json::Value>>,
) -> Result<MpmRunSummary<6>, RunError> {
    run_mpm_scene_from(scene, options, checkpoint)
}

/// Continues `scene` from `checkpoint` (read from `options.out_dir`, its scene checked by
/// [`Checkpoint::current_scene`]), checkpointing as often as the run it continues.
pub fn resume_mpm_scene(
    scene: &MpmScene,
    checkpoint: Checkpoint<serde_json::Value>,
    options: &RunOptions,
) -> Result<MpmRunSummary, RunError> {
    run_mpm_scene_from(scene, options, Some(checkpoint))
}

fn run_mpm_scene_from<const D: usize, const N: usize>(
    scene: &MpmDocument<N>,
    options: &RunOptions,
    resumed: Option<Checkpoint<serde_json::Value>>,
) -> Result<MpmRunSummary<D>, RunError>
where
    Mandel<D>: MpmSpace<D> + Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    let start = Instant::now();
    let model = MpmModel::<D>::build(scene)?;
    let spec = &scene.spec;
    let grid = model.mpm.grid();
    tracing::info!(
        particles = model.particles.len(),
        grid_nodes = grid.n_nodes(),
        cells = ?grid.cells(),
        spacing = grid.spacing(),
        "MPM model built"
    );
    let steps = spec.time.steps;
    let title = spec.title.clone().unwrap_or_else(|| "talus run".into());
    let results = MpmResults::new(
        scene,
        &model,
        &format!("{HISTORY_COLUMNS},{}", mpm_columns(N)),
    )?;
    let mut outputs = MpmOutputs {
        model: &model,
        results,
        fields: FieldWriter {
            out: &options.out_dir,
            title: &title,
            vtu_every: spec.output.vtu_every,
            snapshot_every: spec.output.snapshot_every,
            last_step: steps,
            pvd: Vec::new(),
        },
        out: &options.out_dir,
        write_fields: options.write_fields,
        plots: spec.output.plots,
        title: &title,
        reaction_curve: vec![(0.0, 0.0)],
    };
    let mut stepper = Stepper::new(&model.mpm, model.step_settings);
    let state = MpmState {
        time: 0.0,
        particles: model.particles.clone(),
    };
    let stepped = super::execute(
        &mut stepper,
        state,
        resumed,
        &mut outputs,
        super::Span::whole(spec.time.steps),
        spec.time.step,
        options,
        (scene.path.as_deref(), &scene.source),
    )?;
    if let Some((step, source)) = stepped.failure {
        return Err(RunError::MpmStep {
            step,
            time: stepped.state.time,
            source,
        });
    }
    let particles = stepped.state.particles;
    Ok(MpmRunSummary {
        reports: stepped.reports,
        runout_normalized: model.runout.normalized(model.runout.front(&particles)),
        runout_reported: spec.output.runout,
        runout: model.runout,
        seconds: start.elapsed().as_secs_f64(),
        particles,
    })
}

/// What an MPM run adds to the run loop: the front, runout, kinetic energy and the
/// reported box's force; particle VTUs and PNG maps.
struct MpmOutputs<'a, const D: usize>
where
    Mandel<D>: Dimension,
{
    model: &'a MpmModel<D>,
    results: MpmResults<D>,
    fields: FieldWriter<'a>,
    out: &'a Path,
    write_fields: bool,
    plots: bool,
    title: &'a str,
    /// (settlement, push on the material), both downward positive, from step 0.
    reaction_curve: Vec<(f64, f64)>,
}

/// What [`MpmOutputs`] saves in a checkpoint.
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct MpmProgress {
    results: ResultsProgress,
    pvd: Vec<(f64, String)>,
    reaction_curve: Vec<(f64, f64)>,
}

impl<const D: usize, const N: usize> RunOutputs<&ProgrammedMpm<D>, D> for MpmOutputs<'_, D>
where
    Mandel<D>: MpmSpace<D> + Dimension<Point = [f64; N]>,
{
    fn columns(&self) -> String {
        format!(",{}{}", mpm_columns(N), self.results.results.header())
    }

    fn row(
        &mut self,
        step: usize,
        state: &MpmState<D>,
        report: Option<&MpmStepReport<D>>,
    ) -> String {
        let stats = report.and_then(|r| r.stats.as_ref());
        let force: [f64; N] = self
            .model
            .reaction
            .zip(report)
            .and_then(|(r, report)| report.group_forces().get(r.group).copied())
            .unwrap_or([0.0; N]);
        let settles = self.model.reaction.and_then(|r| r.velocity_y);
        if let (Some(_), Some(vy)) = (report, settles) {
            self.reaction_curve.push((-vy * state.time, -force[1]));
        }
        // The reported box's (settlement, push) for summary.json's limit.
        let reported = settles.and(self.reaction_curve.last().copied());
        let rest = self.results.record(
            self.model,
            &state.particles,
            step,
            state.time,
            report,
            reported,
        );
        let f = self.model.runout.front(&state.particles);
        let forces: String = force.iter().map(|c| format!(",{c:.10e}")).collect();
        format!(
            ",{}{forces},{f:.10e},{:.10e},{:.10e}{rest}",
            stats.map_or(0, |s| s.contact_passes),
            self.model.runout.normalized(f),
            kinetic_energy(&state.particles)
        )
    }

    fn after_step(&mut self, step: usize, state: &MpmState<D>) -> Result<(), RunError> {
        if self.write_fields {
            self.fields
                .after_step(self.model, &state.particles, step, state.time)?;
        }
        Ok(())
    }

    fn message(&self, report: &MpmStepReport<D>, state: &MpmState<D>) -> String {
        format!(
            "{} Newton its, front {:.4} m, E_k = {:.3e} {}",
            report.newton_iterations,
            self.model.runout.front(&state.particles),
            kinetic_energy(&state.particles),
            if N == 3 { "J" } else { "J/m" }
        )
    }

    fn finish(&mut self, state: &MpmState<D>, step: usize) -> Result<(), RunError> {
        if !self.write_fields {
            return Ok(());
        }
        self.fields
            .finish(self.model, &state.particles, step, state.time)?;
        if self.plots && self.reaction_curve.len() > 1 && crate::ranks::ranks().is_root() {
            output::plot_force_displacement(
                &self.out.join("force_displacement.png"),
                &self.reaction_curve,
                self.title,
            )?;
        }
        Ok(())
    }

    fn results(&self) -> &Results {
        &self.results.results
    }

    fn save(&self) -> serde_json::Value {
        serde_json::json!(MpmProgress {
            results: self.results.results.progress(),
            pvd: self.fields.pvd.clone(),
            reaction_curve: self.reaction_curve.clone(),
        })
    }

    fn restore(&mut self, saved: serde_json::Value, step: usize) -> Result<(), RunError> {
        let path = checkpoint::path(self.out);
        let corrupt = |why: String| CheckpointError::Corrupt {
            path: path.clone(),
            why: format!("its MPM outputs: {why}"),
        };
        let p: MpmProgress = serde_json::from_value(saved).map_err(|e| corrupt(e.to_string()))?;
        self.results.results.restore(p.results).map_err(corrupt)?;
        self.fields.pvd = p.pvd;
        self.reaction_curve = p.reaction_curve;
        // The VTUs of later steps, and the one an interruption wrote of its last state.
        crate::run::pieces::drop_unlisted(self.out, &self.fields.pvd)?;
        let earlier = |n: usize| n <= step;
        checkpoint::drop_numbered_files(&self.out.join("snapshots"), "step_", ".png", earlier)?;
        if self.write_fields && !self.fields.pvd.is_empty() {
            output::write_pvd(&self.out.join("solution.pvd"), &self.fields.pvd)?;
        }
        Ok(())
    }
}
