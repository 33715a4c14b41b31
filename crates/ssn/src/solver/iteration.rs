//! The Newton iteration (eqs. 21–25): evaluation of `F`, the stopping test, the line
//! search and the round-off floor.
use std::time::Instant;

use rayon::prelude::*;

use talus_bipotential::NaturalMapLinearization;

use super::{nan_max, Solver};
use crate::error::invalid;
use crate::operator::{apply, block};
use crate::point_share::PointShare;
use crate::stopping;
use crate::{Report, RoundOffFloor, SolveError, Stall, Status};

/// The [`Stall`] rule at the current iterate.
fn stalled(report: &Report, stall: &Stall) -> bool {
    report.iterations >= stall.after
        && stopping::no_decrease(&report.merit_history, stall.window, stall.decrease)
}

impl<const D: usize> Solver<D> {
    /// Solves from `sigma` (or from 0 without warm start) and leaves the last iterate in it.
    /// `Ok` when the report [is accepted](Report::is_accepted): converged, or at the
    /// round-off floor. `Err(NotConverged)` carries the report; `sigma` is then not a
    /// solution.
    pub fn solve(&mut self, sigma: &mut [f64]) -> Result<Report, SolveError> {
        let start = Instant::now();
        let n = self.problem.operator.size();
        if sigma.len() != n {
            return Err(invalid(
                "sigma",
                format!("length {} for an operator of size {n}", sigma.len()),
            ));
        }
        if !self.settings.warm_start {
            sigma.fill(0.0);
        } else if let Some(i) = sigma.iter().position(|v| !v.is_finite()) {
            return Err(invalid(
                "sigma",
                format!("non-finite initial value {} at index {i}", sigma[i]),
            ));
        }
        let mut report = Report::start(
            self.rho
                .iter()
                .fold((f64::INFINITY, 0.0), |(lo, hi), &r| (lo.min(r), hi.max(r))),
        );
        let mut merit = self.evaluate(sigma, false);
        let mut residual = self.residual_norm(sigma);
        report.residual_history.push(residual);
        report.merit_history.push(merit.sqrt());
        loop {
            if !residual.is_finite() {
                report.status = Status::NonFinite;
                break;
            }
            if residual <= self.settings.tolerance * self.norm(sigma).max(1.0) {
                report.status = Status::Converged;
                break;
            }
            if stopping::stagnated(&report.residual_history) {
                self.gather(sigma);
                if let Some(floor) = self.floor_reached(sigma, residual) {
                    report.status = Status::RoundOffFloor;
                    report.round_off_floor = Some(floor);
                    break;
                }
            }
            if self
                .settings
                .stall
                .is_some_and(|stall| stalled(&report, &stall))
            {
                report.status = Status::Stalled;
                break;
            }
            if let Some(fold) = self.settings.fold {
                let pivots = &report.negative_pivots;
                let window = fold.stall.window;
                if pivots.len() >= window
                    && pivots[pivots.len() - window..]
                        .iter()
                        .filter(|&&n| n > 0)
                        .count()
                        >= fold.indefinite
                    && stalled(&report, &fold.stall)
                {
                    report.status = Status::Folded;
                    break;
                }
            }
            if report.iterations == self.settings.max_iterations {
                report.status = Status::MaxIterations;
                break;
            }
            if report.iterations == 0 {
                self.forcing = None;
            }
            let needed = self.settings.tolerance * self.norm(sigma).max(1.0) / residual;
            if let Err(status) = self.newton_direction(&mut report, needed) {
                report.status = status;
                break;
            }
            let regions_before: Vec<talus_bipotential::Region> =
                if tracing::enabled!(tracing::Level::TRACE) {
                    self.lin.iter().map(|l| l.region).collect()
                } else {
                    Vec::new()
                };
            let backtracks_before = report.backtracks;
            match self.line_search(sigma, merit, residual, &mut report) {
                Some(m) => merit = m,
                None => {
                    report.status = Status::LineSearchFailed;
                    break;
                }
            }
            report.iterations += 1;
            report.merit_history.push(merit.sqrt());
            residual = self.residual_norm(sigma);
            if tracing::enabled!(tracing::Level::TRACE) {
                // This rank's points (all of them with one process).
                let owned = self.share.as_ref().map(PointShare::owned);
                let mine = |i: usize| owned.is_none_or(|o| o[i]);
                let count = |r: talus_bipotential::Region| {
                    (0..self.lin.len())
                        .filter(|&i| mine(i) && self.lin[i].region == r)
                        .count()
                };
                let changed = regions_before
                    .iter()
                    .zip(&self.lin)
                    .enumerate()
                    .filter(|(i, (r, l))| mine(*i) && **r != l.region)
                    .count();
                tracing::trace!(
                    changed,
                    step_backtracks = report.backtracks - backtracks_before,
                    merit = merit.sqrt(),
                    interior = count(talus_bipotential::Region::Interior),
                    boundary = count(talus_bipotential::Region::Boundary),
                    polar = count(talus_bipotential::Region::Polar),
                    "regions"
                );
            }
            report.residual_history.push(residual);
            tracing::trace!(
                iteration = report.iterations,
                residual,
                backtracks = report.backtracks,
                "ssn step"
            );
        }
        // Every rank holds every point's σ and z again.
        self.gather(sigma);
        self.gather_z();
        // A failure at the floor is the floor: no step can make progress there.
        if matches!(
            report.status,
            Status::MaxIterations
                | Status::Stalled
                | Status::Folded
                | Status::LineSearchFailed
                | Status::SingularJacobian
        ) {
            if let Some(floor) = self.floor_reached(sigma, residual) {
                tracing::debug!(failure = %report.status, "failure at the round-off floor");
                report.status = Status::RoundOffFloor;
                report.round_off_floor = Some(floor);
            }
        }
        report.residual = residual;
        // Outside the log macro: a collective with a share, which every rank must call
        // whatever its log filter.
        let sigma_inf = self.norm(sigma);
        report.scale = sigma_inf.max(1.0);
        report.seconds = start.elapsed().as_secs_f64();
        tracing::debug!(
            status = %report.status,
            iterations = report.iterations,
            residual,
            sigma_inf,
            backtracks = report.backtracks,
            "ssn solve"
        );
        if report.is_accepted() {
            Ok(report)
        } else {
            Err(SolveError::NotConverged(Box::new(report)))
        }
    }

    /// `Some` when `residual` (at `sigma`) is within `FLOOR_FACTOR` of the estimated
    /// round-off floor there.
    pub(super) fn floor_reached(&self, sigma: &[f64], residual: f64) -> Option<RoundOffFloor> {
        let estimate = stopping::floor_estimate(
            &self.problem.operator,
            self.blocks.as_ref(),
            sigma,
            &self.problem.q,
            &self.residual_rho,
            &self.problem.rules,
        );
        (residual <= stopping::FLOOR_FACTOR * estimate).then_some(RoundOffFloor {
            reached: residual,
            estimate,
        })
    }

    /// `z`, `F` and the linearization at `sigma` (into the trial buffers when `trial`);
    /// returns `‖F‖²`.
    pub(super) fn evaluate(&mut self, sigma: &[f64], trial: bool) -> f64 {
        let z = if trial {
            &mut self.trial_z
        } else {
            &mut self.z
        };
        apply(
            &self.problem.operator,
            self.blocks.as_ref(),
            sigma,
            Some(&self.problem.q),
            z,
            &mut self.scratch,
            self.share.as_ref(),
            self.settings.parallel,
        );
        self.linearize(sigma, trial)
    }

    /// The trial point `σ + t d`, evaluated in full: `z = Wσ + q` computed again rather
    /// than as `z + t W d`, whose round-off would hide the floor the stopping test must
    /// see (`tests/round_off_floor.rs` ends at a residual of exactly 0 with it). Returns
    /// `‖F‖²`.
    pub(super) fn evaluate_along(&mut self, sigma: &[f64], t: f64) -> f64 {
        let mut trial = std::mem::take(&mut self.trial_sigma);
        for ((x, s), d) in trial.iter_mut().zip(sigma).zip(&self.direction) {
            *x = s + t * d;
        }
        let merit = self.evaluate(&trial, true);
        self.trial_sigma = trial;
        merit
    }

    /// `F` and its linearization at `sigma` with the `z` already in place (the trial
    /// buffers when `trial`); returns `‖F‖²`.
    fn linearize(&mut self, sigma: &[f64], trial: bool) -> f64 {
        let (z, lin) = if trial {
            (&self.trial_z, &mut self.trial_lin)
        } else {
            (&self.z, &mut self.lin)
        };
        let rules = &self.problem.rules;
        let rho = &self.rho;
        let owned = self.share.as_ref().map(PointShare::owned);
        let one = |(i, l): (usize, &mut NaturalMapLinearization<D>)| {
            if owned.is_some_and(|o| !o[i]) {
                return;
            }
            *l = rules[i].natural_map_linearization(
                &block::<D>(sigma, i),
                &block::<D>(z, i),
                rho[i],
            );
        };
        if self.settings.parallel {
            lin.par_iter_mut()
                .enumerate()
                .with_min_len(64)
                .for_each(one);
        } else {
            lin.iter_mut().enumerate().for_each(one);
        }
        // Sequential sum: the merit must not depend on the thread count (nor, beyond the
        // ranks' partial sums, on the ranks).
        match &self.share {
            None => lin.iter().map(|l| l.residual.norm_squared()).sum(),
            Some(share) => share.sum(
                share
                    .points()
                    .iter()
                    .map(|&i| lin[i].residual.norm_squared())
                    .sum(),
            ),
        }
    }

    /// `‖F‖∞` at the current iterate (NaN if any entry is).
    pub(super) fn residual_norm(&self, sigma: &[f64]) -> f64 {
        self.residual_norm_with(sigma, &self.z)
    }

    pub(super) fn residual_norm_with(&self, sigma: &[f64], z: &[f64]) -> f64 {
        let rules = &self.problem.rules;
        let residual_rho = &self.residual_rho;
        let owned = self.share.as_ref().map(PointShare::owned);
        let point = |i: usize| {
            if owned.is_some_and(|o| !o[i]) {
                return 0.0;
            }
            let f = rules[i].natural_map_residual(
                &block::<D>(sigma, i),
                &block::<D>(z, i),
                residual_rho[i],
            );
            f.iter().fold(0.0f64, |w, x| {
                if x.is_nan() || w.is_nan() {
                    f64::NAN
                } else {
                    w.max(x.abs())
                }
            })
        };
        // A maximum (NaN if any entry is) does not depend on the order: parallel is exact.
        let worst = if self.settings.parallel {
            (0..rules.len())
                .into_par_iter()
                .with_min_len(64)
                .map(point)
                .reduce(|| 0.0, nan_max)
        } else {
            (0..rules.len()).map(point).fold(0.0, nan_max)
        };
        self.share.as_ref().map_or(worst, |share| share.max(worst))
    }

    /// Armijo backtracking on `‖F‖²` along `self.direction`; moves `sigma` and returns the
    /// new merit, or `None` when no step length is accepted.
    pub(super) fn line_search(
        &mut self,
        sigma: &mut [f64],
        merit: f64,
        measured: f64,
        report: &mut Report,
    ) -> Option<f64> {
        let ls = self.settings.line_search;
        let mut t = 1.0;
        let mut backtracks = 0;
        loop {
            let trial_merit = self.evaluate_along(sigma, t);
            let accept = match ls {
                None => trial_merit.is_finite(),
                // The full step is also taken when the stopping test's residual decreases
                // enough: near the solution the merit of a large ρ sits at its round-off
                // floor and would only admit useless tiny steps.
                Some(ls) => {
                    trial_merit <= (1.0 - 2.0 * ls.armijo * t) * merit
                        || (backtracks == 0
                            && self.residual_norm_with(&self.trial_sigma, &self.trial_z)
                                <= (1.0 - ls.armijo) * measured)
                }
            };
            if accept {
                sigma.copy_from_slice(&self.trial_sigma);
                std::mem::swap(&mut self.z, &mut self.trial_z);
                std::mem::swap(&mut self.lin, &mut self.trial_lin);
                report.backtracks += backtracks;
                return Some(trial_merit);
            }
            match ls {
                Some(ls) if backtracks < ls.max_backtracks => {
                    t *= ls.shrink;
                    backtracks += 1;
                }
                _ => {
                    report.backtracks += backtracks;
                    return self.accept_full_step_if_measured_progress(sigma);
                }
            }
        }
    }

    /// Near the solution `‖F_ρ‖²` with the iteration's (large) ρ reaches its round-off floor
    /// before the stopping test's residual does: then the full Newton step is taken if it
    /// lowers the latter.
    pub(super) fn accept_full_step_if_measured_progress(
        &mut self,
        sigma: &mut [f64],
    ) -> Option<f64> {
        let current = self.residual_norm(sigma);
        let merit = self.evaluate_along(sigma, 1.0);
        let full = self.residual_norm_with(&self.trial_sigma, &self.trial_z);
        if full < current {
            sigma.copy_from_slice(&self.trial_sigma);
            std::mem::swap(&mut self.z, &mut self.trial_z);
            std::mem::swap(&mut self.lin, &mut self.trial_lin);
            Some(merit)
        } else {
            None
        }
    }
}
