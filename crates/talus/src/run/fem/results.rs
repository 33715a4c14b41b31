//! What a run reports besides the solver: the named boundaries' reactions
//! and the monitors, appended to `history.csv`, and `summary.json` at the end
//! (`output::Results`, `docs/scenes.md`, 'Results'); the run loop (`run::steps`) writes it.
use crate::model::fem::ReactionForce;
use crate::model::fem::{
    prescribed_forces_at_rest, Model, NodeMonitors, ReactionGroups, State, StepRecord,
};
use crate::output::Results;
use crate::scene::{Scene, SceneError};

pub struct FemResults {
    groups: ReactionGroups,
    monitors: NodeMonitors,
    pub results: Results,
}

impl FemResults {
    /// The columns of `scene`'s named boundaries and monitors after `base` (history.csv's
    /// other columns).
    pub fn new(scene: &Scene, model: &Model, base: &str) -> Result<Self, SceneError> {
        let names: Vec<Option<String>> =
            scene.spec.boundary.iter().map(|b| b.name.clone()).collect();
        let groups = ReactionGroups::of_model(model, &names);
        let monitors = NodeMonitors::new(scene, model)?;
        let mut results = Results::new(
            base,
            &groups.names,
            &monitors.names,
            scene.spec.output.reaction.clone(),
        )
        .map_err(|e| scene.error(&e.field, e.message))?;
        results.set_force_unit(scene.spec.analysis.geometry.force_unit());
        for w in crate::model::fem::warnings(scene, model) {
            results.warn(w);
        }
        Ok(Self {
            groups,
            monitors,
            results,
        })
    }

    /// Step 0: the initial state at rest.
    pub fn initial(&mut self, model: &Model, state: &State, reaction: f64) -> String {
        let forces = self.groups.sums(&prescribed_forces_at_rest(model, state));
        let monitors = self.monitors.values(model, state);
        self.results
            .record(0, state.time, &forces, &monitors, Some((0.0, reaction)))
    }

    /// After `step`, with the footing displacement of the reported boundary.
    pub fn step(
        &mut self,
        model: &Model,
        state: &State,
        step: usize,
        record: &StepRecord,
        displacement: f64,
    ) -> String {
        let forces = record
            .stats
            .as_ref()
            .map(|s| self.groups.sums(&s.prescribed_forces))
            .unwrap_or_default();
        let monitors = self.monitors.values(model, state);
        self.results.record(
            step,
            state.time,
            &forces,
            &monitors,
            Some((displacement, record.reaction_force())),
        )
    }
}
