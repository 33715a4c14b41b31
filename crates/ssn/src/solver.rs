use std::time::Instant;

use rayon::prelude::*;
use talus_bipotential::NaturalMapLinearization;

use crate::error::invalid;
use crate::newton::schur::SchurFailure;
use crate::newton::{DenseSystem, Factorized, LuChoice, SchurSystem, StressSizedSystem};
use crate::operator::{apply, block, PointBlocks};
use crate::stopping;
use crate::{
    LinearSolver, Operator, ReducedSystem, Report, Rho, RoundOffFloor, Settings, SolveError, Status,
};

/// A linearization that is never read (placeholder before the first evaluation).
fn blank<const D: usize>() -> NaturalMapLinearization<D> {
    NaturalMapLinearization {
        residual: nalgebra::SVector::zeros(),
        projection_jacobian: nalgebra::SMatrix::zeros(),
        coupling: nalgebra::SMatrix::zeros(),
        region: talus_bipotential::Region::Interior,
    }
}

/// Semi-smooth Newton (eqs. 21–25) on `F(σ) = σ − P_C(σ − ρ y(Wσ + q)) = 0`.
///
/// Built once per operator (the symbolic factorization happens here), then `solve` is called
/// per right-hand side; workspaces are reused across iterations and solves.
pub struct Solver<const D: usize> {
    problem: ReducedSystem<D>,
    settings: Settings,
    blocks: Option<PointBlocks<D>>,
    rho: Vec<f64>,
    residual_rho: Vec<f64>,
    dense: Option<DenseSystem>,
    stress_sized: Option<StressSizedSystem>,
    schur: Option<SchurSystem<D>>,
    z: Vec<f64>,
    f: Vec<f64>,
    lin: Vec<NaturalMapLinearization<D>>,
    trial_sigma: Vec<f64>,
    trial_z: Vec<f64>,
    trial_lin: Vec<NaturalMapLinearization<D>>,
    direction: Vec<f64>,
    check: Vec<f64>,
    scratch: Vec<f64>,
}

/// The ρ of the stopping test, whatever ρ the iteration uses: `F_ρ(σ) = 0` for one ρ > 0
/// iff for all, but the size of `F_ρ` scales with ρ, so measuring with a fixed convention
/// keeps the tolerance meaning the same when the iteration's ρ is tuned.
const RESIDUAL_RHO: Rho = Rho::PerPointDiagonal { factor: 1.0 };

/// Accepted `‖J_F d + F‖∞ / ‖F‖∞` of a Newton direction (inexact Newton forcing term).
const LINEAR_FORCING: f64 = 1e-3;

/// Dense Newton matrices up to this size; sparse beyond.
const DENSE_LIMIT: usize = 600;

fn validate(settings: &Settings) -> Result<(), SolveError> {
    if !(settings.tolerance.is_finite() && settings.tolerance > 0.0) {
        return Err(invalid(
            "settings.tolerance",
            format!("{} must be finite and > 0", settings.tolerance),
        ));
    }
    if !(settings.pivot_tolerance > 0.0 && settings.pivot_tolerance <= 1.0) {
        return Err(invalid(
            "settings.pivot_tolerance",
            format!("{} must be in (0, 1]", settings.pivot_tolerance),
        ));
    }
    if settings.max_iterations == 0 {
        return Err(invalid("settings.max_iterations", "must be at least 1"));
    }
    let rho = match settings.rho {
        Rho::PerPointDiagonal { factor }
        | Rho::PerPointCompliance { factor }
        | Rho::GlobalDiagonal { factor }
        | Rho::Fixed(factor) => factor,
    };
    if !(rho.is_finite() && rho > 0.0) {
        return Err(invalid(
            "settings.rho",
            format!("{rho} must be finite and > 0"),
        ));
    }
    if let Some(stall) = settings.stall {
        if !(stall.window >= 1 && stall.decrease > 0.0 && stall.decrease < 1.0) {
            return Err(invalid(
                "settings.stall",
                format!("{stall:?}: need window ≥ 1, 0 < decrease < 1"),
            ));
        }
    }
    if let Some(ls) = settings.line_search {
        if !(ls.armijo > 0.0 && ls.armijo < 0.5 && ls.shrink > 0.0 && ls.shrink < 1.0) {
            return Err(invalid(
                "settings.line_search",
                format!("{ls:?}: need 0 < armijo < 0.5, 0 < shrink < 1"),
            ));
        }
    }
    Ok(())
}

impl<const D: usize> Solver<D> {
    /// Validates the settings, chooses ρ per point and analyses the Newton system's pattern.
    pub fn new(problem: ReducedSystem<D>, settings: Settings) -> Result<Self, SolveError> {
        validate(&settings)?;
        let n = problem.operator.size();
        let n_points = problem.n_points();
        let diagonal = problem.operator.diagonal();
        let rho = choose_rho::<D>(&settings.rho, &diagonal, &problem.operator)?;
        let residual_rho = choose_rho::<D>(&RESIDUAL_RHO, &diagonal, &problem.operator)?;
        let blocks = match &problem.operator {
            Operator::Structured(s) => Some(PointBlocks::new(&s.b, n_points)),
            _ => None,
        };
        let mut solver = Self {
            settings,
            blocks,
            rho,
            residual_rho,
            dense: None,
            stress_sized: None,
            schur: None,
            z: vec![0.0; n],
            f: vec![0.0; n],
            lin: vec![blank(); n_points],
            trial_sigma: vec![0.0; n],
            trial_z: vec![0.0; n],
            trial_lin: vec![blank(); n_points],
            direction: vec![0.0; n],
            check: vec![0.0; n],
            scratch: Vec::new(),
            problem,
        };
        let symmetric = solver.problem.is_associative();
        match (&solver.problem.operator, settings.linear_solver) {
            (Operator::Dense(_), _) if n <= DENSE_LIMIT => solver.dense = Some(DenseSystem::new(n)),
            (Operator::Structured(s), LinearSolver::Auto | LinearSolver::SchurPivoting) => {
                let blocks = solver
                    .blocks
                    .as_ref()
                    .expect("structured operators carry point blocks");
                solver.schur =
                    Some(SchurSystem::new(s, blocks, symmetric).map_err(|e| invalid("B", e))?);
            }
            _ => solver.ensure_stress_sized()?,
        }
        Ok(solver)
    }

    fn ensure_stress_sized(&mut self) -> Result<(), SolveError> {
        if self.stress_sized.is_none() {
            let w = self.problem.operator.to_sparse();
            self.stress_sized = Some(StressSizedSystem::new::<D>(&w).map_err(|e| invalid("W", e))?);
        }
        Ok(())
    }

    pub fn problem(&self) -> &ReducedSystem<D> {
        &self.problem
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// ρ of every point, as used by the Newton iteration.
    pub fn rho(&self) -> &[f64] {
        &self.rho
    }

    /// ρ of every point in the stopping test: `1 / max diag W_i` (the point's block).
    pub fn residual_rho(&self) -> &[f64] {
        &self.residual_rho
    }

    /// Replaces `q`, keeping the operator, its analysis and ρ.
    pub fn set_q(&mut self, q: Vec<f64>) -> Result<(), SolveError> {
        self.problem.set_q(q)
    }

    /// `z = Wσ + q` at the last iterate of the last solve.
    pub fn z(&self) -> &[f64] {
        &self.z
    }

    /// `‖F‖∞` at `sigma` with the stopping test's ρ, without iterating: to choose between
    /// starting points.
    pub fn residual_at(&mut self, sigma: &[f64]) -> Result<f64, SolveError> {
        if sigma.len() != self.problem.operator.size() {
            return Err(invalid(
                "sigma",
                format!(
                    "length {} for an operator of size {}",
                    sigma.len(),
                    self.problem.operator.size()
                ),
            ));
        }
        self.evaluate(sigma, false);
        Ok(self.residual_norm(sigma))
    }

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
            if residual <= self.settings.tolerance * inf_norm(sigma).max(1.0) {
                report.status = Status::Converged;
                break;
            }
            if stopping::stagnated(&report.residual_history) {
                if let Some(floor) = self.floor_reached(sigma, residual) {
                    report.status = Status::RoundOffFloor;
                    report.round_off_floor = Some(floor);
                    break;
                }
            }
            if let Some(stall) = self.settings.stall {
                if report.iterations >= stall.after
                    && stopping::no_decrease(&report.merit_history, stall.window, stall.decrease)
                {
                    report.status = Status::Stalled;
                    break;
                }
            }
            if report.iterations == self.settings.max_iterations {
                report.status = Status::MaxIterations;
                break;
            }
            if let Err(status) = self.newton_direction(&mut report) {
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
                let count = |r: talus_bipotential::Region| {
                    self.lin.iter().filter(|l| l.region == r).count()
                };
                let changed = regions_before
                    .iter()
                    .zip(&self.lin)
                    .filter(|(r, l)| **r != l.region)
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
        // A failure at the floor is the floor: no step can make progress there.
        if matches!(
            report.status,
            Status::MaxIterations
                | Status::Stalled
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
        report.scale = inf_norm(sigma).max(1.0);
        report.seconds = start.elapsed().as_secs_f64();
        tracing::debug!(
            status = %report.status,
            iterations = report.iterations,
            residual,
            sigma_inf = inf_norm(sigma),
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
    fn floor_reached(&self, sigma: &[f64], residual: f64) -> Option<RoundOffFloor> {
        let estimate = stopping::floor_estimate(
            &self.problem.operator,
            self.blocks.as_ref(),
            sigma,
            &self.problem.q,
            &self.residual_rho,
        );
        (residual <= stopping::FLOOR_FACTOR * estimate).then_some(RoundOffFloor {
            reached: residual,
            estimate,
        })
    }

    /// `z`, `F` and the linearization at `sigma` (into the trial buffers when `trial`);
    /// returns `‖F‖²`.
    fn evaluate(&mut self, sigma: &[f64], trial: bool) -> f64 {
        let (z, lin) = if trial {
            (&mut self.trial_z, &mut self.trial_lin)
        } else {
            (&mut self.z, &mut self.lin)
        };
        apply(
            &self.problem.operator,
            self.blocks.as_ref(),
            sigma,
            Some(&self.problem.q),
            z,
            &mut self.scratch,
            self.settings.parallel,
        );
        let rules = &self.problem.rules;
        let rho = &self.rho;
        let z = &*z;
        let one = |(i, l): (usize, &mut NaturalMapLinearization<D>)| {
            *l = rules[i].natural_map_linearization(
                &block::<D>(sigma, i),
                &block::<D>(z, i),
                rho[i],
            );
        };
        if self.settings.parallel {
            lin.par_iter_mut()
                .enumerate()
                .with_min_len(256)
                .for_each(one);
        } else {
            lin.iter_mut().enumerate().for_each(one);
        }
        // Sequential sum: the merit must not depend on the thread count.
        lin.iter().map(|l| l.residual.norm_squared()).sum()
    }

    /// `‖F‖∞` at the current iterate (NaN if any entry is).
    fn residual_norm(&self, sigma: &[f64]) -> f64 {
        self.residual_norm_with(sigma, &self.z)
    }

    fn residual_norm_with(&self, sigma: &[f64], z: &[f64]) -> f64 {
        let rules = &self.problem.rules;
        let mut worst: f64 = 0.0;
        for (i, rule) in rules.iter().enumerate() {
            let f = rule.natural_map_residual(
                &block::<D>(sigma, i),
                &block::<D>(z, i),
                self.residual_rho[i],
            );
            for x in f.iter() {
                if x.is_nan() {
                    return f64::NAN;
                }
                worst = worst.max(x.abs());
            }
        }
        worst
    }

    /// Solves `J_F d = −F` into `self.direction`. A no-pivot LU direction that fails the
    /// accuracy check is recomputed once with the pivoting LU (`Report::pivoting_fallbacks`).
    fn newton_direction(&mut self, report: &mut Report) -> Result<(), Status> {
        for (i, l) in self.lin.iter().enumerate() {
            for a in 0..D {
                self.f[D * i + a] = -l.residual[a];
            }
        }
        let forced = self.settings.linear_solver == LinearSolver::SchurPivoting;
        let mut pivoting = forced;
        loop {
            let used = self.direction_by_schur(pivoting);
            if used.is_none() {
                self.direction_stress_sized()?;
            }
            let accurate = self.direction_is_accurate();
            if !accurate && used == Some(Factorized::NoPivotLu) {
                tracing::warn!("inaccurate no-pivot LU direction: retried with pivoting");
                pivoting = true;
                continue;
            }
            match used {
                Some(f) => {
                    report.schur_steps += 1;
                    if f == Factorized::PivotingLu && !forced {
                        report.pivoting_fallbacks += 1;
                    }
                }
                None => report.stress_sized_steps += 1,
            }
            return if accurate {
                Ok(())
            } else {
                Err(Status::SingularJacobian)
            };
        }
    }

    /// The direction through the velocity-sized Schur system, if the operator is structured
    /// and every local block is regular; `None` sends the step to the stress-sized system.
    fn direction_by_schur(&mut self, pivoting: bool) -> Option<Factorized> {
        let (Some(schur), Operator::Structured(s)) = (self.schur.as_mut(), &self.problem.operator)
        else {
            return None;
        };
        let blocks = self
            .blocks
            .as_ref()
            .expect("structured operators carry point blocks");
        match schur.solve(
            s,
            blocks,
            &self.lin,
            &self.rho,
            &self.f,
            &mut self.direction,
            if pivoting {
                LuChoice::Pivoting
            } else {
                LuChoice::NoPivot {
                    pivot_tolerance: self.settings.pivot_tolerance,
                }
            },
            self.settings.parallel,
        ) {
            Ok(used) => Some(used),
            Err(SchurFailure::SingularBlock(i)) => {
                tracing::debug!(point = i, "singular local block: stress-sized step");
                None
            }
            Err(SchurFailure::Factorization(e)) => {
                tracing::debug!(error = %e, "Schur factorization failed: stress-sized step");
                None
            }
        }
    }

    /// The direction through the stress-sized system `J_F d = −F` (dense or sparse).
    fn direction_stress_sized(&mut self) -> Result<(), Status> {
        if let (Some(dense), Operator::Dense(w)) = (self.dense.as_mut(), &self.problem.operator) {
            dense.solve(w, &self.lin, &self.rho, &self.f, &mut self.direction);
            return Ok(());
        }
        self.ensure_stress_sized()
            .map_err(|_| Status::SingularJacobian)?;
        let sys = self.stress_sized.as_mut().expect("just built");
        sys.solve(&self.lin, &self.rho, &self.f, &mut self.direction)
            .map_err(|e| {
                tracing::warn!(error = %e, "sparse LU failed");
                Status::SingularJacobian
            })
    }

    /// `d` finite and `‖J_F d + F‖∞ ≤ 1e-3 ‖F‖∞`: faer returns finite garbage on a
    /// numerically singular matrix, and a no-pivot LU may lose accuracy to growth.
    fn direction_is_accurate(&mut self) -> bool {
        if !self.direction.iter().all(|v| v.is_finite()) {
            return false;
        }
        apply(
            &self.problem.operator,
            self.blocks.as_ref(),
            &self.direction,
            None,
            &mut self.check,
            &mut self.scratch,
            self.settings.parallel,
        );
        let mut worst: f64 = 0.0;
        for (i, l) in self.lin.iter().enumerate() {
            let d = block::<D>(&self.direction, i);
            let wd = block::<D>(&self.check, i);
            let jd = d - l.projection_jacobian * d + l.coupling * wd * self.rho[i];
            worst = worst.max((jd - block::<D>(&self.f, i)).amax());
        }
        let scale = inf_norm(&self.f);
        // An inexact Newton step with forcing term 1e-3 keeps fast local convergence;
        // beyond it the matrix is numerically singular (or the answer is garbage).
        let accurate = worst <= LINEAR_FORCING * scale;
        if !accurate {
            tracing::warn!(
                linear_residual = worst,
                rhs = scale,
                "inaccurate Newton direction"
            );
        }
        accurate
    }

    /// Armijo backtracking on `‖F‖²` along `self.direction`; moves `sigma` and returns the
    /// new merit, or `None` when no step length is accepted.
    fn line_search(
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
            let mut trial = std::mem::take(&mut self.trial_sigma);
            for ((x, s), d) in trial.iter_mut().zip(sigma.iter()).zip(&self.direction) {
                *x = s + t * d;
            }
            let trial_merit = self.evaluate(&trial, true);
            self.trial_sigma = trial;
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
}

impl<const D: usize> Solver<D> {
    /// Near the solution `‖F_ρ‖²` with the iteration's (large) ρ reaches its round-off floor
    /// before the stopping test's residual does: then the full Newton step is taken if it
    /// lowers the latter.
    fn accept_full_step_if_measured_progress(&mut self, sigma: &mut [f64]) -> Option<f64> {
        let current = self.residual_norm(sigma);
        let mut trial = std::mem::take(&mut self.trial_sigma);
        for ((x, s), d) in trial.iter_mut().zip(sigma.iter()).zip(&self.direction) {
            *x = s + d;
        }
        let merit = self.evaluate(&trial, true);
        let full = self.residual_norm_with(&trial, &self.trial_z);
        self.trial_sigma = trial;
        if full < current {
            sigma.copy_from_slice(&self.trial_sigma);
            std::mem::swap(&mut self.z, &mut self.trial_z);
            std::mem::swap(&mut self.lin, &mut self.trial_lin);
            Some(merit)
        } else {
            None
        }
    }

    /// Moves `sigma` to the solution of the purely elastic problem `Wσ + q = 0`: one Newton
    /// step with every point treated as interior (`D = I`). From there the next
    /// linearization sees the return mapping of the elastic trial, the classical elastic
    /// predictor. Fails like a Newton step when `W` is singular.
    pub fn elastic_predictor(&mut self, sigma: &mut [f64]) -> Result<(), SolveError> {
        let n = self.problem.operator.size();
        if sigma.len() != n {
            return Err(invalid(
                "sigma",
                format!("length {} for an operator of size {n}", sigma.len()),
            ));
        }
        self.evaluate(sigma, false);
        for l in self.lin.iter_mut() {
            // Interior everywhere: F = ρ z, D = I, G = I.
            l.projection_jacobian = nalgebra::SMatrix::identity();
            l.coupling = nalgebra::SMatrix::identity();
            l.region = talus_bipotential::Region::Interior;
        }
        for (i, l) in self.lin.iter_mut().enumerate() {
            l.residual = block::<D>(&self.z, i) * self.rho[i];
        }
        let mut report = Report::start((0.0, 0.0));
        if let Err(status) = self.newton_direction(&mut report) {
            return Err(SolveError::NotConverged(Box::new(Report {
                status,
                ..report
            })));
        }
        for (s, d) in sigma.iter_mut().zip(&self.direction) {
            *s += d;
        }
        Ok(())
    }
}

impl<const D: usize> Solver<D> {
    /// Replaces the problem (operator, `q`, flow rules), keeping the Schur system's
    /// pattern and symbolic analysis when the new operator is structured with the same `B`
    /// sparsity pattern (rows, velocity columns, stored entries) and the same symmetry as
    /// the old one: a new time step, or a new friction pass, on the same particles. ρ is
    /// chosen anew. Otherwise the solver is rebuilt as by [`Solver::new`]. Returns whether
    /// the analysis was reused; on error the solver is left unchanged.
    pub fn replace_problem(&mut self, problem: ReducedSystem<D>) -> Result<bool, SolveError> {
        let reusable = match (&self.problem.operator, &problem.operator, &self.schur) {
            (Operator::Structured(old), Operator::Structured(new), Some(_)) => {
                old.lumped_mass.len() == new.lumped_mass.len()
                    && Self::same_pattern(&old.b, &new.b)
                    && self.problem.is_associative() == problem.is_associative()
            }
            _ => false,
        };
        if !reusable {
            *self = Self::new(problem, self.settings)?;
            return Ok(false);
        }
        let diagonal = problem.operator.diagonal();
        let rho = choose_rho::<D>(&self.settings.rho, &diagonal, &problem.operator)?;
        let residual_rho = choose_rho::<D>(&RESIDUAL_RHO, &diagonal, &problem.operator)?;
        if let Operator::Structured(s) = &problem.operator {
            self.blocks = Some(PointBlocks::new(&s.b, problem.n_points()));
        }
        self.rho = rho;
        self.residual_rho = residual_rho;
        // Built from W's values: stale with the new operator.
        self.stress_sized = None;
        self.problem = problem;
        Ok(true)
    }

    /// Same shape and the same stored entries, column by column (values may differ).
    fn same_pattern(
        a: &faer::sparse::SparseColMat<usize, f64>,
        b: &faer::sparse::SparseColMat<usize, f64>,
    ) -> bool {
        let (a, b) = (a.symbolic(), b.symbolic());
        a.nrows() == b.nrows()
            && a.ncols() == b.ncols()
            && (0..a.ncols()).all(|j| a.row_idx_of_col_raw(j) == b.row_idx_of_col_raw(j))
    }
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(
        0.0,
        |m: f64, x| if x.is_nan() { f64::NAN } else { m.max(x.abs()) },
    )
}

fn choose_rho<const D: usize>(
    rule: &Rho,
    diagonal: &[f64],
    operator: &Operator<D>,
) -> Result<Vec<f64>, SolveError> {
    let n_points = diagonal.len() / D;
    let point_max = |i: usize| {
        diagonal[D * i..D * i + D]
            .iter()
            .fold(0.0f64, |m, v| m.max(*v))
    };
    let rho: Vec<f64> = match *rule {
        Rho::Fixed(r) => vec![r; n_points],
        Rho::GlobalDiagonal { factor } => {
            let m = diagonal.iter().fold(0.0f64, |m, v| m.max(*v));
            vec![factor / m; n_points]
        }
        Rho::PerPointDiagonal { factor } => (0..n_points).map(|i| factor / point_max(i)).collect(),
        Rho::PerPointCompliance { factor } => match operator {
            Operator::Structured(s) => s
                .compliance
                .iter()
                .map(|c| factor / (0..D).fold(0.0f64, |m, k| m.max(c[(k, k)])))
                .collect(),
            _ => {
                return Err(invalid(
                    "settings.rho",
                    "PerPointCompliance needs a structured operator",
                ))
            }
        },
    };
    if let Some(i) = rho.iter().position(|r| !(r.is_finite() && *r > 0.0)) {
        return Err(invalid(
            "W",
            format!(
                "diagonal block of point {i} has no positive entry (max {}): ρ cannot be scaled",
                point_max(i)
            ),
        ));
    }
    Ok(rho)
}
