//! The one time-stepping engine of Talus, for finite elements and the material point
//! method alike (Guillet et al. 2024, §2.3: eqs. 15–16 per step). A [`Discretization`]
//! builds each sub-step's reduced problem `h z = Wσ + q` and applies its solution; the
//! engine's [`Stepper`] solves it with talus-ssn's semi-smooth Newton from a predictor,
//! halves a sub-step whose solve fails, and reports what each step cost
//! ([`StepReport`]); a [`Run`] adds the collapse watch. [`StepSettings`] has one preset per
//! method; [`Ramp`] is the load programmes' multiplier in time.
//!
//! No scene, file or terminal is read here: settings come in as this crate's types.
mod collapse;
mod discretization;
mod parabola;
mod ramp;
mod report;
mod run;
mod settings;
mod step_control;
mod stepper;

pub use collapse::{
    Collapse, CollapseWatch, Motion, COLLAPSE_DISPLACEMENT_RATIO, COLLAPSE_ENERGY_RATIO,
    COLLAPSE_RISING_STEPS,
};
pub use discretization::{Discretization, Loading, Problem};
pub use parabola::Parabola;
pub use ramp::{Ramp, RampError};
pub use report::{Predictor, StepError, StepReport};
pub use run::{Collapsed, Failed, Run};
pub use settings::{PredictorRule, StepSettings};
pub use step_control::{Growth, StepControl};
pub use stepper::{Stepper, StepperMemory};

// The README's example (a FEM model stepped with talus-fem alone), compiled and run as a
// doctest (`cargo test --doc`).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
