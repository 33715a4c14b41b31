//! An MPM model's load programmes (`docs/scenes.md`, 'Load programmes'): the sub-step from
//! `tₙ` to `tₙ₊₁` is implicit, so it takes gravity, the prescribed velocities and the surface
//! loads of `tₙ₊₁`, each scaled by its ramp there. `talus-mpm` applies the values
//! ([`SubstepLoads`]) per sub-step; the ramps are kept here.
use std::ops::Deref;

use talus_engine::{Discretization, Loading, Motion, Problem, Ramp};
use talus_ssn::{ReducedSystem, SolveError};

use crate::{Mpm, MpmError, MpmState, Particles, Substep, SubstepLoads, SubstepStats};

/// A surface load that follows a ramp: its particles and their forces at multiplier 1
/// (N/m), kept apart from `Particles::external_force` (the constant loads) so that each
/// sub-step's force is `ramp(tₙ₊₁) · force`, never a product of past scalings.
#[derive(Debug, Clone, PartialEq)]
pub struct RampedSurfaceLoad {
    pub ramp: Ramp,
    pub particles: Vec<usize>,
    pub force: Vec<[f64; 2]>,
}

/// The ramps of an MPM scene; `None` and an empty list are the constant multiplier 1.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MpmLoadProgramme {
    pub gravity: Option<Ramp>,
    /// One per `[[prescribed]]` box, in order.
    pub prescribed: Vec<Option<Ramp>>,
    pub surface_loads: Vec<RampedSurfaceLoad>,
}

impl MpmLoadProgramme {
    /// The loads of a sub-step ending at `t` (s) from `particles`: without any ramp, the
    /// constant loads exactly ([`SubstepLoads::default`]).
    pub fn loads_at(&self, t: f64, particles: &Particles) -> SubstepLoads {
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
                    force[p][0] += f * f1[0];
                    force[p][1] += f * f1[1];
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
pub struct ProgrammedMpm {
    mpm: Mpm,
    programme: MpmLoadProgramme,
}

impl ProgrammedMpm {
    pub fn new(mpm: Mpm, programme: MpmLoadProgramme) -> Self {
        Self { mpm, programme }
    }

    pub fn programme(&self) -> &MpmLoadProgramme {
        &self.programme
    }
}

impl Deref for ProgrammedMpm {
    type Target = Mpm;

    fn deref(&self) -> &Mpm {
        &self.mpm
    }
}

/// As [`Mpm`]'s, but each sub-step begins under the loads of its end time.
impl Discretization for ProgrammedMpm {
    type State = MpmState;
    type Substep = Substep;
    type Stats = SubstepStats;
    type Error = MpmError;

    fn fixed_system(&self, h: f64) -> Option<Result<ReducedSystem<4>, SolveError>> {
        self.mpm.fixed_system(h)
    }

    fn time(&self, state: &MpmState) -> f64 {
        state.time
    }

    fn stress<'s>(&self, state: &'s MpmState) -> &'s [f64] {
        self.mpm.stress(state)
    }

    /// The MPM predictors (`[mpm] predictor`: the last stresses or an elastic solve) never
    /// extrapolate a stress rate, so they need not know where the ramps bend.
    fn loading(&self, state: &MpmState, h: f64) -> Loading {
        self.mpm.loading(state, h)
    }

    fn begin(&self, state: &MpmState, h: f64) -> Result<(Substep, Problem), MpmError> {
        let loads = self.programme.loads_at(state.time + h, &state.particles);
        let (substep, system) = self.mpm.begin_substep_with(&state.particles, h, &loads)?;
        Ok((substep, Problem::System(system)))
    }

    fn after_solve(
        &self,
        substep: &mut Substep,
        state: &MpmState,
        sigma: &[f64],
        z: &[f64],
    ) -> Result<Option<Problem>, MpmError> {
        self.mpm.after_solve(substep, state, sigma, z)
    }

    fn finish(
        &self,
        substep: Substep,
        state: &mut MpmState,
        sigma: Vec<f64>,
        z: &[f64],
        h: f64,
    ) -> Result<SubstepStats, MpmError> {
        self.mpm.finish(substep, state, sigma, z, h)
    }

    fn motion(&self, state: &MpmState) -> Option<Motion> {
        self.mpm.motion(state)
    }

    fn left_domain(&self, error: &MpmError) -> bool {
        self.mpm.left_domain(error)
    }
}
