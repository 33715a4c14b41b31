//! What the stepping engine asks of a discretization (FEM, MPM): per sub-step, the reduced
//! problem of eqs. 15–16 (`B`, `M`, `S`, loads), and the update once the solve converged.
//! The engine runs the Newton solves; a discretization never does.
use talus_bipotential::FlowRule;
use talus_ssn::{ReducedSystem, SolveError};

use crate::Motion;

/// The reduced problem `h z = Wσ + q` of one solve.
pub enum Problem<const D: usize = 4> {
    /// `q` for the operator [`Discretization::fixed_system`] gave for this `h` (FEM: `W`
    /// does not depend on the state under small strains, only `q` changes).
    Rhs(Vec<f64>),
    /// `q` and the points' flow rules for the fixed operator (FEM under a pore pressure
    /// that changes in time: the cones moved, `W` did not).
    RhsAndRules(Vec<f64>, Vec<FlowRule<D>>),
    /// A whole system (MPM: the particles moved, so `B` and `M` changed).
    System(ReducedSystem<D>),
}

/// How the loading of a sub-step `[t₀, t₁]` relates to the one before it, for the predictor
/// (`docs/scenes.md`, 'Load programmes').
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Loading {
    /// The loading rate jumps at `t₀` (start from rest, a velocity jump, a ramp's kink):
    /// the last stress rate does not predict this sub-step.
    pub jumps: bool,
    /// The loading is not smooth over the sub-step (a jump at its start included): its
    /// stress rate will not predict the next one.
    pub changes_inside: bool,
}

/// `D` is the Mandel size of a stress point: 4 in plane strain and axisymmetry, 6 in 3D.
pub trait Discretization<const D: usize = 4> {
    /// What is carried from step to step (stress, velocities, displacements or particles).
    type State: Clone;
    /// What one sub-step keeps from its first solve to its update.
    type Substep;
    /// What a converged sub-step measured (reactions, grid size), kept for the step's last.
    type Stats: Clone + std::fmt::Debug;
    type Error: std::error::Error + Send + Sync + 'static;

    /// The reduced system of every sub-step of length `h` when it does not depend on the
    /// state (then [`Discretization::begin`] returns [`Problem::Rhs`]); `None` otherwise.
    fn fixed_system(&self, h: f64) -> Option<Result<ReducedSystem<D>, SolveError>>;

    /// The state's time (s).
    fn time(&self, state: &Self::State) -> f64;

    /// σₙ: the Mandel stress per point, flat, the Newton iteration's unknown.
    fn stress<'s>(&self, state: &'s Self::State) -> &'s [f64];

    /// The loading of the sub-step of length `h` from `state`, for the predictor.
    fn loading(&self, state: &Self::State, h: f64) -> Loading;

    /// Eqs. 15–16 for the sub-step of length `h` from `state`.
    fn begin(
        &self,
        state: &Self::State,
        h: f64,
    ) -> Result<(Self::Substep, Problem<D>), Self::Error>;

    /// After a converged solve (`sigma`, `z = Wσ + q`): `None` when the sub-step is
    /// settled, or the next problem to solve from `sigma` (MPM's friction passes).
    fn after_solve(
        &self,
        substep: &mut Self::Substep,
        state: &Self::State,
        sigma: &[f64],
        z: &[f64],
    ) -> Result<Option<Problem<D>>, Self::Error>;

    /// Moves `state` to the end of the sub-step from the last solve (eqs. 13–15).
    fn finish(
        &self,
        substep: Self::Substep,
        state: &mut Self::State,
        sigma: Vec<f64>,
        z: &[f64],
        h: f64,
    ) -> Result<Self::Stats, Self::Error>;

    /// The state's motion for the collapse watch (`docs/scenes.md`, 'Collapse'); `None`:
    /// not watched.
    fn motion(&self, _state: &Self::State) -> Option<Motion> {
        None
    }

    /// Whether `error` says the body left what the method can represent (MPM: a particle
    /// left the grid): during accelerating motion, a collapse.
    fn left_domain(&self, _error: &Self::Error) -> bool {
        false
    }
}

impl<T: Discretization<D>, const D: usize> Discretization<D> for &T {
    type State = T::State;
    type Substep = T::Substep;
    type Stats = T::Stats;
    type Error = T::Error;

    fn fixed_system(&self, h: f64) -> Option<Result<ReducedSystem<D>, SolveError>> {
        (**self).fixed_system(h)
    }
    fn time(&self, state: &Self::State) -> f64 {
        (**self).time(state)
    }
    fn stress<'s>(&self, state: &'s Self::State) -> &'s [f64] {
        (**self).stress(state)
    }
    fn loading(&self, state: &Self::State, h: f64) -> Loading {
        (**self).loading(state, h)
    }
    fn begin(
        &self,
        state: &Self::State,
        h: f64,
    ) -> Result<(Self::Substep, Problem<D>), Self::Error> {
        (**self).begin(state, h)
    }
    fn after_solve(
        &self,
        substep: &mut Self::Substep,
        state: &Self::State,
        sigma: &[f64],
        z: &[f64],
    ) -> Result<Option<Problem<D>>, Self::Error> {
        (**self).after_solve(substep, state, sigma, z)
    }
    fn finish(
        &self,
        substep: Self::Substep,
        state: &mut Self::State,
        sigma: Vec<f64>,
        z: &[f64],
        h: f64,
    ) -> Result<Self::Stats, Self::Error> {
        (**self).finish(substep, state, sigma, z, h)
    }
    fn motion(&self, state: &Self::State) -> Option<Motion> {
        (**self).motion(state)
    }
    fn left_domain(&self, error: &Self::Error) -> bool {
        (**self).left_domain(error)
    }
}
