//! `[[stage]]`: construction in stages (`docs/scenes.md`, 'Stages'). Each stage runs its
//! own `steps` of `[time] step`, after switching regions off (`deactivate`: excavation)
//! or on (`activate`: construction), setting a new water table, and the loads and
//! boundary conditions whose `stages` name it.
use serde::{Deserialize, Serialize};

use super::source::Locate;
use super::{SceneError, SceneSpec, SceneVector, WaterSpec};

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StageSpec {
    pub name: String,
    /// Steps of `[time] step` in this stage.
    pub steps: usize,
    /// Regions dug out at the stage's start: their stresses are released into the rest of
    /// the body over the stage's steps; their mass, weight and stiffness leave.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub deactivate: Vec<String>,
    /// Regions built at the stage's start: stress free, their weight ramped in over the
    /// stage's steps. A region a stage activates is absent before it.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub activate: Vec<String>,
    /// The water table from this stage on (default: the previous stage's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub water: Option<WaterSpec>,
    /// Displacements start from zero at this stage (stresses carry on).
    #[serde(default)]
    pub reset_displacements: bool,
    /// Run the scene's `[stability]` analysis on the state at the stage's end.
    #[serde(default)]
    pub factor_of_safety: bool,
}

impl<V: super::SceneVector> SceneSpec<V> {
    /// The steps of the whole run: `[time] steps`, or the stages' sum (saturated: the cap
    /// on steps refuses it, `scales::stage_steps_cap`).
    pub fn total_steps(&self) -> usize {
        if self.stage.is_empty() {
            self.time.steps
        } else {
            (self.stage.iter()).fold(0, |sum, s| sum.saturating_add(s.steps))
        }
    }
}

impl SceneSpec {
    /// Whether a load or boundary condition with `stages` (its `stages` key) acts in the
    /// stage named `stage` (`None`: an unstaged scene, where everything acts).
    pub fn acts_in(stages: &Option<Vec<String>>, stage: Option<&str>) -> bool {
        match (stages, stage) {
            (Some(names), Some(stage)) => names.iter().any(|n| n == stage),
            _ => true,
        }
    }
}

/// The stages and every `stages` key checked against each other: names unique and known,
/// steps at least 1, `[time] steps` left to the stages, a factor of safety only with
/// `[stability]`. Regions are checked against the mesh when the model is built.
pub fn check<V: SceneVector>(scene: &impl Locate, spec: &SceneSpec<V>) -> Result<(), SceneError> {
    let names: Vec<&str> = spec.stage.iter().map(|s| s.name.as_str()).collect();
    let keys = spec
        .boundary
        .iter()
        .enumerate()
        .map(|(k, b)| (format!("boundary[{k}].stages"), &b.stages))
        .chain(
            (spec.traction.iter().enumerate())
                .map(|(k, t)| (format!("traction[{k}].stages"), &t.stages)),
        )
        .chain(
            (spec.pressure.iter().enumerate())
                .map(|(k, p)| (format!("pressure[{k}].stages"), &p.stages)),
        )
        .chain(
            (spec.point_load.iter().enumerate())
                .map(|(k, p)| (format!("point_load[{k}].stages"), &p.stages)),
        );
    for (field, stages) in keys {
        let Some(stages) = stages else { continue };
        if names.is_empty() {
            return Err(scene.error(
                &field,
                "names stages, but the scene has no [[stage]]: remove the key or add stages",
            ));
        }
        for (j, s) in stages.iter().enumerate() {
            if !names.contains(&s.as_str()) {
                return Err(scene.error(
                    &format!("{field}[{j}]"),
                    format!(
                        "\"{s}\" is no stage of the scene (stages: {})",
                        names.join(", ")
                    ),
                ));
            }
        }
    }
    if spec.stage.is_empty() {
        return Ok(());
    }
    if spec.time.steps != 0 {
        return Err(scene.error(
            "time.steps",
            format!(
                "{} with [[stage]]: each stage gives its own `steps`, [time] gives `step` only",
                spec.time.steps
            ),
        ));
    }
    for (k, s) in spec.stage.iter().enumerate() {
        if s.name.trim().is_empty() {
            return Err(scene.error(&format!("stage[{k}].name"), "must not be empty"));
        }
        if let Some(j) = names[..k].iter().position(|n| *n == s.name) {
            return Err(scene.error(
                &format!("stage[{k}].name"),
                format!("\"{}\" is already the name of stage[{j}]", s.name),
            ));
        }
        if s.steps == 0 {
            return Err(scene.error(&format!("stage[{k}].steps"), "must be at least 1"));
        }
        if s.factor_of_safety && spec.stability.is_none() {
            return Err(scene.error(
                &format!("stage[{k}].factor_of_safety"),
                "needs a [stability] section (its method and settings) to run",
            ));
        }
    }
    if spec.stability.is_some() && !spec.stage.iter().any(|s| s.factor_of_safety) {
        return Err(scene.error(
            "stability",
            "with [[stage]], the analysis runs at the end of the stages that ask for it: \
             set factor_of_safety = true on one",
        ));
    }
    Ok(())
}
