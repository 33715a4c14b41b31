//! `talus run`: a scene stepped to its end, with history, ParaView files and PNG plots.
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use talus_ssn::{Rho, Settings, Stall};

use crate::output::{self, FieldSnapshot, MeshView, OutputError};
use crate::scene::{RhoScaling, Scene, SceneError, SolverSpec};
use crate::simulation::{Model, State, StepError, StepRecord, Stepper};

/// Column names of `history.csv`.
pub const HISTORY_HEADER: &str =
    "step,time,newton_iterations,residual,reaction_force,footing_displacement,seconds";

#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error("{0}")]
    Scene(#[from] SceneError),
    #[error("cannot write {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The run stopped at `step`; what was written before it is kept.
    #[error("step {step}: {source}")]
    Step { step: usize, source: StepError },
    /// An MPM run stopped at `step`, which started at `time` (s); what was written before
    /// it is kept.
    #[error("step {step} (from t = {time:.6} s): {source}")]
    MpmStep {
        step: usize,
        time: f64,
        source: talus_mpm::MpmError,
    },
}

/// What a finished run measured.
#[derive(Debug, Clone)]
pub struct RunSummary {
    pub records: Vec<StepRecord>,
    /// Footing displacement (m, downward positive) after each step.
    pub displacements: Vec<f64>,
    pub seconds: f64,
    pub final_state: State,
}

pub struct RunOptions {
    pub out_dir: PathBuf,
    /// Draw a progress bar on a terminal (tracing logs otherwise).
    pub progress: bool,
    /// Write VTU files and PNG plots (history.csv is always written).
    pub write_fields: bool,
}

pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RunError + '_ {
    move |source| RunError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// A progress bar over `steps` when `progress` is asked for and stderr is a terminal.
pub(crate) fn progress_bar(steps: usize, progress: bool) -> Option<indicatif::ProgressBar> {
    (progress && std::io::stderr().is_terminal()).then(|| {
        let bar = indicatif::ProgressBar::new(steps as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} steps, {elapsed} elapsed, eta {eta} {msg}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    })
}

/// Solver settings of a scene.
pub fn solver_settings(scene: &Scene) -> Settings {
    ssn_settings(&scene.spec.solver, FEM_STALL_WINDOW)
}

/// `[solver] stall_window` when the scene does not set it. FEM: the attempts that fail at
/// the footing's mechanism onset stall for 20–40 iterations before `max_iterations`;
/// stopping them (from iteration 25, after 10 iterations without a halving of the merit)
/// cuts the Newton iterations of the 104×48 footing's hardest steps (`docs/solver.md`). MPM: the slow but steady first friction
/// passes are better left to run (the a = 2 column: 92.2 → 102.4 iterations per step with
/// 10). `docs/solver.md`, "Non-associative Newton at the mechanism's onset".
pub const FEM_STALL_WINDOW: usize = 10;
/// The stall rule applies from this iteration on: slow solves that converge within it (up
/// to 23 iterations on the footing snapshots) keep their step, and so their results.
pub const STALL_AFTER: usize = 25;
pub const MPM_STALL_WINDOW: usize = 0;

/// The talus-ssn settings of a `[solver]` section (FEM and MPM scenes alike), with the
/// method's stall window when the scene sets none.
pub fn ssn_settings(s: &SolverSpec, default_stall_window: usize) -> Settings {
    let stall_window = s.stall_window.unwrap_or(default_stall_window);
    Settings {
        tolerance: s.tolerance,
        max_iterations: s.max_iterations,
        rho: match s.rho_scaling {
            RhoScaling::Compliance => Rho::PerPointCompliance {
                factor: s.rho_factor,
            },
            RhoScaling::Diagonal => Rho::PerPointDiagonal {
                factor: s.rho_factor,
            },
        },
        line_search: if s.line_search {
            Settings::default().line_search
        } else {
            None
        },
        stall: (stall_window > 0).then_some(Stall {
            after: STALL_AFTER,
            window: stall_window,
            decrease: 0.5,
        }),
        ..Settings::default()
    }
}

pub fn run_scene(scene: &Scene, options: &RunOptions) -> Result<RunSummary, RunError> {
    let start = Instant::now();
    let model = Model::from_scene(scene)?;
    let asm = &model.assembly;
    let dofs = asm.dofs();
    let out = &options.out_dir;
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    let history_path = out.join("history.csv");
    let mut history = std::io::BufWriter::new(
        std::fs::File::create(&history_path).map_err(io_err(&history_path))?,
    );
    let _ = std::fs::remove_file(out.join("summary.json"));
    let mut results = crate::run_results::FemResults::new(scene, &model, HISTORY_HEADER)?;
    writeln!(history, "{HISTORY_HEADER}{}", results.results.header())
        .map_err(io_err(&history_path))?;

    let mut state = model.initial_state(scene)?;
    let mut stepper = Stepper::new(
        &model,
        solver_settings(scene),
        scene.spec.solver.max_step_halvings,
    );
    let time = scene.spec.time;
    let reaction_nodes: Vec<usize> = model
        .reaction_dofs
        .iter()
        .map(|&(j, _)| dofs.prescribed_dofs()[j].0)
        .collect();
    let bar = progress_bar(time.steps, options.progress);
    tracing::info!(
        points = asm.n_points(),
        free_dofs = dofs.n_free(),
        elements = model.mesh.triangles.len(),
        cone_fit = model.material.parameters().cone_fit.name(),
        k_d = model.material.k_d(),
        "model built"
    );

    let initial_reaction = stepper.reaction(&state);
    let extra = results.initial(&model, &state, initial_reaction);
    writeln!(history, "0,0,0,0,{initial_reaction:.10e},0,0{extra}")
        .map_err(io_err(&history_path))?;

    let vtu_dir = out.join("vtu");
    let mut pvd_entries = Vec::new();
    if options.write_fields {
        std::fs::create_dir_all(&vtu_dir).map_err(io_err(&vtu_dir))?;
        write_snapshot(&model, &state, &vtu_dir.join("step_00000.vtu"))?;
        pvd_entries.push((state.time, "vtu/step_00000.vtu".to_string()));
    }
    let mut records = Vec::new();
    let mut displacements = Vec::new();
    let mut failure = None;
    for step in 1..=time.steps {
        let record = match stepper.advance(&mut state, time.step) {
            Ok(r) => r,
            Err(source) => {
                failure = Some(RunError::Step { step, source });
                break;
            }
        };
        let displacement = if reaction_nodes.is_empty() {
            0.0
        } else {
            -reaction_nodes
                .iter()
                .map(|&n| state.displacement[n][1])
                .sum::<f64>()
                / reaction_nodes.len() as f64
        };
        let extra = results.step(&model, &state, step, &record, displacement);
        writeln!(
            history,
            "{step},{:.10e},{},{:.6e},{:.10e},{:.10e},{:.6e}{extra}",
            record.time,
            record.newton_iterations,
            record.residual,
            record.reaction_force,
            displacement,
            record.seconds
        )
        .and_then(|_| history.flush())
        .map_err(io_err(&history_path))?;
        tracing::info!(
            step,
            time = record.time,
            iterations = record.newton_iterations,
            residual = record.residual,
            reaction = record.reaction_force,
            "step"
        );
        if let Some(bar) = &bar {
            bar.set_message(format!(
                "{} Newton its, F = {:.4e} N/m",
                record.newton_iterations, record.reaction_force
            ));
            bar.inc(1);
        }
        let every = scene.spec.output.vtu_every;
        if options.write_fields && ((every > 0 && step % every == 0) || step == time.steps) {
            std::fs::create_dir_all(&vtu_dir).map_err(io_err(&vtu_dir))?;
            let name = format!("step_{step:05}.vtu");
            write_snapshot(&model, &state, &vtu_dir.join(&name))?;
            pvd_entries.push((state.time, format!("vtu/{name}")));
        }
        records.push(record);
        displacements.push(displacement);
    }
    if let Some(bar) = bar {
        bar.finish();
    }
    if options.write_fields && !records.is_empty() {
        if !pvd_entries.is_empty() {
            output::write_pvd(&out.join("solution.pvd"), &pvd_entries)?;
        }
        if scene.spec.output.plots {
            write_plots(
                scene,
                &model,
                &state,
                &records,
                &displacements,
                initial_reaction,
                out,
            )?;
        }
    }
    crate::run_results::write_summary(&results.results, failure.as_ref(), time.steps, out)?;
    if let Some(f) = failure {
        return Err(f);
    }
    Ok(RunSummary {
        records,
        displacements,
        seconds: start.elapsed().as_secs_f64(),
        final_state: state,
    })
}

/// Per-element averages of the Gauss-point stress and plastic strain.
fn element_fields(model: &Model, state: &State) -> (Vec<[f64; 4]>, Vec<f64>) {
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

fn write_snapshot(model: &Model, state: &State, path: &Path) -> Result<(), RunError> {
    let (stress, plastic) = element_fields(model, state);
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
        },
    )?;
    Ok(())
}

fn write_plots(
    scene: &Scene,
    model: &Model,
    state: &State,
    records: &[StepRecord],
    displacements: &[f64],
    initial_reaction: f64,
    out: &Path,
) -> Result<(), RunError> {
    let title = scene
        .spec
        .title
        .clone()
        .unwrap_or_else(|| "talus run".into());
    if !model.reaction_dofs.is_empty() {
        let mut curve = vec![(0.0, initial_reaction)];
        curve.extend(
            displacements
                .iter()
                .zip(records)
                .map(|(d, r)| (*d, r.reaction_force)),
        );
        output::plot_force_displacement(&out.join("force_displacement.png"), &curve, &title)?;
    }
    let histories: Vec<(usize, Vec<f64>)> = records
        .iter()
        .enumerate()
        .flat_map(|(i, r)| r.residual_histories.iter().map(move |h| (i + 1, h.clone())))
        .filter(|(_, h)| !h.is_empty())
        .collect();
    if !histories.is_empty() {
        output::plot_newton_residuals(
            &out.join("newton_residuals.png"),
            &histories,
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
        "cumulative plastic strain ∫‖ε̇ᵖ‖dt",
    )?;
    Ok(())
}
