//! `[stability]` checked against the scene: every error names the field and its value.
use talus_fem::{Dimension, Mandel};

use super::StabilityScene;
use crate::model::fem::Model;
use crate::scene::{AnalysisKind, DilatancyRule, SceneError, StabilityMethod};

/// `tolerance` when the scene gives none: the bracket's relative width.
pub const DEFAULT_TOLERANCE: f64 = 0.005;
/// `max_trials` when the scene gives none: enough for a bracket from F = 1 to 32 and its
/// bisection to 1e-3 (5 + 15 trials) twice over.
pub const DEFAULT_MAX_TRIALS: usize = 40;
/// `trial_steps` when the scene gives none (`docs/stability.md`, 'Failure criterion').
pub const DEFAULT_TRIAL_STEPS: usize = 12;
/// The trials' Newton tolerance when the scene gives no `newton_tolerance` (or the
/// `[solver] tolerance` when looser). The criterion judges displacement increments at 1e-3
/// of the loading's; a relative residual of 1e-10 moves them by orders of magnitude less,
/// and saves up to 14% of a search's Newton iterations against 1e-12 (`docs/stability.md`,
/// 'Search').
pub const DEFAULT_NEWTON_TOLERANCE: f64 = 1e-10;

/// A validated `[stability]`.
#[derive(Debug, Clone, PartialEq)]
pub struct StabilitySettings {
    pub method: StabilityMethod,
    pub tolerance: f64,
    pub dilatancy: DilatancyRule,
    pub bracket: Option<[f64; 2]>,
    pub first_guess: f64,
    /// The monitored node and its monitor's name; `None`: the whole body.
    pub monitor: Option<(usize, String)>,
    pub max_trials: usize,
    pub trial_steps: usize,
    /// The Newton tolerance of a continued search's trials ([`DEFAULT_NEWTON_TOLERANCE`]).
    pub newton_tolerance: f64,
    /// Each trial starts from the largest stable trial's end state and the next factor
    /// is extrapolated from the stable trials' load–displacement curve
    /// (`docs/stability.md`, 'Search'); `false`: every trial from the equilibrium, the
    /// blind doubling and bisection (the search before issue 24, kept for comparison).
    /// No scene key: `true` for every scene.
    pub continuation: bool,
}

use super::bracket::{MAX_FACTOR, MIN_FACTOR};

impl StabilitySettings {
    /// `None` for a scene without `[stability]`; the loading ends with the scene's
    /// `[time]`, at `h · steps`.
    pub fn of<const D: usize>(
        scene: &impl StabilityScene<D>,
        model: &Model<D>,
    ) -> Result<Option<Self>, SceneError>
    where
        Mandel<D>: Dimension,
    {
        let time = scene.spec().time;
        Self::at(scene, model, time.step * time.steps as f64)
    }

    /// The same for a loading that ends at `end` (s): its ramps must have ended and its
    /// boundaries stopped by then.
    pub fn at<const D: usize>(
        scene: &impl StabilityScene<D>,
        model: &Model<D>,
        end: f64,
    ) -> Result<Option<Self>, SceneError>
    where
        Mandel<D>: Dimension,
    {
        let Some(spec) = &scene.spec().stability else {
            return Ok(None);
        };
        let tolerance = spec.tolerance.unwrap_or(DEFAULT_TOLERANCE);
        if !(tolerance.is_finite() && tolerance > 0.0 && tolerance < 1.0) {
            return Err(scene.error(
                "stability.tolerance",
                format!("{tolerance} must be finite and in (0, 1): the bracket's relative width"),
            ));
        }
        let dilatancy = match (spec.method, spec.dilatancy) {
            (StabilityMethod::GravityIncrease, Some(d)) => {
                return Err(scene.error(
                    "stability.dilatancy",
                    format!(
                        "\"{}\" applies to method = \"strength_reduction\" only",
                        d.name()
                    ),
                ))
            }
            (_, d) => d.unwrap_or(DilatancyRule::Scaled),
        };
        if spec.method == StabilityMethod::GravityIncrease && scene.spec().gravity.is_none() {
            return Err(scene.error(
                "stability.method",
                "\"gravity_increase\" multiplies `gravity`, which is not given",
            ));
        }
        if let (StabilityMethod::GravityIncrease, Some(g)) = (spec.method, scene.spec().gravity) {
            // Zero weight times any factor is zero: the search would never end.
            let g = g.as_ref();
            if g.iter().all(|c| *c == 0.0) {
                let zeros = vec!["0"; g.len()].join(", ");
                return Err(scene.error(
                    "gravity",
                    format!("[{zeros}] m/s²: \"gravity_increase\" has no weight to increase"),
                ));
            }
        }
        if let Some([lo, hi]) = spec.bracket {
            if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo) {
                return Err(scene.error(
                    "stability.bracket",
                    format!("[{lo}, {hi}] must be finite with 0 < lo < hi"),
                ));
            }
            if lo < MIN_FACTOR || hi > MAX_FACTOR {
                return Err(scene.error(
                    "stability.bracket",
                    format!(
                        "[{lo:e}, {hi:e}] must lie within [{MIN_FACTOR}, {MAX_FACTOR}]: a factor \
                         beyond divides or multiplies the strength or weight into what no \
                         soil has"
                    ),
                ));
            }
            if spec.first_guess.is_some() {
                return Err(scene.error(
                    "stability.first_guess",
                    "give either `bracket` or `first_guess`, not both",
                ));
            }
        }
        let first_guess = spec.first_guess.unwrap_or(1.0);
        if !(first_guess.is_finite() && (MIN_FACTOR..=MAX_FACTOR).contains(&first_guess)) {
            return Err(scene.error(
                "stability.first_guess",
                format!("{first_guess:e} must be finite and in [{MIN_FACTOR}, {MAX_FACTOR}]"),
            ));
        }
        let max_trials = spec.max_trials.unwrap_or(DEFAULT_MAX_TRIALS);
        if max_trials < 2 {
            return Err(scene.error(
                "stability.max_trials",
                format!("{max_trials} must be at least 2 (one stable, one failing trial)"),
            ));
        }
        let trial_steps = spec.trial_steps.unwrap_or(DEFAULT_TRIAL_STEPS);
        if trial_steps < super::criterion::MIN_STEPS {
            return Err(scene.error(
                "stability.trial_steps",
                format!(
                    "{trial_steps} must be at least {} (the criterion compares steps)",
                    super::criterion::MIN_STEPS
                ),
            ));
        }
        let newton_tolerance = match spec.newton_tolerance {
            Some(t) if !(t.is_finite() && t > 0.0 && t < 1.0) => {
                return Err(scene.error(
                    "stability.newton_tolerance",
                    format!("{t} must be finite and in (0, 1): the trials' relative residual"),
                ))
            }
            Some(t) => t,
            None => DEFAULT_NEWTON_TOLERANCE.max(scene.spec().solver.tolerance),
        };
        let monitor = match &spec.monitor {
            None => None,
            Some(name) => {
                let node = scene.monitor_node(model, name)?;
                let dofs = model.assembly.dofs();
                if (0..<Mandel<D> as Dimension>::COMPONENTS).all(|c| dofs.free(node, c).is_none()) {
                    return Err(scene.error(
                        "stability.monitor",
                        format!(
                            "\"{name}\" sits on node {node}, which every boundary condition \
                             holds still: its displacement cannot tell a mechanism; \
                             monitor a free point (the crest of a slope, the top of a cut)"
                        ),
                    ));
                }
                Some((node, name.clone()))
            }
        };
        check_loading_settles(scene, model, end)?;
        Ok(Some(Self {
            method: spec.method,
            tolerance,
            dilatancy,
            bracket: spec.bracket,
            first_guess,
            monitor,
            max_trials,
            trial_steps,
            newton_tolerance,
            continuation: true,
        }))
    }
}

/// The trials start from the state the scene's loading reached and hold that loading: it
/// must be quasi-static, every ramp must have ended by the loading's end `end` (s), and no
/// boundary may still move then.
fn check_loading_settles<const D: usize>(
    scene: &impl StabilityScene<D>,
    model: &Model<D>,
    end: f64,
) -> Result<(), SceneError>
where
    Mandel<D>: Dimension,
{
    let spec = scene.spec();
    if spec.analysis.kind != AnalysisKind::QuasiStatic {
        return Err(scene.error(
            "analysis.kind",
            "[stability] needs kind = \"quasi_static\": each trial is judged by how its \
             displacement increments grow, which inertia would blur",
        ));
    }
    for (field, ramp) in crate::scene::check::ramps(spec) {
        if let Some(last) = ramp.as_ref().and_then(|r| r.last()) {
            if last[0] > end * (1.0 + 1e-12) {
                return Err(scene.error(
                    &field,
                    format!(
                        "ends at t = {} s, after the loading's last step (t = {end} s): \
                         [stability] holds the loading of the last step",
                        last[0]
                    ),
                ));
            }
        }
    }
    let v = model.prescribed_velocity_at(end);
    if let Some(j) = v.iter().position(|v| *v != 0.0) {
        let k = model.dof_owner[j];
        return Err(scene.error(
            &format!("boundary[{k}].velocity"),
            format!(
                "{:?} m/s still moves at the end of the loading (t = {end} s): [stability] \
                 needs the body at rest under a held load",
                spec.boundary[k].velocity
            ),
        ));
    }
    Ok(())
}
