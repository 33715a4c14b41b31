//! The material point method as the stepping engine's [`Discretization`]: each sub-step
//! builds its own reduced system (the particles moved), and may ask for more solves while
//! the friction walls' stick/slide states settle.
use talus_engine::{Discretization, Loading, Motion, Problem, StepReport};
use talus_ssn::{ReducedSystem, SolveError};

use crate::{Mpm, MpmError, Particles, Substep, SubstepStats};

/// The particles and the time they are at.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MpmState {
    pub time: f64,
    pub particles: Particles,
}

/// What one MPM step did.
pub type MpmStepReport = StepReport<SubstepStats>;

/// The walls' and boxes' forces of an MPM step's report.
pub trait GroupForces {
    /// Force each wall, then each prescribed box, applied to the material in the step's
    /// last sub-step (N/m).
    fn group_forces(&self) -> &[[f64; 2]];
}

impl GroupForces for MpmStepReport {
    fn group_forces(&self) -> &[[f64; 2]] {
        self.stats.as_ref().map_or(&[], |s| &s.group_forces)
    }
}

impl Discretization for Mpm {
    type State = MpmState;
    type Substep = Substep;
    type Stats = SubstepStats;
    type Error = MpmError;

    fn fixed_system(&self, _: f64) -> Option<Result<ReducedSystem<4>, SolveError>> {
        None
    }

    fn time(&self, state: &MpmState) -> f64 {
        state.time
    }

    fn stress<'s>(&self, state: &'s MpmState) -> &'s [f64] {
        state.particles.stress.as_flattened()
    }

    /// Constant loads: nothing jumps after the start.
    fn loading(&self, _: &MpmState, _: f64) -> Loading {
        Loading::default()
    }

    fn begin(&self, state: &MpmState, h: f64) -> Result<(Substep, Problem), MpmError> {
        let (substep, system) = self.begin_substep(&state.particles, h)?;
        Ok((substep, Problem::System(system)))
    }

    fn after_solve(
        &self,
        substep: &mut Substep,
        state: &MpmState,
        sigma: &[f64],
        z: &[f64],
    ) -> Result<Option<Problem>, MpmError> {
        Ok(substep
            .after_solve(self, &state.particles, sigma, z)?
            .map(Problem::System))
    }

    fn finish(
        &self,
        substep: Substep,
        state: &mut MpmState,
        sigma: Vec<f64>,
        _: &[f64],
        h: f64,
    ) -> Result<SubstepStats, MpmError> {
        let stats = substep.finish(self, &mut state.particles, sigma)?;
        state.time += h;
        Ok(stats)
    }

    /// Large deformations are what the method is for: only the kinetic energy is watched
    /// (`docs/scenes.md`, 'Collapse').
    fn motion(&self, state: &MpmState) -> Option<Motion> {
        Some(Motion {
            kinetic_energy: crate::kinetic_energy(&state.particles),
            prescribed_kinetic_energy: 0.0,
            free_displacement_ratio: None,
        })
    }

    fn left_domain(&self, error: &MpmError) -> bool {
        matches!(error, MpmError::ParticleLeftGrid { .. })
    }
}
