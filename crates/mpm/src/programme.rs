//! An MPM model's load programmes (`docs/scenes.md`, 'Load programmes'): the sub-step from
//! `tₙ` to `tₙ₊₁` is implicit, so it takes gravity, the prescribed velocities and the surface
//! loads of `tₙ₊₁`, each scaled by its ramp there. `talus-mpm` applies the values
//! ([`SubstepLoads`]) per sub-step; the ramps are kept here.
use std::ops::Deref;

use talus_engine::{Discretization, Loading, Motion, Problem, Ramp};
use talus_ssn::{ReducedSystem, SolveError};

use crate::dimension::{Dimension, Mandel, Vector};
use crate::{Mpm, MpmError, MpmState, Particles, Substep, SubstepLoads, SubstepStats};

/// A surface load that follows a ramp: its particles and their forces at multiplier 1
/// (N/m), kept apart from `Particles::external_force` (the constant loads) so that each
/// sub-step's force is `ramp(tₙ₊₁) · force`, never a product of past scalings.
#[derive(Debug, Clone, PartialEq)]
pub struct RampedSurfaceLoad<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub ramp: Ramp,
    pub particles: Vec<usize>,
    pub force: Vec<Vector<D>>,
}

/// The ramps of an MPM scene; `None` and an empty list are the constant multiplier 1.
#[derive(Debug, Clone, PartialEq)]
pub struct MpmLoadProgramme<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub gravity: Option<Ramp>,
    /// One per `[[prescribed]]` box, in order.
    pub prescribed: Vec<Option<Ramp>>,
    pub surface_loads: Vec<RampedSurfaceLoad<D>>,
}

impl<const D: usize> Default for MpmLoadProgramme<D>
where
    Mandel<D>: Dimension,
{
    fn default() -> Self {
        Self {
            gravity: None,
            prescribed: Vec::new(),
            surface_loads: Vec::new(),
        }
    }
}

impl<const D: usize> MpmLoadProgramme<D>
where
    Mandel<D>: Dimension,
{
    /// The loads of a sub-step ending at `t` (s) from `particles`: without any ramp, the
    /// constant loads exactly ([`SubstepLoads::default`]).
    pub fn loads_at(&self, t: f64, particles: &Particles<D>) -> SubstepLoads<D> {
        let prescribed = if self.prescribed.iter().any(Option::is_some) {
            self.prescribed
                .iter()
                .map(|r| r.as_ref().map_or(1.0, |r| r.at(t)))
                .collect()
        } else {
            Vec::new()
        };
        let external_force = (!self.surface_loads.is_empty()).then(|| {
            let mut force = particles.external_force.clone();
            for load in &self.surface_loads {
                let f = load.ramp.at(t);
                for (&p, f1) in load.particles.iter().zip(&load.force) {
                    for a in 0..Mandel::<D>::AXES {
                        force[p][a] += f * f1[a];
                    }
                }
            }
            force
        });
        SubstepLoads {
            gravity: self.gravity.as_ref().map_or(1.0, |r| r.at(t)),
            prescribed,
            external_force,
        }
    }
}

/// The MPM of a scene with its load programme: what the engine steps. It reads as the
/// [`Mpm`] it holds.
#[derive(Debug, Clone)]
pub struct ProgrammedMpm<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    mpm: Mpm<D>,
    programme: MpmLoadProgramme<D>,
}

impl<const D: usize> ProgrammedMpm<D>
where
    Mandel<D>: Dimension,
{
    pub fn new(mpm: Mpm<D>, programme: MpmLoadProgramme<D>) -> Self {
        Self { mpm, programme }
    }

    pub fn programme(&self) -> &MpmLoadProgramme<D> {
        &self.programme
    }
}

impl<const D: usize> Deref for ProgrammedMpm<D>
where
    Mandel<D>: Dimension,
{
    type Target = Mpm<D>;

    fn deref(&self) -> &Mpm<D> {
        &self.mpm
    }
}

/// As [`Mpm`]'s, but each sub-step begins under the loads of its end time.
impl<const D: usize> Discretization<D> for ProgrammedMpm<D>
where
    Mandel<D>: Dimension,
{
    type State = MpmState<D>;
    type Substep = Substep<D>;
    type Stats = SubstepStats<D>;
    type Error = MpmError;

    fn fixed_system(&self, h: f64) -> Option<Result<ReducedSystem<D>, SolveError>> {
        self.mpm.fixed_system(h)
    }

    fn time(&self, state: &MpmState<D>) -> f64 {
        state.time
    }

    fn stress<'s>(&self, state: &'s MpmState<D>) -> &'s [f64] {
        self.mpm.stress(state)
    }

    /// The MPM predictors (`[mpm] predictor`: the last stresses or an elastic solve) never
    /// extrapolate a stress rate, so they need not know where the ramps bend.
    fn loading(&self, state: &MpmState<D>, h: f64) -> Loading {
        self.mpm.loading(state, h)
    }

    fn begin(&self, state: &MpmState<D>, h: f64) -> Result<(Substep<D>, Problem<D>), MpmError> {
        let loads = self.programme.loads_at(state.time + h, &state.particles);
        let (substep, system) = self.mpm.begin_substep_with(&state.particles, h, &loads)?;
        Ok((substep, Problem::System(system)))
    }

    fn after_solve(
        &self,
        substep: &mut Substep<D>,
        state: &MpmState<D>,
        sigma: &[f64],
        z: &[f64],
    ) -> Result<Option<Problem<D>>, MpmError> {
        self.mpm.after_solve(substep, state, sigma, z)
    }

    fn finish(
        &self,
        substep: Substep<D>,
        state: &mut MpmState<D>,
        sigma: Vec<f64>,
        z: &[f64],
        h: f64,
    ) -> Result<SubstepStats<D>, MpmError> {
        self.mpm.finish(substep, state, sigma, z, h)
    }

    fn motion(&self, state: &MpmState<D>) -> Option<Motion> {
        self.mpm.motion(state)
    }

    fn left_domain(&self, error: &MpmError) -> bool {
        self.mpm.left_domain(error)
    }
}
