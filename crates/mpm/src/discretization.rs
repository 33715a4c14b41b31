//! The material point method as the stepping engine's [`Discretization`]: each sub-step
//! builds its own reduced system (the particles moved), and may ask for more solves while
//! the friction walls' stick/slide states settle.
use talus_engine::{Discretization, Loading, Motion, Problem, StepReport};
use talus_ssn::{ReducedSystem, SolveError};

use crate::dimension::{Dimension, Mandel, Vector};
use crate::{Mpm, MpmError, Particles, Substep, SubstepStats};

/// The particles and the time they are at.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(bound = "")]
pub struct MpmState<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub time: f64,
    pub particles: Particles<D>,
}

/// What one MPM step did.
pub type MpmStepReport<const D: usize = 4> = StepReport<SubstepStats<D>>;

/// The walls' and boxes' forces of an MPM step's report.
pub trait GroupForces {
    /// `[f64; 2]` or `[f64; 3]`.
    type Force;
    /// Force each wall, then each prescribed box, applied to the material in the step's
    /// last sub-step (N/m in 2D, N in 3D).
    fn group_forces(&self) -> &[Self::Force];
}

impl<const D: usize> GroupForces for MpmStepReport<D>
where
    Mandel<D>: Dimension,
{
    type Force = Vector<D>;
    fn group_forces(&self) -> &[Vector<D>] {
        self.stats.as_ref().map_or(&[], |s| &s.group_forces)
    }
}

impl<const D: usize> Discretization<D> for Mpm<D>
where
    Mandel<D>: Dimension,
{
    type State = MpmState<D>;
    type Substep = Substep<D>;
    type Stats = SubstepStats<D>;
    type Error = MpmError;

    fn fixed_system(&self, _: f64) -> Option<Result<ReducedSystem<D>, SolveError>> {
        None
    }

    fn time(&self, state: &MpmState<D>) -> f64 {
        state.time
    }

    fn stress<'s>(&self, state: &'s MpmState<D>) -> &'s [f64] {
        state.particles.stress.as_flattened()
    }

    /// Constant loads: nothing jumps after the start.
    fn loading(&self, _: &MpmState<D>, _: f64) -> Loading {
        Loading::default()
    }

    fn begin(&self, state: &MpmState<D>, h: f64) -> Result<(Substep<D>, Problem<D>), MpmError> {
        let (substep, system) = self.begin_substep(&state.particles, h)?;
        Ok((substep, Problem::System(system)))
    }

    fn after_solve(
        &self,
        substep: &mut Substep<D>,
        state: &MpmState<D>,
        sigma: &[f64],
        z: &[f64],
    ) -> Result<Option<Problem<D>>, MpmError> {
        Ok(substep
            .after_solve(self, &state.particles, sigma, z)?
            .map(Problem::System))
    }

    fn finish(
        &self,
        substep: Substep<D>,
        state: &mut MpmState<D>,
        sigma: Vec<f64>,
        _: &[f64],
        h: f64,
    ) -> Result<SubstepStats<D>, MpmError> {
        let stats = substep.finish(self, &mut state.particles, sigma)?;
        state.time += h;
        Ok(stats)
    }

    /// Large deformations are what the method is for: only the kinetic energy is watched
    /// (`docs/scenes.md`, 'Collapse').
    fn motion(&self, state: &MpmState<D>) -> Option<Motion> {
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
