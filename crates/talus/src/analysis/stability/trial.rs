//! One trial factor `F`: the model with the strength divided (or gravity multiplied) by `F`,
//! stepped by the engine from a start state until the criterion decides. The search starts
//! each trial from the state of the largest stable trial so far (the loading's equilibrium
//! before any): `docs/stability.md`, 'Procedure'.
use std::time::Instant;

use crate::model::fem::{Model, State};
use talus_engine::{PredictorRule, StepSettings, Stepper};
use talus_fem::{Dimension, Mandel};

use super::criterion::{Criterion, Verdict};

/// A node's vector in a model of Mandel size `D`: `[f64; 2]` or `[f64; 3]`.
pub type Point<const D: usize> = <Mandel<D> as Dimension>::Point;

/// What one trial did (in 2D, `D = 4`, or 3D, `D = 6`).
#[derive(Debug, Clone)]
pub struct Trial<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub factor: f64,
    /// The factor of the state the trial started from: the largest stable trial's, or
    /// the loading's equilibrium (`None`).
    pub start: Option<f64>,
    pub verdict: Verdict,
    /// The criterion's measure per completed step: the displacement increment (m).
    pub increments: Vec<f64>,
    /// Newton iterations, failed attempts included.
    pub newton_iterations: usize,
    pub seconds: f64,
    /// The step that did not converge even after its halvings, and why.
    pub error: Option<String>,
    /// The displacement increment of the last completed step at every node (m).
    pub last_increment: Vec<Point<D>>,
    /// Accumulated plastic strain increment of the trial (from its start state) per Gauss
    /// point.
    pub plastic_increment: Vec<f64>,
    /// The stress at the trial's end (Mandel, per Gauss point, flat; Pa).
    pub stress: Vec<f64>,
    /// The criterion's measure (at the monitored node, or the largest over the body) of
    /// the displacement at the trial's end from the search's equilibrium (m): the
    /// load–displacement curve the next factor is extrapolated from (`continuation`).
    pub moved: f64,
}

impl<const D: usize> Trial<D>
where
    Mandel<D>: Dimension,
{
    pub fn steps(&self) -> usize {
        self.increments.len()
    }

    pub fn fails(&self) -> bool {
        self.verdict.fails()
    }

    /// The last step's increment over the one before (the criterion's growth), if two.
    pub fn growth(&self) -> Option<f64> {
        let n = self.increments.len();
        (n >= 2).then(|| self.increments[n - 1] / self.increments[n - 2])
    }
}

/// Where a trial's steps start their Newton iterations (`docs/stability.md`, 'Predictor').
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrialPredictor {
    /// The scene's rule on every step (the blind search).
    Scene,
    /// The elastic predictor for an associative step, σₙ otherwise, while the body
    /// settles; σₙ after a step whose increment did not decrease (the criterion's
    /// growth) or whose Newton solve needed its line search (points changing regions
    /// en masse: plastic flow): a mechanism forming or moving on keeps its stress at
    /// yield, nearly stationary, where the elastic predictor overshoots
    /// ([`TrialPredictor::next`]).
    FollowMotion,
}

impl TrialPredictor {
    /// The rule of the step after `increments` (the criterion's measures so far), the
    /// last of which took `backtracks` line-search backtracks, for a scene whose rule is
    /// `scene`.
    pub fn next(
        self,
        increments: &[f64],
        backtracks: usize,
        scene: PredictorRule,
    ) -> PredictorRule {
        match (self, increments) {
            (TrialPredictor::Scene, _) => scene,
            (TrialPredictor::FollowMotion, [.., a, b]) if b >= a => PredictorRule::Previous,
            (TrialPredictor::FollowMotion, [_, ..]) if backtracks > 0 => PredictorRule::Previous,
            (TrialPredictor::FollowMotion, _) => PredictorRule::ElasticIfAssociative,
        }
    }
}

/// Steps `model` (already set to the trial's factor) from `start`, the state of the trial
/// at factor `start.1` (`None`: `equilibrium` itself), by `h` until `criterion` decides,
/// each step from the predictor `predictor` picks; the trial, and its end state when it
/// is stable (only such a state starts later trials). `equilibrium` is the search's: the
/// displacement [`Trial::moved`] is measured from it (the plastic strain of the trial
/// from `start`).
#[allow(clippy::too_many_arguments)]
pub fn run_trial_from<const D: usize>(
    model: &Model<D>,
    settings: StepSettings,
    predictor: TrialPredictor,
    start: (&State<D>, Option<f64>),
    equilibrium: &State<D>,
    factor: f64,
    h: f64,
    criterion: &Criterion,
) -> (Trial<D>, Option<State<D>>)
where
    Mandel<D>: Dimension,
{
    let (start_state, start_factor) = start;
    let start = Instant::now();
    let mut stepper = Stepper::new(model, settings);
    let mut state = start_state.clone();
    let mut increments = Vec::new();
    let mut last_increment = vec![Point::<D>::default(); state.displacement.len()];
    let mut newton_iterations = 0;
    let mut error = None;
    let mut backtracks = 0;
    let verdict = loop {
        stepper.set_predictor(predictor.next(&increments, backtracks, settings.predictor));
        let before = state.displacement.clone();
        match stepper.advance(&mut state, h) {
            Ok(report) => {
                backtracks = report.backtracks;
                newton_iterations += report.total_newton_iterations();
            }
            Err(e) => {
                error = Some(format!("step {}: {e}", increments.len() + 1));
                break criterion.after_failed_step(&increments);
            }
        }
        difference(&mut last_increment, &state.displacement, &before);
        increments.push(criterion.measure(&last_increment));
        if let Some(v) = criterion.judge(&increments) {
            break v;
        }
    };
    let plastic_increment = state
        .plastic_strain
        .iter()
        .zip(&start_state.plastic_strain)
        .map(|(a, b)| a - b)
        .collect();
    let mut total = vec![Point::<D>::default(); state.displacement.len()];
    difference(&mut total, &state.displacement, &equilibrium.displacement);
    let moved = criterion.measure(&total);
    // The stress is copied only when the end state is kept.
    let (stress, state) = if verdict == Verdict::Stable {
        (state.sigma.clone(), Some(state))
    } else {
        (state.sigma, None)
    };
    let trial = Trial {
        factor,
        start: start_factor,
        verdict,
        increments,
        newton_iterations,
        seconds: start.elapsed().as_secs_f64(),
        error,
        last_increment,
        plastic_increment,
        stress,
        moved,
    };
    (trial, state)
}

/// `out = a − b`, node by node, component by component.
pub fn difference<P: AsRef<[f64]> + AsMut<[f64]>>(out: &mut [P], a: &[P], b: &[P]) {
    for ((d, a), b) in out.iter_mut().zip(a).zip(b) {
        for ((d, a), b) in d.as_mut().iter_mut().zip(a.as_ref()).zip(b.as_ref()) {
            *d = a - b;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// σₙ after a step that did not decrease the increment or that backtracked, the
    /// settling rule otherwise; the blind search's trials keep the scene's rule whatever
    /// the motion.
    #[test]
    fn a_mechanism_moving_on_starts_from_the_last_stress() {
        use PredictorRule::*;
        let follow = |increments: &[f64], backtracks: usize| {
            TrialPredictor::FollowMotion.next(increments, backtracks, Extrapolated)
        };
        assert_eq!(follow(&[], 0), ElasticIfAssociative);
        assert_eq!(follow(&[0.3], 0), ElasticIfAssociative);
        // Settling (F = 1.36 on scenes/slope.toml, criterion.rs): the settling rule.
        assert_eq!(follow(&[1.31e-2, 7.60e-5], 0), ElasticIfAssociative);
        // Accelerating (F = 1.40), or held: the last stress.
        assert_eq!(follow(&[2.82e-1, 4.56e-1], 0), Previous);
        assert_eq!(follow(&[2.82e-1, 4.56e-1, 0.2], 0), ElasticIfAssociative);
        assert_eq!(follow(&[0.1, 0.1], 0), Previous);
        // A step that needed its line search: the last stress, even while settling.
        assert_eq!(follow(&[0.3], 9), Previous);
        assert_eq!(follow(&[1.31e-2, 7.60e-5], 1), Previous);
        // Nothing stepped yet: no step's backtracks to go by.
        assert_eq!(follow(&[], 9), ElasticIfAssociative);
        for increments in [&[][..], &[2.82e-1, 4.56e-1]] {
            assert_eq!(
                TrialPredictor::Scene.next(increments, 9, Extrapolated),
                Extrapolated
            );
        }
    }
}
