//! Factor of safety (`[stability]`, `docs/stability.md`): the scene's loading brings the
//! body to equilibrium, then each trial factor `F` restarts from that state with the
//! strength divided by `F` (strength reduction) or gravity multiplied by `F` (gravity
//! increase), stepped by the one engine until the criterion calls it stable or failing;
//! `F` is bracketed, then bisected to the tolerance.
//!
//! [`run`] is the whole of `talus run` on such a scene. A caller with its own loading (a
//! construction stage asking for the factor of safety of the state at its end) builds the
//! analysis with [`Analysis::from_model`] and calls [`search`] with its equilibrium state.
pub mod bracket;
pub mod continuation;
pub mod criterion;
mod outputs;
mod scene;
pub mod settings;
pub mod strength;
pub mod trial;

use std::time::Instant;

use talus_bipotential::Material;
use talus_fem::{Dimension, Mandel};

use crate::model::fem::{Model, State};
use crate::run::RunError;
use crate::scene::{SceneError, StabilityMethod};
use talus_engine::{Failed, Run, StepSettings, Stepper};

pub use bracket::{Bracket, Guide, Next, Outcome};
pub use continuation::Planner;
pub use criterion::{Criterion, Verdict};
pub use outputs::{
    run, run_blind, search, write_mechanism, SearchStatus, StabilityRun, TRIAL_COLUMNS,
};
pub use scene::StabilityScene;
pub use settings::StabilitySettings;
pub use strength::{plane_strain_match, Strength};
pub use trial::{Trial, TrialPredictor};

/// The loading phase: the scene's own steps from its initial state ([`Analysis::equilibrium`]),
/// or a caller's (a construction stage's end, given to [`search`]); 2D (`D = 4`) or 3D
/// (`D = 6`).
#[derive(Debug, Clone)]
pub struct Equilibrium<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    /// The state the trials restart from. Its largest nodal displacement is the
    /// criterion's scale `U` ([`Criterion::set_scale`], which [`search`] calls).
    pub state: State<D>,
    /// Steps, Newton iterations and seconds of the loading: `history.csv`'s row 0 only.
    pub steps: usize,
    pub newton_iterations: usize,
    pub seconds: f64,
    /// The criterion's measure over the last loading step (m): row 0's `last_increment`
    /// only (a caller may give 0).
    pub last_increment: f64,
}

/// A scene set up for trials: the model (its material or gravity changed per trial), the
/// scene's material and gravity at factor 1, the stepping settings and the criterion; in 2D
/// (`D = 4`) or 3D (`D = 6`).
pub struct Analysis<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub model: Model<D>,
    pub settings: StabilitySettings,
    pub criterion: Criterion,
    step_settings: StepSettings,
    h: f64,
    steps: usize,
    /// The scene's materials at factor 1, and whether strength reduction weakens each.
    scene_materials: Vec<Material>,
    reduce: Vec<bool>,
    /// The forces at factor 1 (gravity increase adds `(F − 1)` times the weight).
    force_free: Vec<f64>,
    force_prescribed: Vec<f64>,
    /// The weight at the end of the loading (N/m), free and prescribed dofs.
    weight: Option<(Vec<f64>, Vec<f64>)>,
    /// Where the scene's `[stability]` is: errors of a trial name it.
    located: SceneError,
}

impl<const D: usize> Analysis<D>
where
    Mandel<D>: Dimension,
{
    /// `None` for a scene without `[stability]`: [`Analysis::from_model`] with the
    /// scene's model and the end of its `[time]`, `h · steps`.
    pub fn new(scene: &impl StabilityScene<D>) -> Result<Option<Self>, RunError> {
        let model = scene.build_model()?;
        let time = scene.spec().time;
        Self::from_model(scene, model, time.step * time.steps as f64)
    }

    /// The analysis of `scene`'s `[stability]` on `model` (built from `scene`, possibly
    /// changed since: a stage's regions) whose loading ends at `end_time` (s): the
    /// trials hold the loads of `end_time`, the ramps must have ended by then and no
    /// boundary may still move (`settings`), and gravity increase adds the weight of
    /// `end_time`'s gravity multiplier. `None` for a scene without `[stability]`. The
    /// model is set to F = 1.
    pub fn from_model(
        scene: &impl StabilityScene<D>,
        model: Model<D>,
        end_time: f64,
    ) -> Result<Option<Self>, RunError> {
        let Some(settings) = StabilitySettings::at(scene, &model, end_time)? else {
            return Ok(None);
        };
        let spec = scene.spec();
        let (h, steps) = (spec.time.step, spec.time.steps);
        let weight = match (settings.method, spec.gravity) {
            (StabilityMethod::GravityIncrease, Some(g)) => {
                let (free, prescribed) = scene.weight(&model, g)?;
                let ramp = crate::scene::check::ramp(scene, "gravity_ramp", &spec.gravity_ramp)?;
                let f = ramp.map_or(1.0, |r| r.at(end_time));
                Some((
                    free.iter().map(|v| f * v).collect(),
                    prescribed.iter().map(|v| f * v).collect(),
                ))
            }
            _ => None,
        };
        let criterion =
            Criterion::new(settings.monitor.as_ref().map(|m| m.0), settings.trial_steps);
        let mut analysis = Self {
            step_settings: spec.solver.fem(),
            h,
            steps,
            scene_materials: model.materials.clone(),
            reduce: spec.material.all().iter().map(|m| m.reduced()).collect(),
            force_free: model.force_free.clone(),
            force_prescribed: model.force_prescribed.clone(),
            weight,
            criterion,
            settings,
            model,
            located: scene.error("stability", ""),
        };
        // The loading phase runs with the material of F = 1 (for strength reduction, the
        // matched cone of `strength::drucker_prager`).
        analysis
            .set_factor(1.0)
            .map_err(|e| scene.error("material", e))?;
        Ok(Some(analysis))
    }

    /// Sets the model to factor `f`.
    pub fn set_factor(&mut self, f: f64) -> Result<(), String> {
        match self.settings.method {
            StabilityMethod::StrengthReduction => {
                let mut materials = self.scene_materials.clone();
                for (m, reduce) in materials.iter_mut().zip(&self.reduce) {
                    let Material::DruckerPrager(dp) = m else {
                        continue;
                    };
                    if !reduce {
                        continue;
                    }
                    let params = dp.parameters();
                    let reduced = Strength::of(params).reduced(f, self.settings.dilatancy);
                    *m = Material::DruckerPrager(
                        strength::drucker_prager(params, &reduced)
                            .map_err(|e| format!("the strength reduced by F = {f}: {e}"))?,
                    );
                }
                self.model
                    .set_materials(materials)
                    .map_err(|e| e.to_string())?;
            }
            StabilityMethod::GravityIncrease => {
                let (free, prescribed) = self.weight.as_ref().ok_or("no gravity")?;
                for (k, v) in self.model.force_free.iter_mut().enumerate() {
                    *v = self.force_free[k] + (f - 1.0) * free[k];
                }
                for (k, v) in self.model.force_prescribed.iter_mut().enumerate() {
                    *v = self.force_prescribed[k] + (f - 1.0) * prescribed[k];
                }
            }
        }
        Ok(())
    }

    /// The Newton tolerance of [`Analysis::trial_from`]'s steps: the continued search's
    /// [`StabilitySettings::newton_tolerance`], the blind search's `[solver] tolerance`.
    pub fn trial_tolerance(&self) -> f64 {
        if self.settings.continuation {
            self.settings.newton_tolerance
        } else {
            self.step_settings.solver.tolerance
        }
    }

    /// A `[stability]` error of this scene (a trial's material that cannot be built).
    pub(crate) fn error(&self, message: String) -> SceneError {
        SceneError {
            message,
            ..self.located.clone()
        }
    }

    /// The scene's loading, `time.steps` steps of `time.step` from its initial state, with
    /// the material of F = 1, watched for collapse as a plain run is (`docs/scenes.md`,
    /// 'Collapse'): a body that accelerates away under its loading has no equilibrium to
    /// start trials from, `RunError::Collapsed`.
    pub fn equilibrium(
        &mut self,
        scene: &impl StabilityScene<D>,
    ) -> Result<Equilibrium<D>, RunError> {
        let start = Instant::now();
        self.set_factor(1.0)
            .map_err(|e| scene.error("material", e))?;
        let mut state = scene.initial_state(&self.model)?;
        let mut stepper = Stepper::new(&self.model, self.step_settings);
        let mut run = Run::start(&mut stepper, &state);
        let mut newton_iterations = 0;
        let mut last_increment = 0.0;
        for step in 1..=self.steps {
            let before = state.displacement.clone();
            let (report, collapse) = match run.step(&mut state, step, self.h) {
                Ok(r) => r,
                Err(Failed {
                    collapse: Some(c), ..
                }) => return Err(RunError::Collapsed(c)),
                Err(Failed { step, error, .. }) => {
                    return Err(RunError::Step {
                        step,
                        source: error,
                    })
                }
            };
            if let Some(c) = collapse {
                return Err(RunError::Collapsed(c));
            }
            newton_iterations += report.total_newton_iterations();
            let mut du = before.clone();
            trial::difference(&mut du, &state.displacement, &before);
            last_increment = self.criterion.measure(&du);
        }
        self.criterion.set_scale(&state.displacement);
        Ok(Equilibrium {
            state,
            steps: self.steps,
            newton_iterations,
            seconds: start.elapsed().as_secs_f64(),
            last_increment,
        })
    }

    /// One trial at factor `f` from `equilibrium`, with the scene's predictor.
    pub fn trial(&mut self, f: f64, equilibrium: &State<D>) -> Result<Trial<D>, String> {
        self.set_factor(f)?;
        let (trial, _) = trial::run_trial_from(
            &self.model,
            self.step_settings,
            TrialPredictor::Scene,
            (equilibrium, None),
            equilibrium,
            f,
            self.h,
            &self.criterion,
        );
        Ok(trial)
    }

    /// One trial at factor `f` from `start`, the end state of the stable trial at factor
    /// `start.1` (`None`: `equilibrium` itself); the trial, and its end state when it is
    /// stable (the next trials' start). Its [`Trial::moved`] is measured from `equilibrium`.
    ///
    /// A continued search's steps follow the motion ([`TrialPredictor::FollowMotion`]) and
    /// stop Newton at [`StabilitySettings::newton_tolerance`]; the blind one keeps the
    /// scene's predictor and `[solver] tolerance`. Measured in `docs/stability.md`,
    /// 'Search'.
    pub fn trial_from(
        &mut self,
        f: f64,
        start: (&State<D>, Option<f64>),
        equilibrium: &State<D>,
    ) -> Result<(Trial<D>, Option<State<D>>), String> {
        self.set_factor(f)?;
        let mut settings = self.step_settings;
        settings.solver.tolerance = self.trial_tolerance();
        let predictor = if self.settings.continuation {
            TrialPredictor::FollowMotion
        } else {
            TrialPredictor::Scene
        };
        Ok(trial::run_trial_from(
            &self.model,
            settings,
            predictor,
            start,
            equilibrium,
            f,
            self.h,
            &self.criterion,
        ))
    }
}
