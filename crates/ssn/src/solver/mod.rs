//! The semi-smooth Newton solver: its state and set-up here; the iteration, the Newton
//! direction, the elastic predictor, problem replacement and ρ in their own files.
mod direction;
mod elastic_predictor;
mod iteration;
mod replace;
mod rho;

use rho::{choose_rho, RESIDUAL_RHO};
use talus_bipotential::{FlowRule, NaturalMapLinearization};

use crate::error::invalid;
use crate::newton::{DenseSystem, SchurSystem, StressSizedSystem};
pub(crate) use crate::norm::inf_norm;
use crate::operator::{block, PointBlocks};
use crate::point_share::PointShare;
use crate::{
    Forcing, LinearSolver, NewtonSolve, Operator, Precision, ReducedSystem, Rho, Settings,
    SolveError, Stall,
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
    /// The last Krylov forcing term of the current solve (Eisenstat–Walker's safeguard).
    forcing: Option<f64>,
    /// GMRES on the stress-sized system (`NewtonSolve::Krylov` without a Schur system).
    stress_krylov: StressKrylov,
    /// The points this rank owns (`LinearSolver::Distributed`): within a solve only their
    /// σ, z and linearizations are current here; a solve ends with all of them gathered.
    share: Option<PointShare>,
}

/// The stress-sized Krylov path's state.
#[derive(Default)]
struct StressKrylov {
    workspace: Option<crate::krylov::GmresWorkspace>,
    /// The last GMRES solve needed more than `degraded_iterations`: refactorize next time.
    degraded: bool,
    /// `W x` inside the product with `J_F`.
    wx: Vec<f64>,
}

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
    let stall_ok =
        |stall: &Stall| stall.window >= 1 && stall.decrease > 0.0 && stall.decrease < 1.0;
    if let Some(stall) = settings.stall {
        if !stall_ok(&stall) {
            return Err(invalid(
                "settings.stall",
                format!("{stall:?}: need window ≥ 1, 0 < decrease < 1"),
            ));
        }
    }
    if let Some(fold) = settings.fold {
        if !(stall_ok(&fold.stall) && fold.indefinite >= 1) {
            return Err(invalid(
                "settings.fold",
                format!("{fold:?}: need window ≥ 1, indefinite ≥ 1, 0 < decrease < 1"),
            ));
        }
    }
    if let NewtonSolve::Krylov(k) = settings.newton_solve {
        let forcing_ok = |eta: f64| eta > 0.0 && eta <= LINEAR_FORCING;
        let forcing = match k.forcing {
            Forcing::Fixed(eta) => forcing_ok(eta),
            Forcing::EisenstatWalker { gamma, alpha, max } => {
                gamma > 0.0 && gamma <= 1.0 && alpha > 1.0 && alpha <= 2.0 && forcing_ok(max)
            }
        };
        if !(k.restart >= 1 && k.max_iterations >= 1 && forcing) {
            return Err(invalid(
                "settings.newton_solve",
                format!(
                    "{k:?}: need restart ≥ 1, max_iterations ≥ 1, η in (0, {LINEAR_FORCING}], \
                     0 < gamma ≤ 1, 1 < alpha ≤ 2"
                ),
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
            forcing: None,
            stress_krylov: StressKrylov::default(),
            share: None,
            problem,
        };
        let symmetric = solver.problem.is_associative();
        if settings.linear_solver.is_distributed()
            && !matches!(solver.problem.operator, Operator::Structured(_))
        {
            return Err(invalid(
                "settings.linear_solver",
                "Distributed (MUMPS) factorizes the Schur system of a structured operator \
                 (S + h² B M⁻¹ Bᵀ), not a dense or sparse W",
            ));
        }
        match (&solver.problem.operator, settings.linear_solver) {
            (Operator::Dense(_), _) if n <= DENSE_LIMIT => solver.dense = Some(DenseSystem::new(n)),
            (
                Operator::Structured(s),
                LinearSolver::Auto | LinearSolver::SchurPivoting | LinearSolver::Distributed(_),
            ) => {
                let blocks = solver
                    .blocks
                    .as_ref()
                    .expect("structured operators carry point blocks");
                let single = matches!(
                    settings.newton_solve,
                    NewtonSolve::Krylov(k) if k.precision == Precision::Single
                );
                if single && !symmetric {
                    return Err(invalid(
                        "settings.newton_solve",
                        "a single-precision factor needs an associative flow rule (Cholesky)",
                    ));
                }
                let distributed = match settings.linear_solver {
                    LinearSolver::Distributed(ranks) => Some(ranks),
                    _ => None,
                };
                if distributed.is_some()
                    && (settings.newton_solve != NewtonSolve::Direct || !cfg!(feature = "mpi"))
                {
                    return Err(invalid(
                        "settings.linear_solver",
                        "Distributed (MUMPS) needs the cargo feature `mpi` and \
                         `NewtonSolve::Direct`",
                    ));
                }
                solver.schur = Some(
                    SchurSystem::new(s, blocks, symmetric, settings.ordering, single, distributed)
                        .map_err(|e| invalid("B", e))?,
                );
            }
            _ => solver.ensure_stress_sized()?,
        }
        let share = match &solver.schur {
            Some(schur) => schur.point_share().map_err(|e| invalid("B", e))?,
            None => None,
        };
        if let Some(share) = share {
            if let Some(blocks) = solver.blocks.as_mut() {
                blocks.keep_points(share.owned());
            }
            tracing::debug!(
                rank = share.rank(),
                points = share.points().len(),
                of_points = n_points,
                "this rank's points"
            );
            solver.share = Some(share);
        }
        Ok(solver)
    }

    /// `‖v‖∞` of a stress-sized vector over every rank's own points (NaN if any entry is).
    fn norm(&self, v: &[f64]) -> f64 {
        match &self.share {
            None => inf_norm(v),
            Some(share) => share.max(
                share
                    .points()
                    .iter()
                    .map(|&i| inf_norm(&v[D * i..D * i + D]))
                    .fold(0.0, nan_max),
            ),
        }
    }

    /// `z` whole on every rank (as `z()` promises).
    fn gather_z(&mut self) {
        if let Some(share) = &self.share {
            share.gather_points::<D>(&mut self.z);
        }
    }

    /// Every point's block of `v` current on every rank (after a distributed solve's
    /// work on owned points).
    fn gather(&self, v: &mut [f64]) {
        if let Some(share) = &self.share {
            share.gather_points::<D>(v);
        }
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

    /// Replaces the flow rules, with the same number of points and symmetry
    /// ([`ReducedSystem::set_rules`]); the factorizations stay valid.
    pub fn set_rules(&mut self, rules: Vec<FlowRule<D>>) -> Result<(), SolveError> {
        self.problem.set_rules(rules)
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
        let residual = self.residual_norm(sigma);
        // `z()` whole on every rank, as after a solve.
        self.gather_z();
        Ok(residual)
    }
}

/// The larger of two values, NaN if either is.
fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

impl<const D: usize> Solver<D> {
    /// Stored entries of the velocity-sized Newton matrix's factors (`L`, or `L` and `U`);
    /// `None` without a Schur system.
    pub fn factor_nnz(&self) -> Option<usize> {
        self.schur.as_ref().map(|s| s.factor_nnz())
    }

    /// Bytes of the velocity-sized Newton matrix's stored factors (f64 and, with
    /// `Precision::Single`, f32) and of its GMRES workspace; `None` without a Schur system.
    pub fn factor_memory(&self) -> Option<(usize, usize)> {
        self.schur.as_ref().map(|s| s.memory())
    }
}
