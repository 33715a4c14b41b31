//! The stepper: each step of `h` is one or more sub-steps, each the reduced problem
//! `h z = Wσ + q` of eqs. 15–16 built by a [`Discretization`] and solved by talus-ssn's
//! semi-smooth Newton from a predictor; a sub-step whose solve fails is redone as two
//! halves (`docs/solver.md`, "Time stepping").
use std::time::Instant;

use talus_ssn::{Report, SolveError, Solver};

use crate::{
    Discretization, Predictor, PredictorRule, Problem, StepError, StepReport, StepSettings,
};

/// Advances a discretization's state step by step. For a discretization whose operator
/// does not depend on the state (FEM), one `Solver` (and one symbolic factorization) per
/// distinct `h`, reused across steps: only `q` changes.
pub struct Stepper<D: Discretization> {
    discretization: D,
    settings: StepSettings,
    fixed: Vec<(f64, Solver<4>)>,
    /// `(σₙ − σₙ₋₁)/h` of the last sub-step: with [`PredictorRule::Extrapolated`] each
    /// solve starts from σₙ + h σ̇, which under steady loading is second-order close to the
    /// answer.
    stress_rate: Option<Vec<f64>>,
    /// The sub-step level the next step starts at, and the steps taken at it without a
    /// halving (`StepSettings::halving_memory`).
    memory_level: usize,
    clean_steps: usize,
}

/// The [`Stepper`]'s own state between steps ([`Stepper::memory`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepperMemory {
    pub stress_rate: Option<Vec<f64>>,
    pub memory_level: usize,
    pub clean_steps: usize,
}

/// How a sub-step failed.
enum SubstepError<E> {
    /// Newton did not converge: worth retrying with a smaller step. The iterations and
    /// backtracks of all the attempt's solves.
    NotConverged(Box<Report>, usize, usize),
    Fatal(StepErrorKind<E>),
}

enum StepErrorKind<E> {
    Solver(SolveError),
    Discretization(E),
}

impl<D: Discretization> Stepper<D> {
    pub fn new(discretization: D, settings: StepSettings) -> Self {
        Self {
            discretization,
            settings,
            fixed: Vec::new(),
            stress_rate: None,
            memory_level: 0,
            clean_steps: 0,
        }
    }

    pub fn discretization(&self) -> &D {
        &self.discretization
    }

    pub fn settings(&self) -> &StepSettings {
        &self.settings
    }

    /// `(σₙ − σₙ₋₁)/h` of the last sub-step, if the next step will extrapolate from it.
    pub fn stress_rate(&self) -> Option<&[f64]> {
        self.stress_rate.as_deref()
    }

    /// Restores a stress rate saved with [`Stepper::stress_rate`] (to resume a run from a
    /// saved state with the same predictor).
    pub fn set_stress_rate(&mut self, rate: Option<Vec<f64>>) {
        self.stress_rate = rate;
    }

    /// Halvings the next step starts with (`StepSettings::halving_memory`): 0 = full h.
    pub fn remembered_halvings(&self) -> usize {
        self.memory_level
    }

    /// What the next step depends on besides the state: the stress rate of the predictor
    /// and the halving memory (a checkpoint).
    pub fn memory(&self) -> StepperMemory {
        StepperMemory {
            stress_rate: self.stress_rate.clone(),
            memory_level: self.memory_level,
            clean_steps: self.clean_steps,
        }
    }

    /// Restores what [`Stepper::memory`] saved: the next step is then the one the saving
    /// stepper would have taken. The fixed operators' solvers are rebuilt on first use;
    /// they keep nothing from one solve to the next that changes its numbers (the numeric
    /// factorization is redone every Newton iteration, the symbolic analyses depend only on
    /// the pattern), so a rebuilt solver gives the same bits (`docs/scenes.md`,
    /// 'Checkpoints and resume').
    pub fn restore_memory(&mut self, memory: StepperMemory) {
        self.stress_rate = memory.stress_rate;
        self.memory_level = memory.memory_level;
        self.clean_steps = memory.clean_steps;
    }

    /// One step of `h` (s). A sub-step whose solve fails is redone as two halves, down to
    /// `h / 2^max_halvings`; past that the step fails and `state` is left as it was before
    /// the step. With `halving_memory > 0` the step starts at the sub-step size the last
    /// halved step converged with.
    pub fn advance(
        &mut self,
        state: &mut D::State,
        h: f64,
    ) -> Result<StepReport<D::Stats>, StepError<D::Error>> {
        if !(h.is_finite() && h > 0.0) {
            return Err(StepError::Solver(SolveError::InvalidInput {
                field: "h",
                reason: format!("{h} s must be finite and > 0"),
            }));
        }
        let start = Instant::now();
        let mut report = StepReport::new(self.discretization.time(state), h);
        // Start at the sub-step the last halved step converged with (its failed attempts
        // at larger sizes would most likely fail again), still within max_halvings.
        let remember = self.settings.halving_memory > 0;
        let level = if remember {
            self.memory_level.min(self.settings.max_halvings)
        } else {
            0
        };
        let mut trial = state.clone();
        let parts = 1usize << level;
        for _ in 0..parts {
            self.advance_level(&mut trial, h / parts as f64, level, &mut report)?;
        }
        *state = trial;
        if remember {
            let deepest = (h / report.smallest_h).log2().round() as usize;
            if deepest > level {
                self.memory_level = deepest;
                self.clean_steps = 0;
            } else {
                self.clean_steps += 1;
                if self.clean_steps >= self.settings.halving_memory {
                    self.memory_level = level.saturating_sub(1);
                    self.clean_steps = 0;
                }
            }
        }
        report.time = self.discretization.time(state);
        report.seconds = start.elapsed().as_secs_f64();
        Ok(report)
    }

    fn advance_level(
        &mut self,
        state: &mut D::State,
        h: f64,
        level: usize,
        report: &mut StepReport<D::Stats>,
    ) -> Result<(), StepError<D::Error>> {
        let mut trial = state.clone();
        match self.substep(&mut trial, h, report) {
            Ok(()) => {
                *state = trial;
                Ok(())
            }
            Err(SubstepError::NotConverged(r, iterations, backtracks)) => {
                report.failed_newton_iterations += iterations;
                report.failed_backtracks += backtracks;
                report.solve_seconds += r.seconds;
                if level >= self.settings.max_halvings {
                    return Err(StepError::NotConverged {
                        time: self.discretization.time(state) + h,
                        h,
                        halvings: level,
                        report_status: r.status,
                        iterations: r.iterations,
                        residual: r.residual / r.scale,
                    });
                }
                // Halving is the step control at work, not a fault: a step that fails after
                // its halvings is the error.
                tracing::debug!(
                    time = self.discretization.time(state),
                    h,
                    status = %r.status,
                    "step did not converge: halving h"
                );
                self.advance_level(state, 0.5 * h, level + 1, report)?;
                self.advance_level(state, 0.5 * h, level + 1, report)
            }
            Err(SubstepError::Fatal(StepErrorKind::Solver(e))) => Err(StepError::Solver(e)),
            Err(SubstepError::Fatal(StepErrorKind::Discretization(e))) => {
                Err(StepError::Discretization(e))
            }
        }
    }

    /// The solver for a fixed operator of step `h`, built on first use.
    fn fixed_solver(&mut self, h: f64) -> Result<usize, SubstepError<D::Error>> {
        if let Some(p) = self.fixed.iter().position(|(hh, _)| *hh == h) {
            return Ok(p);
        }
        let system = match self.discretization.fixed_system(h) {
            Some(Ok(s)) => s,
            Some(Err(e)) => return Err(fatal_solver(e)),
            None => {
                return Err(SubstepError::Fatal(StepErrorKind::Solver(
                    SolveError::InvalidInput {
                        field: "problem",
                        reason: "a right-hand side without a fixed operator".into(),
                    },
                )))
            }
        };
        let solver = Solver::new(system, self.settings.solver).map_err(fatal_solver)?;
        self.fixed.push((h, solver));
        Ok(self.fixed.len() - 1)
    }

    /// One sub-step: the discretization's problem, solved (several times if it asks, e.g.
    /// MPM friction passes) from the predictor, then its update.
    fn substep(
        &mut self,
        state: &mut D::State,
        h: f64,
        report: &mut StepReport<D::Stats>,
    ) -> Result<(), SubstepError<D::Error>> {
        let disc = &self.discretization;
        let loading = disc.loading(state, h);
        let (mut substep, problem) = disc.begin(state, h).map_err(fatal_disc)?;
        let clock = Instant::now();
        // A fixed operator's solver lives in `self.fixed`; a sub-step's own system, here.
        let mut own = None;
        let solver = match problem {
            Problem::Rhs(q) => {
                let p = self.fixed_solver(h)?;
                let solver = &mut self.fixed[p].1;
                solver.set_q(q).map_err(fatal_solver)?;
                solver
            }
            Problem::RhsAndRules(q, rules) => {
                let p = self.fixed_solver(h)?;
                let solver = &mut self.fixed[p].1;
                solver.set_q(q).map_err(fatal_solver)?;
                solver.set_rules(rules).map_err(fatal_solver)?;
                solver
            }
            Problem::System(system) => {
                own.insert(Solver::new(system, self.settings.solver).map_err(fatal_solver)?)
            }
        };
        let disc = &self.discretization;

        // Starting point (`docs/solver.md`, "Time stepping"): σₙ + h σ̇ when the last
        // sub-step's loading was smooth (steady flow is then predicted to second order);
        // out of rest or after a jump in the loading rate, the elastic predictor.
        let sigma_n = disc.stress(state).to_vec();
        let mut sigma = sigma_n.clone();
        let rule = self.settings.predictor;
        let rate = match rule {
            PredictorRule::Extrapolated if !loading.jumps => self.stress_rate.take(),
            _ => None,
        };
        let predictor = match (&rate, rule) {
            (Some(rate), _) => {
                for (s, r) in sigma.iter_mut().zip(rate) {
                    *s += h * r;
                }
                Predictor::Extrapolated
            }
            (None, PredictorRule::Previous) => Predictor::Previous,
            (None, _) => match solver.elastic_predictor(&mut sigma) {
                Ok(()) => Predictor::Elastic,
                Err(_) => {
                    sigma.copy_from_slice(&sigma_n);
                    Predictor::Previous
                }
            },
        };
        tracing::trace!(?predictor, "start of sub-step");

        let (mut iterations, mut backtracks, mut solves, mut reused) = (0, 0, 0, 0);
        let mut histories = Vec::new();
        let last = loop {
            let r = match solver.solve(&mut sigma) {
                Ok(r) => r,
                Err(SolveError::NotConverged(r)) => {
                    // The halved retries start from the same rate: after a failure the
                    // elastic predictor is much further from the solution (`docs/solver.md`,
                    // "Non-associative Newton at the mechanism's onset").
                    self.stress_rate = rate;
                    let (i, b) = (iterations + r.iterations, backtracks + r.backtracks);
                    return Err(SubstepError::NotConverged(r, i, b));
                }
                Err(e) => return Err(fatal_solver(e)),
            };
            if solves == 0 {
                report.first_solve_iterations += r.iterations;
                report.first_solve_backtracks += r.backtracks;
            }
            solves += 1;
            iterations += r.iterations;
            backtracks += r.backtracks;
            histories.push((
                r.residual_history.iter().map(|v| v / r.scale).collect(),
                r.merit_history.iter().map(|v| v / r.scale).collect(),
            ));
            match disc
                .after_solve(&mut substep, state, &sigma, solver.z())
                .map_err(fatal_disc)?
            {
                None => break r,
                Some(Problem::Rhs(q)) => solver.set_q(q).map_err(fatal_solver)?,
                Some(Problem::RhsAndRules(q, rules)) => {
                    solver.set_q(q).map_err(fatal_solver)?;
                    solver.set_rules(rules).map_err(fatal_solver)?;
                }
                Some(Problem::System(system)) if self.settings.reuse_analysis => {
                    reused += solver.replace_problem(system).map_err(fatal_solver)? as usize;
                }
                Some(Problem::System(system)) => {
                    *solver = Solver::new(system, self.settings.solver).map_err(fatal_solver)?;
                }
            }
        };
        let solve_seconds = clock.elapsed().as_secs_f64();
        if let Some(floor) = last.round_off_floor {
            tracing::warn!(
                time = disc.time(state),
                h,
                residual = floor.reached / last.scale,
                floor_estimate = floor.estimate / last.scale,
                "sub-step accepted at the round-off floor, above the tolerance"
            );
        }
        let z = solver.z().to_vec();
        let stats = disc
            .finish(substep, state, sigma, &z, h)
            .map_err(fatal_disc)?;
        // A rate is worth extrapolating only if this sub-step's loading was smooth.
        self.stress_rate =
            (rule == PredictorRule::Extrapolated && !loading.changes_inside).then(|| {
                disc.stress(state)
                    .iter()
                    .zip(&sigma_n)
                    .map(|(a, b)| (a - b) / h)
                    .collect()
            });

        report.substeps += 1;
        report.smallest_h = report.smallest_h.min(h);
        report.newton_iterations += iterations;
        report.max_newton_iterations = report.max_newton_iterations.max(iterations);
        report.backtracks += backtracks;
        report.solves_per_substep = report.solves_per_substep.max(solves);
        report.reused_analyses += reused;
        report.statuses.push(last.status);
        report.predictors.push(predictor);
        report.residual = last.residual;
        report.relative_residual = last.residual / last.scale;
        for (residuals, merits) in histories {
            report.residual_histories.push(residuals);
            report.merit_histories.push(merits);
        }
        report.stats = Some(stats);
        report.solve_seconds += solve_seconds;
        Ok(())
    }
}

fn fatal_solver<E>(e: SolveError) -> SubstepError<E> {
    SubstepError::Fatal(StepErrorKind::Solver(e))
}

fn fatal_disc<E>(e: E) -> SubstepError<E> {
    SubstepError::Fatal(StepErrorKind::Discretization(e))
}
