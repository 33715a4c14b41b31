//! The stepper: each step of `h` is one or more sub-steps, each the reduced problem
//! `h z = Wσ + q` of eqs. 15–16 built by a [`Discretization`] and solved by talus-ssn's
//! semi-smooth Newton from a predictor; the step control ([`StepControl`]) picks the
//! sub-step sizes (`docs/solver.md`, "Time stepping").
use std::time::Instant;

use talus_ssn::{ReducedSystem, Report, SolveError, Solver};

use crate::parabola::Parabola;
use crate::{
    Discretization, Predictor, PredictorRule, Problem, StepControl, StepError, StepReport,
    StepSettings,
};

/// Advances a discretization's state step by step. For a discretization whose operator
/// does not depend on the state (FEM), one `Solver` (and one symbolic factorization) for
/// every sub-step size, reused across steps: `q` changes every sub-step, the operator's
/// `h` when the size does.
pub struct Stepper<M: Discretization<D>, const D: usize = 4> {
    discretization: M,
    settings: StepSettings,
    /// The fixed operator's solver and the sub-step size it is set up for.
    fixed: Option<(f64, Solver<D>)>,
    /// `(σₙ − σₙ₋₁)/h` of the last sub-step: with [`PredictorRule::Extrapolated`] each
    /// solve starts from σₙ + h σ̇, which under steady loading is second-order close to the
    /// answer.
    stress_rate: Option<Vec<f64>>,
    /// The rate before it, and whether the next sub-step extrapolates along the parabola.
    parabola: Parabola,
    /// The sub-step size the next step starts at, and what the control learned.
    control: StepControl,
    /// Whether a sub-step accepted at the round-off floor was logged at `warn` already: a
    /// relaxed material ends every solve there (`docs/solver.md`, 'The round-off floor'),
    /// so the later ones go to `debug` and are counted in `StepReport::statuses`.
    floor_warned: bool,
}

/// The [`Stepper`]'s own state between steps ([`Stepper::memory`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepperMemory {
    pub stress_rate: Option<Vec<f64>>,
    /// Absent from checkpoints written before the parabolic predictor (their next
    /// steps extrapolate along the line until two rates are measured again).
    #[serde(default)]
    pub parabola: Parabola,
    /// Absent from checkpoints written before the step control (their steps restart at
    /// the full h).
    #[serde(default)]
    pub control: StepControl,
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

impl<M: Discretization<D>, const D: usize> Stepper<M, D> {
    pub fn new(discretization: M, settings: StepSettings) -> Self {
        Self {
            discretization,
            settings,
            fixed: None,
            stress_rate: None,
            parabola: Parabola::default(),
            control: StepControl::default(),
            floor_warned: false,
        }
    }

    pub fn discretization(&self) -> &M {
        &self.discretization
    }

    pub fn settings(&self) -> &StepSettings {
        &self.settings
    }

    /// The predictor of the next sub-steps: a caller that watches the motion (a stability
    /// trial, `docs/stability.md`, 'Predictor') switches it between steps.
    pub fn set_predictor(&mut self, rule: PredictorRule) {
        self.settings.predictor = rule;
    }

    /// `(σₙ − σₙ₋₁)/h` of the last sub-step, if the next step will extrapolate from it.
    pub fn stress_rate(&self) -> Option<&[f64]> {
        self.stress_rate.as_deref()
    }

    /// Restores a stress rate saved with [`Stepper::stress_rate`] (to resume a run from a
    /// saved state with the same predictor).
    pub fn set_stress_rate(&mut self, rate: Option<Vec<f64>>) {
        self.stress_rate = rate;
        // Its sub-step size is not known: the line until two rates are measured again.
        self.parabola = Parabola::default();
    }

    /// Halvings the next step starts with ([`StepControl`]): 0 = full h.
    pub fn remembered_halvings(&self) -> usize {
        self.control.level.min(self.settings.max_halvings)
    }

    /// What the next step depends on besides the state: the stress rate of the predictor
    /// and the step control's memory (a checkpoint).
    pub fn memory(&self) -> StepperMemory {
        StepperMemory {
            stress_rate: self.stress_rate.clone(),
            parabola: self.parabola.clone(),
            control: self.control.clone(),
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
        self.parabola = memory.parabola;
        self.control = memory.control;
    }

    /// One step of `h` (s), as sub-steps of `h / 2^level` chosen by the step control
    /// ([`StepControl`], `docs/solver.md`, 'The step control'): a sub-step whose solve fails
    /// is retried at half the size, down to `h / 2^max_halvings`; past that the step fails
    /// and `state` is left as it was before the step. The size the step ends with, and
    /// what the control learned, carry over to the next step.
    pub fn advance(
        &mut self,
        state: &mut M::State,
        h: f64,
    ) -> Result<StepReport<M::Stats>, StepError<M::Error>> {
        if !(h.is_finite() && h > 0.0) {
            return Err(StepError::Solver(SolveError::InvalidInput {
                field: "h",
                reason: format!("{h} s must be finite and > 0"),
            }));
        }
        let start = Instant::now();
        let mut report = StepReport::new(self.discretization.time(state), h);
        let max_level = self.settings.max_halvings;
        let growth = self.settings.growth;
        // A failed step leaves the control as it found it, as it leaves the state.
        let control_before = self.control.clone();
        self.control.level = self.control.level.min(max_level);
        let mut trial = state.clone();
        // Progress in units of h / 2^max_level.
        let end = 1usize << max_level;
        let mut position = 0;
        while position < end {
            let level = self.control.level;
            let parts = 1usize << level;
            let mut attempt = trial.clone();
            match self.substep(&mut attempt, h / parts as f64, &mut report) {
                Ok(iterations) => {
                    trial = attempt;
                    position += end / parts;
                    self.control
                        .accepted(position, iterations, max_level, &growth);
                }
                Err(SubstepError::NotConverged(r, iterations, backtracks)) => {
                    report.failed_newton_iterations += iterations;
                    report.failed_backtracks += backtracks;
                    report.solve_seconds += r.seconds;
                    let sub_h = h / parts as f64;
                    if !self.control.failed(max_level, &growth) {
                        self.control = control_before;
                        return Err(StepError::NotConverged {
                            time: self.discretization.time(&trial) + sub_h,
                            h: sub_h,
                            halvings: level,
                            report_status: r.status,
                            iterations: r.iterations,
                            residual: r.residual / r.scale,
                        });
                    }
                    // Halving is the step control at work, not a fault: a step that fails
                    // after its halvings is the error.
                    tracing::debug!(
                        time = self.discretization.time(&trial),
                        h = sub_h,
                        status = %r.status,
                        iterations = r.iterations,
                        negative_pivots = ?r.negative_pivots,
                        merits = ?r.merit_history.iter().map(|m| (m / r.scale) as f32).collect::<Vec<_>>(),
                        "sub-step did not converge: halving it"
                    );
                }
                Err(SubstepError::Fatal(e)) => {
                    self.control = control_before;
                    return Err(match e {
                        StepErrorKind::Solver(e) => StepError::Solver(e),
                        StepErrorKind::Discretization(e) => StepError::Discretization(e),
                    });
                }
            }
        }
        *state = trial;
        report.time = self.discretization.time(state);
        report.seconds = start.elapsed().as_secs_f64();
        Ok(report)
    }

    /// Sets up the solver of a fixed operator for step `h`: built on first use, then moved to
    /// another sub-step size by `Solver::replace_problem`, which keeps its symbolic analysis
    /// and workspaces. One solver serves every size: a halving run needs one operator's
    /// and one factor's memory (`docs/performance.md`, 'Memory per sub-step size'), and
    /// since the numeric factorization is redone every Newton iteration, a solver moved to
    /// `h` gives the bits a new one would.
    fn set_up_fixed(&mut self, h: f64) -> Result<(), SubstepError<M::Error>> {
        if self.fixed.as_ref().is_some_and(|(hh, _)| *hh != h) {
            let system = self.fixed_system(h)?;
            let (hh, solver) = self.fixed.as_mut().expect("checked above");
            // On error the solver is left unchanged, still set up for its old size.
            solver.replace_problem(system).map_err(fatal_solver)?;
            *hh = h;
        }
        if self.fixed.is_none() {
            let system = self.fixed_system(h)?;
            let solver = Solver::new(system, self.settings.solver).map_err(fatal_solver)?;
            self.fixed = Some((h, solver));
        }
        Ok(())
    }

    fn fixed_system(&self, h: f64) -> Result<ReducedSystem<D>, SubstepError<M::Error>> {
        match self.discretization.fixed_system(h) {
            Some(Ok(s)) => Ok(s),
            Some(Err(e)) => Err(fatal_solver(e)),
            None => Err(SubstepError::Fatal(StepErrorKind::Solver(
                SolveError::InvalidInput {
                    field: "problem",
                    reason: "a right-hand side without a fixed operator".into(),
                },
            ))),
        }
    }

    /// One sub-step: the discretization's problem, solved (several times if it asks, e.g.
    /// MPM friction passes) from the predictor, then its update.
    fn substep(
        &mut self,
        state: &mut M::State,
        h: f64,
        report: &mut StepReport<M::Stats>,
    ) -> Result<usize, SubstepError<M::Error>> {
        let disc = &self.discretization;
        let loading = disc.loading(state, h);
        let (mut substep, problem) = disc.begin(state, h).map_err(fatal_disc)?;
        let clock = Instant::now();
        // A fixed operator's solver lives in `self.fixed`; a sub-step's own system, here.
        let mut own = None;
        let solver = match problem {
            Problem::Rhs(q) => {
                self.set_up_fixed(h)?;
                let solver = &mut self.fixed.as_mut().expect("set up").1;
                solver.set_q(q).map_err(fatal_solver)?;
                solver
            }
            Problem::RhsAndRules(q, rules) => {
                self.set_up_fixed(h)?;
                let solver = &mut self.fixed.as_mut().expect("set up").1;
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
        // sub-step's loading was smooth (steady flow is then predicted to second order),
        // along the parabola through the last three stresses when that was clearly closer
        // on the last sub-step; out of rest or after a jump in the loading rate, the
        // elastic predictor.
        let sigma_n = disc.stress(state).to_vec();
        let mut sigma = sigma_n.clone();
        // `ElasticIfAssociative` is decided on this sub-step's own flow rules.
        let rule = match self.settings.predictor {
            PredictorRule::ElasticIfAssociative if solver.problem().is_associative() => {
                PredictorRule::Elastic
            }
            PredictorRule::ElasticIfAssociative => PredictorRule::Previous,
            rule => rule,
        };
        let rate = match rule {
            PredictorRule::Extrapolated if !loading.jumps => self.stress_rate.take(),
            _ => None,
        };
        let predictor = match (&rate, rule) {
            (Some(rate), _) => {
                let parabola = self.parabola.extrapolate(&mut sigma, rate, h);
                tracing::trace!(parabola, "extrapolated");
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
            tracing::debug!(
                h,
                iterations = r.iterations,
                negative_pivots = ?r.negative_pivots,
                factorizations = r.factorizations,
                krylov_iterations = r.krylov_iterations,
                krylov_failures = r.krylov_failures,
                merits = ?r.merit_history.iter().map(|m| (m / r.scale) as f32).collect::<Vec<_>>(),
                "sub-step solve"
            );
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
            let (time, residual, estimate) = (
                disc.time(state),
                floor.reached / last.scale,
                floor.estimate / last.scale,
            );
            if self.floor_warned {
                tracing::debug!(
                    time,
                    h,
                    residual,
                    floor_estimate = estimate,
                    "sub-step accepted at the round-off floor"
                );
            } else {
                self.floor_warned = true;
                tracing::warn!(
                    time,
                    h,
                    residual,
                    floor_estimate = estimate,
                    "sub-step accepted at the round-off floor, above the tolerance (the \
                     next ones are logged at debug and counted in the run's last line)"
                );
            }
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
        self.parabola.record(rate, self.stress_rate.as_deref(), h);

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
        Ok(iterations)
    }
}

fn fatal_solver<E>(e: SolveError) -> SubstepError<E> {
    SubstepError::Fatal(StepErrorKind::Solver(e))
}

fn fatal_disc<E>(e: E) -> SubstepError<E> {
    SubstepError::Fatal(StepErrorKind::Discretization(e))
}
