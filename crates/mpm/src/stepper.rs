//! The engine on an [`Mpm`] and one particle set whose time it keeps: for programs and
//! tests that step particles without a scene.
use talus_engine::{StepError, StepSettings, Stepper};

use crate::dimension::{Dimension, Mandel};
use crate::{Mpm, MpmError, MpmState, MpmStepReport, Particles};

pub struct MpmStepper<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    stepper: Stepper<Mpm<D>, D>,
    time: f64,
}

impl<const D: usize> MpmStepper<D>
where
    Mandel<D>: Dimension,
{
    /// With the MPM defaults ([`StepSettings::mpm`]).
    pub fn new(mpm: Mpm<D>) -> Self {
        Self::with_settings(mpm, StepSettings::mpm())
    }

    pub fn with_settings(mpm: Mpm<D>, settings: StepSettings) -> Self {
        Self {
            stepper: Stepper::new(mpm, settings),
            time: 0.0,
        }
    }

    pub fn mpm(&self) -> &Mpm<D> {
        self.stepper.discretization()
    }

    pub fn settings(&self) -> &StepSettings {
        self.stepper.settings()
    }

    /// Halvings the next step starts with (`talus_engine::StepControl`).
    pub fn remembered_halvings(&self) -> usize {
        self.stepper.remembered_halvings()
    }

    /// One step of `h` (s): `particles` are left as they were if it fails.
    pub fn advance(
        &mut self,
        particles: &mut Particles<D>,
        h: f64,
    ) -> Result<MpmStepReport<D>, StepError<MpmError>> {
        let mut state = MpmState {
            time: self.time,
            particles: std::mem::take(particles),
        };
        let result = self.stepper.advance(&mut state, h);
        self.time = state.time;
        *particles = state.particles;
        result
    }
}
