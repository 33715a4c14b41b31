//! The generic part of a run: steps taken one after another by the [`Stepper`], each
//! accepted state read by the collapse watch (`docs/scenes.md`, 'Collapse'). What is
//! written after each step (histories, fields, checkpoints) is the caller's.
use std::ops::ControlFlow;

use crate::{Collapse, CollapseWatch, Discretization, StepError, StepReport, Stepper};

/// Where a run ended in collapse.
#[derive(Debug, Clone, PartialEq)]
pub struct Collapsed {
    /// The step after which the criterion held (MPM: the step that left the grid), and
    /// the time it started from (s).
    pub step: usize,
    pub time: f64,
    pub why: Collapse,
}

impl std::fmt::Display for Collapsed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "collapse at step {} (t = {:.6e} s): {}",
            self.step, self.time, self.why
        )
    }
}

/// A step that failed: the stepper's error, and the collapse it means when the body left
/// what the method represents while accelerating.
#[derive(Debug)]
pub struct Failed<E: std::error::Error + 'static> {
    pub step: usize,
    pub error: StepError<E>,
    pub collapse: Option<Collapsed>,
}

/// A [`Stepper`] and the collapse watch over the states it accepts.
pub struct Run<'s, M: Discretization<D>, const D: usize = 4> {
    pub stepper: &'s mut Stepper<M, D>,
    pub watch: CollapseWatch,
}

impl<'s, M: Discretization<D>, const D: usize> Run<'s, M, D> {
    /// A run from `state`, which the watch reads as its first.
    pub fn start(stepper: &'s mut Stepper<M, D>, state: &M::State) -> Self {
        let mut watch = CollapseWatch::new();
        if let Some(m) = stepper.discretization().motion(state) {
            watch.observe(&m);
        }
        Self { stepper, watch }
    }

    /// A run that goes on with the watch it had (a resumed run).
    pub fn resume(stepper: &'s mut Stepper<M, D>, watch: CollapseWatch) -> Self {
        Self { stepper, watch }
    }

    /// Step `step` of `h` (s) from `state`: its report and, when the criterion holds after
    /// it, the collapse. On failure `state` is as before the step.
    #[allow(clippy::type_complexity)]
    pub fn step(
        &mut self,
        state: &mut M::State,
        step: usize,
        h: f64,
    ) -> Result<(StepReport<M::Stats>, Option<Collapsed>), Failed<M::Error>> {
        let disc = self.stepper.discretization();
        let time = disc.time(state);
        match self.stepper.advance(state, h) {
            Ok(report) => {
                let disc = self.stepper.discretization();
                let motion = disc.motion(state);
                let collapse = motion
                    .and_then(|m| self.watch.observe(&m))
                    .map(|why| Collapsed {
                        step,
                        time: disc.time(state),
                        why,
                    });
                Ok((report, collapse))
            }
            Err(error) => {
                // A step that left the domain while the body accelerated: the collapse is
                // the cause, not the grid.
                let left = matches!(&error, StepError::Discretization(d)
                    if self.stepper.discretization().left_domain(d));
                let collapse = left
                    .then(|| self.watch.on_leaving_domain())
                    .flatten()
                    .map(|why| Collapsed { step, time, why });
                Err(Failed {
                    step,
                    error,
                    collapse,
                })
            }
        }
    }

    /// Steps `first..=last` of `h` (s) from `state`, calling `after` with each accepted
    /// step; `Break` from it ends the run after that step. Returns the reports and the
    /// collapse that ended the run, if one did.
    #[allow(clippy::type_complexity)]
    pub fn steps(
        &mut self,
        state: &mut M::State,
        first: usize,
        last: usize,
        h: f64,
        mut after: impl FnMut(usize, &M::State, &StepReport<M::Stats>) -> ControlFlow<()>,
    ) -> Result<(Vec<StepReport<M::Stats>>, Option<Collapsed>), Failed<M::Error>> {
        let mut reports = Vec::new();
        for step in first..=last {
            let (report, collapse) = self.step(state, step, h)?;
            let stop = after(step, state, &report).is_break();
            reports.push(report);
            if collapse.is_some() {
                return Ok((reports, collapse));
            }
            if stop {
                break;
            }
        }
        Ok((reports, None))
    }
}
