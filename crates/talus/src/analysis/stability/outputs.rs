//! `talus run` on a scene with `[stability]`: the loading, the trials, and their files —
//! `history.csv` (one row per trial), `summary.json` with `factor_of_safety`, and the
//! failure mechanism at the smallest failing factor (`mechanism.png`, `mechanism.vtu`).
//! [`search`] is the trials alone, from a given equilibrium (a construction stage's end).
use std::io::Write;
use std::path::Path;
use std::time::Instant;

use talus_fem::{Dimension, ElementMesh, Mandel};

use crate::model::fem::{element_means, Model};
use crate::output::{
    self, CollapseTime, FactorOfSafety, FieldSnapshot, MeshView, RunStatus, Summary,
};
use crate::run::{io_err, RunError, RunOptions, StepProgress};
use crate::scene::StabilityMethod;

use super::{Analysis, Bracket, Equilibrium, Next, Planner, StabilityScene, Trial, Verdict};
use crate::model::fem::State;

/// `history.csv`'s columns: one row per trial, row 0 the loading (`docs/stability.md`).
pub const TRIAL_COLUMNS: &str = "trial,factor,outcome,first_increment,last_increment,growth,rest_level,steps,newton_iterations,seconds,start,moved";

/// How the search ended: `summary.json`'s `factor_of_safety.status`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SearchStatus {
    /// The bracket reached the tolerance: the factor is its middle.
    Found,
    /// Every trial came to rest up to the search's upper end (`bracket::MAX_FACTOR`): no
    /// mechanism, no factor.
    NoMechanism,
    /// Every trial failed down to the search's lower end (`bracket::MIN_FACTOR`).
    NoStableFactor,
    /// Stable and unconverged trials closed in with no failing trial between.
    Unbracketed,
    /// `max_trials` ran out first.
    MaxTrials,
    /// The observer (SIGINT/SIGTERM) stopped the search first.
    Interrupted,
}

impl SearchStatus {
    pub fn name(self) -> &'static str {
        match self {
            SearchStatus::Found => "found",
            SearchStatus::NoMechanism => "no_mechanism",
            SearchStatus::NoStableFactor => "no_stable_factor",
            SearchStatus::Unbracketed => "unbracketed",
            SearchStatus::MaxTrials => "max_trials",
            SearchStatus::Interrupted => "interrupted",
        }
    }
}

/// What a stability run found (2D, `D = 4`, or 3D, `D = 6`).
#[derive(Debug, Clone)]
pub struct StabilityRun<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub factor_of_safety: FactorOfSafety,
    pub status: SearchStatus,
    /// The observer stopped the search (the factor may still have been found).
    pub interrupted: bool,
    pub equilibrium: Equilibrium<D>,
    pub trials: Vec<Trial<D>>,
    pub seconds: f64,
}

/// The loading, then trials until the bracket is within the tolerance (or `max_trials`),
/// by [`search`]; `summary.json` and the mechanism's files. A loading that collapses or
/// does not converge ends the run with its error, `summary.json` saying so
/// (`collapsed`, `not_converged`), and no trials.
pub fn run<const D: usize, const N: usize>(
    scene: &impl StabilityScene<D>,
    options: &RunOptions,
) -> Result<StabilityRun<D>, RunError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
{
    run_with(scene, options, true)
}

/// [`run`] with the search before issue 24: every trial from the loading's equilibrium,
/// doubling, then bisection (`StabilitySettings::continuation = false`). For comparisons,
/// and for a check pinned to that search's factors.
pub fn run_blind<const D: usize, const N: usize>(
    scene: &impl StabilityScene<D>,
    options: &RunOptions,
) -> Result<StabilityRun<D>, RunError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
{
    run_with(scene, options, false)
}

fn run_with<const D: usize, const N: usize>(
    scene: &impl StabilityScene<D>,
    options: &RunOptions,
    continuation: bool,
) -> Result<StabilityRun<D>, RunError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
{
    let start = Instant::now();
    let mut analysis = Analysis::new(scene)?
        .ok_or_else(|| scene.error("stability", "the scene has no [stability] section"))?;
    analysis.settings.continuation = continuation;
    let out = &options.out_dir;
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    let summary_path = out.join("summary.json");
    let _ = std::fs::remove_file(&summary_path);
    let history_path = out.join("history.csv");
    let spec = scene.spec();
    let steps_requested = spec.time.steps;
    let unit = spec.analysis.geometry.force_unit();
    let warnings = warnings(scene, &analysis.model);
    for w in &warnings {
        tracing::warn!("{w}");
    }
    let equilibrium = match analysis.equilibrium(scene) {
        Ok(e) => e,
        Err(e) => {
            // history.csv holds the loading's row when it collapsed: no trial, no equilibrium.
            let mut history = TRIAL_COLUMNS.to_string() + "\n";
            let mut summary = match &e {
                RunError::Collapsed(c) => {
                    history += &format!("0,1,collapsed,,,,,{},,\n", c.step);
                    let mut s =
                        empty_summary(RunStatus::Collapsed, c.step, steps_requested, c.time, unit);
                    s.collapse = Some(CollapseTime {
                        step: c.step,
                        time: c.time,
                    });
                    s.error = Some(format!("the loading collapsed, no equilibrium: {e}"));
                    s
                }
                _ => {
                    let mut s =
                        empty_summary(RunStatus::NotConverged, 0, steps_requested, 0.0, unit);
                    s.error = Some(format!("the loading did not reach equilibrium: {e}"));
                    s
                }
            };
            std::fs::write(&history_path, history).map_err(io_err(&history_path))?;
            summary.warnings = warnings;
            summary.write(&summary_path)?;
            tracing::info!("{}", summary.sentence());
            return Err(e);
        }
    };
    let mut found = search(&mut analysis, equilibrium, &history_path, options)?;
    found.seconds = start.elapsed().as_secs_f64();
    if options.write_fields {
        write_mechanism(scene, &analysis, &found, out)?;
    }
    let status = if found.interrupted {
        RunStatus::Interrupted
    } else {
        RunStatus::Finished
    };
    let equilibrium = &found.equilibrium;
    let mut summary = empty_summary(
        status,
        equilibrium.steps,
        steps_requested,
        equilibrium.state.time,
        unit,
    );
    let fos = &found.factor_of_safety;
    let [lo, hi] = fos.bracket;
    let max_trials = analysis.settings.max_trials;
    summary.error = match found.status {
        SearchStatus::Found | SearchStatus::NoMechanism | SearchStatus::Interrupted => None,
        SearchStatus::MaxTrials => Some(format!(
            "no bracket within the tolerance after {} trials (max_trials = {max_trials})",
            found.trials.len()
        )),
        SearchStatus::Unbracketed => Some(format!(
            "no trial failed by the criterion between the largest stable F = {} and the \
             smallest unconverged one, F = {}: no bracket (history.csv has the trials)",
            lo.map_or("none".into(), |v| v.to_string()),
            found
                .trials
                .iter()
                .filter(|t| t.verdict.outcome() == super::Outcome::Unknown)
                .map(|t| t.factor)
                .fold(f64::INFINITY, f64::min)
        )),
        SearchStatus::NoStableFactor => Some(format!(
            "every trial failed, down to F = {}: the body does not come to rest even with \
             its strength multiplied (or its weight divided) by {:.0}; the loading's last \
             step still moved by {:.3e} m (rest: {:.3e} m)",
            hi.map_or("none".into(), |v| v.to_string()),
            1.0 / hi.unwrap_or(1.0),
            equilibrium.last_increment,
            super::criterion::REST * analysis.criterion.scale
        )),
    };
    summary.factor_of_safety = Some(fos.clone());
    summary.warnings = warnings;
    summary.write(&summary_path)?;
    tracing::info!("{}", summary.sentence());
    if found.interrupted {
        return Err(RunError::Interrupted {
            step: found.trials.len(),
            time: found.equilibrium.state.time,
        });
    }
    Ok(found)
}

/// The warnings of a `[stability]` run: the model's, and the ramps faster than its step.
fn warnings<const D: usize>(scene: &impl StabilityScene<D>, model: &Model<D>) -> Vec<String>
where
    Mandel<D>: Dimension,
{
    let spec = scene.spec();
    let mut warnings = scene.model_warnings(model);
    warnings.extend(crate::scene::check::fast_ramps(
        &crate::scene::check::ramps(spec),
        spec.time.step,
        spec.time.step * spec.time.steps as f64,
    ));
    warnings
}

/// The trials from `equilibrium` (the loading's end: [`Analysis::equilibrium`], or a
/// caller's own state, e.g. a construction stage's end) until the bracket is within the
/// tolerance, `max_trials` run out, or the search reaches its end (`bracket`); each trial
/// told to `options.observer` (a `Break` stops the search: `interrupted`). Writes
/// `trials_csv` afresh: [`TRIAL_COLUMNS`], row 0 the equilibrium, then one row per trial.
///
/// Sets the criterion's scale `U` from `equilibrium.state`'s largest nodal displacement
/// (`Criterion::set_scale`): a caller whose displacements were reset should know that the
/// rest level is `10⁻³ U` of what the state holds. `equilibrium.last_increment`, `steps`,
/// `newton_iterations` and `seconds` are only written in row 0 (0 is fine). Leaves the
/// model at F = 1. Writes neither `summary.json` nor the mechanism ([`write_mechanism`]).
pub fn search<const D: usize>(
    analysis: &mut Analysis<D>,
    equilibrium: Equilibrium<D>,
    trials_csv: &Path,
    options: &RunOptions,
) -> Result<StabilityRun<D>, RunError>
where
    Mandel<D>: Dimension,
{
    let start = Instant::now();
    analysis
        .criterion
        .set_scale(&equilibrium.state.displacement);
    let mut history = std::fs::File::create(trials_csv).map_err(io_err(trials_csv))?;
    let mut line = |text: String| {
        writeln!(history, "{text}")
            .and_then(|_| history.flush())
            .map_err(io_err(trials_csv))
    };
    line(TRIAL_COLUMNS.to_string())?;
    line(format!(
        "0,1,equilibrium,,{:.6e},,{:.6e},{},{},{:.6e},,0",
        equilibrium.last_increment,
        super::criterion::REST * analysis.criterion.scale,
        equilibrium.steps,
        equilibrium.newton_iterations,
        equilibrium.seconds
    ))?;

    let s = &analysis.settings;
    let (max_trials, tolerance, continuation) = (s.max_trials, s.tolerance, s.continuation);
    let mut bracket = Bracket::new(tolerance, s.first_guess, s.bracket);
    // An elastic body moves by `U` per unit factor of gravity increase (its loading moved
    // it by `U` under the weight of F = 1); strength reduction moves an elastic body not at
    // all, but `U` still measures how far beyond elastic its first motion is.
    let mut planner = Planner::new(
        Some(analysis.criterion.scale),
        analysis.settings.method == StabilityMethod::StrengthReduction,
    );
    // The end state of the largest stable trial, the next trials' start (continuation).
    let mut stable_state: Option<(State<D>, f64)> = None;
    let mut trials: Vec<Trial<D>> = Vec::new();
    let mut end = None;
    let mut interrupted = false;
    while trials.len() < max_trials {
        let next = if continuation {
            bracket.next_guided(&planner.guide())
        } else {
            bracket.next_trial()
        };
        let f = match next {
            Next::Try(f) => f,
            other => {
                end = Some(other);
                break;
            }
        };
        let start = match &stable_state {
            Some((state, lo)) if *lo < f => (state, Some(*lo)),
            _ => (&equilibrium.state, None),
        };
        let (trial, state) = match analysis.trial_from(f, start, &equilibrium.state) {
            Ok(t) => t,
            Err(e) => return Err(analysis.error(e).into()),
        };
        tracing::info!(
            factor = f,
            start = trial.start.unwrap_or(1.0),
            outcome = trial.verdict.name(),
            steps = trial.steps(),
            iterations = trial.newton_iterations,
            moved = trial.moved,
            "trial"
        );
        line(trial_row(trials.len() + 1, &trial, analysis))?;
        bracket.record(f, trial.verdict.outcome());
        if trial.fails() {
            planner.failing(f, trial.moved);
        }
        if trial.verdict == Verdict::Stable {
            planner.stable(f, trial.moved);
        }
        if let Some(state) = state.filter(|_| continuation && bracket.lo == Some(f)) {
            stable_state = Some((state, f));
        }
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
    // The last trial may have closed the search.
    if end.is_none() {
        end = Some(bracket.next_trial()).filter(|n| !matches!(n, Next::Try(_)));
    }
    analysis.set_factor(1.0).map_err(|e| analysis.error(e))?;
    let status = match end {
        Some(Next::Done { .. }) => SearchStatus::Found,
        _ if interrupted => SearchStatus::Interrupted,
        Some(Next::NoMechanism { .. }) => SearchStatus::NoMechanism,
        Some(Next::NoStableFactor { .. }) => SearchStatus::NoStableFactor,
        Some(Next::Unbracketed) => SearchStatus::Unbracketed,
        Some(Next::Try(_)) | None => SearchStatus::MaxTrials,
    };
    let value = match end {
        Some(Next::Done { lo, hi }) => Some(0.5 * (lo + hi)),
        _ => None,
    };
    let factor_of_safety = FactorOfSafety {
        value,
        status: status.name().to_string(),
        bracket: [bracket.lo, bracket.hi],
        within_tolerance: value.is_some(),
        tolerance,
        method: analysis.settings.method.name().to_string(),
        dilatancy: (analysis.settings.method == StabilityMethod::StrengthReduction)
            .then(|| analysis.settings.dilatancy.name().to_string()),
        criterion: analysis.criterion.describe(),
        trials: trials.len(),
        newton_tolerance: Some(analysis.trial_tolerance()),
    };
    Ok(StabilityRun {
        factor_of_safety,
        status,
        interrupted,
        equilibrium,
        trials,
        seconds: start.elapsed().as_secs_f64(),
    })
}

fn empty_summary(
    status: RunStatus,
    steps: usize,
    requested: usize,
    time: f64,
    force_unit: &str,
) -> Summary {
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
        force_unit: force_unit.to_string(),
        factor_of_safety: None,
        collapse: None,
        warnings: Vec::new(),
        stages: Vec::new(),
    }
}

fn trial_row<const D: usize>(k: usize, t: &Trial<D>, analysis: &Analysis<D>) -> String
where
    Mandel<D>: Dimension,
{
    let opt = |v: Option<f64>| v.map(|v| format!("{v:.6e}")).unwrap_or_default();
    format!(
        "{k},{:.16e},{},{},{},{},{:.6e},{},{},{:.6e},{},{:.6e}",
        t.factor,
        t.verdict.name(),
        opt(t.increments.first().copied()),
        opt(t.increments.last().copied()),
        opt(t.growth()),
        super::criterion::REST * analysis.criterion.scale,
        t.steps(),
        t.newton_iterations,
        t.seconds,
        opt(t.start),
        t.moved
    )
}

/// Per-element mean of a per-node vector's magnitude.
fn element_magnitude<const D: usize, const N: usize>(model: &Model<D>, u: &[[f64; N]]) -> Vec<f64>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
{
    let length = |v: &[f64; N]| v.iter().fold(0.0f64, |l, c| l.hypot(*c));
    (model.mesh.elements().iter())
        .map(|t| t.iter().map(|&n| length(&u[n])).sum::<f64>() / t.len() as f64)
        .collect()
}

/// `mechanism.vtu` and (with `[output] plots`, in 2D) `mechanism.png` in `out`: the trial
/// with the smallest failing factor, the bracket's upper end (nothing when no trial
/// failed). In 3D the VTU holds tetrahedra.
pub fn write_mechanism<const D: usize, const N: usize>(
    scene: &impl StabilityScene<D>,
    analysis: &Analysis<D>,
    found: &StabilityRun<D>,
    out: &Path,
) -> Result<(), RunError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
{
    let Some(t) = found
        .trials
        .iter()
        .filter(|t| t.fails())
        .min_by(|a, b| a.factor.total_cmp(&b.factor))
    else {
        return Ok(());
    };
    let model = &analysis.model;
    let time = found.equilibrium.state.time;
    let mesh = MeshView {
        nodes: model.mesh.node_positions(),
        elements: model.mesh.elements(),
    };
    let spec = scene.spec();
    let h = spec.time.step;
    let velocity: Vec<[f64; N]> = (t.last_increment.iter())
        .map(|d| d.map(|c| c / h))
        .collect();
    let stress = element_means::<D, D>(model, &t.stress);
    let plastic: Vec<f64> = element_means::<1, D>(model, &t.plastic_increment)
        .into_iter()
        .map(|[s]| s)
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
    if spec.output.plots {
        let method = match analysis.settings.method {
            StabilityMethod::GravityIncrease => "gravity ×",
            StabilityMethod::StrengthReduction => "strength ÷",
        };
        // The picture is a trial's, at the bracket's upper end; the factor reported is the
        // bracket's middle: the title says which is which.
        let reported = match found.factor_of_safety.value {
            Some(v) => format!(" (reported F = {v:.4})"),
            None => String::new(),
        };
        let title = spec
            .title
            .clone()
            .unwrap_or_else(|| "factor of safety".into());
        let subtitle = format!(
            "mechanism: {method} {:.4}, the bracket's upper end{reported}",
            t.factor
        );
        scene.plot_mechanism(
            model,
            &out.join("mechanism.png"),
            &element_magnitude(model, &t.last_increment),
            [&title, &subtitle, "|Δu| over the trial's last step (m)"],
        )?;
    }
    Ok(())
}
