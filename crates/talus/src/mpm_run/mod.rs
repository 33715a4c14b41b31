//! `talus run` on a material-point scene (`[grid]`): the particles stepped to the end with
//! [`talus_mpm::Mpm::advance`], writing `history.csv`, particle VTUs with a `.pvd`
//! collection, and PNG maps of the plastic strain, as the FEM run does.
mod build;
mod measure;
mod outputs;
mod results;

use std::io::Write;
use std::time::Instant;

use talus_mpm::{Particles, StepReport};

use crate::output;
use crate::run::{io_err, progress_bar, RunError, RunOptions};
use crate::scene::MpmScene;

pub use build::{MpmModel, Reaction};
pub use measure::{front, kinetic_energy, RunoutReference};
use outputs::FieldWriter;

/// Column names of an MPM `history.csv`.
pub const MPM_HISTORY_HEADER: &str = "step,time,newton_iterations,max_newton_iterations,substeps,residual,contact_passes,reaction_force_x,reaction_force_y,front,runout_normalized,kinetic_energy,seconds";

/// What a finished MPM run measured.
#[derive(Debug, Clone)]
pub struct MpmRunSummary {
    /// One report per step.
    pub reports: Vec<StepReport>,
    /// `(L − L₀)/L₀` after the last step (see [`RunoutReference`]).
    pub runout_normalized: f64,
    /// Whether the scene asked for the runout (`output.runout`).
    pub runout_reported: bool,
    pub seconds: f64,
    pub particles: Particles,
}

impl MpmRunSummary {
    pub fn total_newton_iterations(&self) -> usize {
        self.reports.iter().map(|r| r.newton_iterations).sum()
    }

    /// The most Newton iterations one step took (all its sub-steps).
    pub fn max_newton_iterations(&self) -> usize {
        self.reports
            .iter()
            .map(|r| r.newton_iterations)
            .max()
            .unwrap_or(0)
    }

    pub fn max_residual(&self) -> f64 {
        self.reports.iter().map(|r| r.residual).fold(0.0, f64::max)
    }
}

pub fn run_mpm_scene(scene: &MpmScene, options: &RunOptions) -> Result<MpmRunSummary, RunError> {
    let start = Instant::now();
    let model = MpmModel::from_scene(scene)?;
    let spec = &scene.spec;
    let out = &options.out_dir;
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    let history_path = out.join("history.csv");
    let mut history = std::io::BufWriter::new(
        std::fs::File::create(&history_path).map_err(io_err(&history_path))?,
    );
    let mut write_row = |row: String| {
        writeln!(history, "{row}")
            .and_then(|_| history.flush())
            .map_err(io_err(&history_path))
    };
    let _ = std::fs::remove_file(out.join("summary.json"));
    let mut results = results::MpmResults::new(scene, &model, MPM_HISTORY_HEADER)?;
    write_row(format!("{MPM_HISTORY_HEADER}{}", results.results.header()))?;
    let grid = model.mpm.grid();
    tracing::info!(
        particles = model.particles.len(),
        grid_nodes = grid.n_nodes(),
        cells = ?grid.cells(),
        spacing = grid.spacing(),
        "MPM model built"
    );

    let mut particles = model.particles.clone();
    let (h, steps) = (spec.time.step, spec.time.steps);
    let title = spec.title.clone().unwrap_or_else(|| "talus run".into());
    let mut fields = FieldWriter {
        out,
        title: &title,
        vtu_every: spec.output.vtu_every,
        snapshot_every: spec.output.snapshot_every,
        last_step: steps,
        pvd: Vec::new(),
    };
    let f0 = front(&particles);
    let settles = model.reaction.is_some_and(|r| r.velocity_y.is_some());
    let extra = results.record(
        &model,
        &particles,
        0,
        0.0,
        None,
        settles.then_some((0.0, 0.0)),
    );
    write_row(format!(
        "0,0,0,0,0,0,0,0,0,{f0:.10e},{:.10e},{:.10e},0{extra}",
        model.runout.normalized(f0),
        kinetic_energy(&particles)
    ))?;
    if options.write_fields {
        fields.after_step(&model, &particles, 0, 0.0)?;
    }
    let bar = progress_bar(steps, options.progress);
    let mut reports = Vec::new();
    let mut reaction_curve = vec![(0.0, 0.0)];
    let mut failure = None;
    let mut time = 0.0;
    for step in 1..=steps {
        let report = match model.mpm.advance(&mut particles, h) {
            Ok(r) => r,
            Err(source) => {
                failure = Some(RunError::MpmStep { step, time, source });
                break;
            }
        };
        time = step as f64 * h;
        let force = model
            .reaction
            .and_then(|r| report.group_forces.get(r.group).copied())
            .unwrap_or([0.0; 2]);
        if let Some(Reaction {
            velocity_y: Some(vy),
            ..
        }) = model.reaction
        {
            // Settlement and the push on the material, both downward positive.
            reaction_curve.push((-vy * time, -force[1]));
        }
        let f = front(&particles);
        let runout = model.runout.normalized(f);
        let energy = kinetic_energy(&particles);
        let reported = reaction_curve.last().copied().filter(|_| settles);
        let extra = results.record(&model, &particles, step, time, Some(&report), reported);
        write_row(format!(
            "{step},{time:.10e},{},{},{},{:.6e},{},{:.10e},{:.10e},{f:.10e},{runout:.10e},{energy:.10e},{:.6e}{extra}",
            report.newton_iterations,
            report.max_newton_iterations,
            report.substeps,
            report.residual,
            report.contact_passes,
            force[0],
            force[1],
            report.seconds
        ))?;
        tracing::info!(
            step,
            time,
            iterations = report.newton_iterations,
            substeps = report.substeps,
            residual = report.residual,
            front = f,
            kinetic_energy = energy,
            "step"
        );
        if let Some(bar) = &bar {
            bar.set_message(format!(
                "{} Newton its, front {f:.4} m, E_k = {energy:.3e} J/m",
                report.newton_iterations
            ));
            bar.inc(1);
        }
        if options.write_fields {
            fields.after_step(&model, &particles, step, time)?;
        }
        reports.push(report);
    }
    if let Some(bar) = bar {
        bar.finish();
    }
    if options.write_fields {
        fields.finish(&model, &particles, time)?;
        if spec.output.plots && reaction_curve.len() > 1 {
            output::plot_force_displacement(
                &out.join("force_displacement.png"),
                &reaction_curve,
                &title,
            )?;
        }
    }
    crate::run_results::write_summary(&results.results, failure.as_ref(), steps, out)?;
    if let Some(f) = failure {
        return Err(f);
    }
    Ok(MpmRunSummary {
        reports,
        runout_normalized: model.runout.normalized(front(&particles)),
        runout_reported: spec.output.runout,
        seconds: start.elapsed().as_secs_f64(),
        particles,
    })
}
