//! `talus run` on a scene with `[stability]`: the loading, the trials, and their files —
//! `history.csv` (one row per trial), `summary.json` with `factor_of_safety`, and the
//! failure mechanism at the smallest failing factor (`mechanism.png`, `mechanism.vtu`).
use std::io::Write;
use std::path::Path;
use std::time::Instant;

use crate::model::fem::Model;
use crate::output::{self, FactorOfSafety, FieldSnapshot, MeshView, RunStatus, Summary};
use crate::run::{io_err, RunError, RunOptions, StepProgress};
use crate::scene::{Scene, StabilityMethod};

use super::{Analysis, Bracket, Equilibrium, Next, Trial};

/// `history.csv`'s columns: one row per trial, row 0 the loading (`docs/stability.md`).
pub const TRIAL_COLUMNS: &str = "trial,factor,outcome,first_increment,last_increment,growth,rest_level,steps,newton_iterations,seconds";

/// What a stability run found.
#[derive(Debug, Clone)]
pub struct StabilityRun {
    pub factor_of_safety: FactorOfSafety,
    pub equilibrium: Equilibrium,
    pub trials: Vec<Trial>,
    pub seconds: f64,
}

/// The loading, then trials until the bracket is within the tolerance (or `max_trials`).
pub fn run(scene: &Scene, options: &RunOptions) -> Result<StabilityRun, RunError> {
    let start = Instant::now();
    let mut analysis = Analysis::new(scene)?
        .ok_or_else(|| scene.error("stability", "the scene has no [stability] section"))?;
    let out = &options.out_dir;
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    let summary_path = out.join("summary.json");
    let _ = std::fs::remove_file(&summary_path);
    let history_path = out.join("history.csv");
    let mut history = std::fs::File::create(&history_path).map_err(io_err(&history_path))?;
    let mut line = |text: String| {
        writeln!(history, "{text}")
            .and_then(|_| history.flush())
            .map_err(io_err(&history_path))
    };
    line(TRIAL_COLUMNS.to_string())?;
    let steps_requested = scene.spec.time.steps;
    let equilibrium = match analysis.equilibrium(scene) {
        Ok(e) => e,
        Err(e) => {
            let mut summary = empty_summary(RunStatus::NotConverged, 0, steps_requested, 0.0);
            summary.error = Some(format!("the loading did not reach equilibrium: {e}"));
            summary.write(&summary_path)?;
            return Err(e);
        }
    };
    line(format!(
        "0,1,equilibrium,,{:.6e},,{:.6e},{},{},{:.6e}",
        equilibrium.last_increment,
        super::criterion::REST * analysis.criterion.scale,
        equilibrium.steps,
        equilibrium.newton_iterations,
        equilibrium.seconds
    ))?;

    let s = &analysis.settings;
    let (max_trials, tolerance) = (s.max_trials, s.tolerance);
    let mut bracket = Bracket::new(tolerance, s.first_guess, s.bracket);
    let mut trials: Vec<Trial> = Vec::new();
    let mut done = None;
    let mut interrupted = false;
    while trials.len() < max_trials {
        let f = match bracket.next_trial() {
            Next::Try(f) => f,
            Next::Done { lo, hi } => {
                done = Some((lo, hi));
                break;
            }
            Next::Unbracketed => break,
        };
        let trial = analysis
            .trial(f, &equilibrium.state)
            .map_err(|e| scene.error("stability", e))?;
        tracing::info!(
            factor = f,
            outcome = trial.verdict.name(),
            steps = trial.steps(),
            iterations = trial.newton_iterations,
            "trial"
        );
        line(trial_row(trials.len() + 1, &trial, &analysis))?;
        bracket.record(f, trial.verdict.outcome());
        let stop = options.observer.as_ref().is_some_and(|observe| {
            // One call per trial: `step` counts trials (`docs/stability.md`).
            observe(&StepProgress {
                step: trials.len() + 1,
                steps: max_trials,
                time: equilibrium.state.time,
                newton_iterations: trial.newton_iterations,
                substeps: trial.steps(),
                relative_residual: 0.0,
                message: format!("F = {f:.4}: {}", trial.verdict.name()),
            })
            .is_break()
        });
        trials.push(trial);
        if stop {
            interrupted = true;
            break;
        }
    }
    if done.is_none() {
        if let Next::Done { lo, hi } = bracket.next_trial() {
            done = Some((lo, hi));
        }
    }
    let factor_of_safety = FactorOfSafety {
        value: done.map(|(lo, hi)| 0.5 * (lo + hi)),
        bracket: [bracket.lo, bracket.hi],
        within_tolerance: done.is_some(),
        tolerance,
        method: analysis.settings.method.name().to_string(),
        dilatancy: (analysis.settings.method == StabilityMethod::StrengthReduction)
            .then(|| analysis.settings.dilatancy.name().to_string()),
        criterion: analysis.criterion.describe(),
        trials: trials.len(),
    };
    // The mechanism of the smallest factor that failed by the criterion.
    let mechanism = trials
        .iter()
        .filter(|t| t.fails())
        .min_by(|a, b| a.factor.total_cmp(&b.factor));
    if let (true, Some(t)) = (options.write_fields, mechanism) {
        write_mechanism(scene, &analysis.model, t, equilibrium.state.time, out)?;
    }
    let status = if interrupted {
        RunStatus::Interrupted
    } else {
        RunStatus::Finished
    };
    let mut summary = empty_summary(
        status,
        equilibrium.steps,
        steps_requested,
        equilibrium.state.time,
    );
    if !factor_of_safety.within_tolerance && !interrupted {
        summary.error = Some(format!(
            "no bracket within the tolerance after {} trials (max_trials = {max_trials})",
            trials.len()
        ));
    }
    summary.factor_of_safety = Some(factor_of_safety.clone());
    summary.warnings = crate::model::fem::warnings(scene, &analysis.model);
    for w in &summary.warnings {
        tracing::warn!("{w}");
    }
    summary.write(&summary_path)?;
    tracing::info!("{}", summary.sentence());
    if interrupted {
        return Err(RunError::Interrupted {
            step: trials.len(),
            time: equilibrium.state.time,
        });
    }
    Ok(StabilityRun {
        factor_of_safety,
        equilibrium,
        trials,
        seconds: start.elapsed().as_secs_f64(),
    })
}

fn empty_summary(status: RunStatus, steps: usize, requested: usize, time: f64) -> Summary {
    Summary {
        status,
        error: None,
        steps,
        steps_requested: requested,
        time,
        boundaries: Default::default(),
        monitors: Default::default(),
        reaction: None,
        limit: None,
        force_unit: "N/m".to_string(),
        factor_of_safety: None,
        collapse: None,
        warnings: Vec::new(),
    }
}

fn trial_row(k: usize, t: &Trial, analysis: &Analysis) -> String {
    let opt = |v: Option<f64>| v.map(|v| format!("{v:.6e}")).unwrap_or_default();
    format!(
        "{k},{:.10e},{},{},{},{},{:.6e},{},{},{:.6e}",
        t.factor,
        t.verdict.name(),
        opt(t.increments.first().copied()),
        opt(t.increments.last().copied()),
        opt(t.growth()),
        super::criterion::REST * analysis.criterion.scale,
        t.steps(),
        t.newton_iterations,
        t.seconds
    )
}

/// Per-element mean of a per-node vector's magnitude.
fn element_magnitude(model: &Model, u: &[[f64; 2]]) -> Vec<f64> {
    model
        .mesh
        .triangles
        .iter()
        .map(|t| t.iter().map(|&n| u[n][0].hypot(u[n][1])).sum::<f64>() / t.len() as f64)
        .collect()
}

/// Per-element means of per-Gauss-point values (`width` numbers each).
fn element_means(model: &Model, values: &[f64], width: usize) -> Vec<Vec<f64>> {
    let n_el = model.mesh.triangles.len();
    let mut sums = vec![vec![0.0; width]; n_el];
    let mut count = vec![0usize; n_el];
    for (p, &e) in model.assembly.gauss_element.iter().enumerate() {
        for (s, v) in sums[e]
            .iter_mut()
            .zip(&values[width * p..width * p + width])
        {
            *s += v;
        }
        count[e] += 1;
    }
    for (s, c) in sums.iter_mut().zip(count) {
        s.iter_mut().for_each(|v| *v /= c.max(1) as f64);
    }
    sums
}

fn write_mechanism(
    scene: &Scene,
    model: &Model,
    t: &Trial,
    time: f64,
    out: &Path,
) -> Result<(), RunError> {
    let mesh = MeshView {
        nodes: &model.mesh.nodes,
        triangles: &model.mesh.triangles,
    };
    let h = scene.spec.time.step;
    let velocity: Vec<[f64; 2]> = t
        .last_increment
        .iter()
        .map(|d| [d[0] / h, d[1] / h])
        .collect();
    let stress: Vec<[f64; 4]> = element_means(model, &t.stress, 4)
        .into_iter()
        .map(|s| [s[0], s[1], s[2], s[3]])
        .collect();
    let plastic: Vec<f64> = element_means(model, &t.plastic_increment, 1)
        .into_iter()
        .map(|s| s[0])
        .collect();
    output::write_vtu(
        &out.join("mechanism.vtu"),
        &FieldSnapshot {
            mesh,
            time: time + h * t.steps() as f64,
            displacement: &t.last_increment,
            velocity: &velocity,
            stress: &stress,
            plastic_strain: &plastic,
            material: Some(&model.element_materials()),
            pore_pressure: None,
        },
    )?;
    if scene.spec.output.plots {
        let method = match scene.spec.stability.as_ref().map(|s| s.method) {
            Some(StabilityMethod::GravityIncrease) => "gravity ×",
            _ => "strength ÷",
        };
        output::plot_field_on_mesh(
            &out.join("mechanism.png"),
            &mesh,
            None,
            &element_magnitude(model, &t.last_increment),
            &format!(
                "failure mechanism, {method} {:.4}: displacement increment of the trial's last step",
                t.factor
            ),
            "|Δu| (m)",
        )
        .map_err(RunError::Output)?;
    }
    Ok(())
}
