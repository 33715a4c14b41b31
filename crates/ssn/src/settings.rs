use crate::factorization::Ordering;

/// How ρ of the natural map `σ = P_K(σ − ρ y)` is chosen. ρ has units of stress per
/// strain; any ρ > 0 (per point) keeps the same solution but changes the iteration count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Rho {
    /// `ρ_i = factor / max_{k ∈ point i} W_kk`: normalised per point (`docs/derivations.md`,
    /// 'ρ per point'), so graded meshes and particle volumes spanning decades get comparable
    /// steps.
    PerPointDiagonal { factor: f64 },
    /// `ρ_i = factor / max diag S_i` for a structured `W = S + h² B M⁻¹ Bᵀ`: the scale of a
    /// return mapping (factor 1 gives `ρ_i = 2G / V_i` for isotropic elasticity), so the
    /// first Newton step predicts the plastic points as an elastic predictor would.
    PerPointCompliance { factor: f64 },
    /// `ρ = factor / max_k W_kk`, one value for every point.
    GlobalDiagonal { factor: f64 },
    /// The value given, for every point.
    Fixed(f64),
}

impl Rho {
    /// The factor of a scaled ρ, or the value of a fixed one.
    pub const fn factor(&self) -> f64 {
        match *self {
            Rho::PerPointDiagonal { factor }
            | Rho::PerPointCompliance { factor }
            | Rho::GlobalDiagonal { factor }
            | Rho::Fixed(factor) => factor,
        }
    }
}

/// Backtracking (Armijo) line search on the merit `½‖F‖²`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineSearch {
    /// Sufficient decrease `‖F(σ + t d)‖² ≤ (1 − 2 c t) ‖F(σ)‖²`.
    pub armijo: f64,
    /// Step reduction per backtrack.
    pub shrink: f64,
    /// Backtracks before the step is declared failed.
    pub max_backtracks: usize,
}

impl LineSearch {
    pub const DEFAULT: Self = Self {
        armijo: 1e-4,
        shrink: 0.5,
        max_backtracks: 40,
    };
}

impl Default for LineSearch {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// From iteration `after` on, ends a solve whose merit `‖F_ρ‖₂` has not fallen below
/// `decrease` times its value `window` iterations earlier ([`Status::Stalled`](crate::Status::Stalled)), so that a
/// caller who can react (a shorter time step) need not wait for `max_iterations`
/// (`docs/solver.md`, "Non-associative Newton at the mechanism's onset").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stall {
    /// Iterations before the rule applies: a solve that is slow but converges within them
    /// keeps its time step.
    pub after: usize,
    /// Iterations looked back; at least 1.
    pub window: usize,
    /// Required decrease over the window, in (0, 1).
    pub decrease: f64,
}

impl Stall {
    /// From iteration 25 (slow solves that converge within it, up to 23 iterations on the
    /// footing snapshots, keep their step), a merit not halved over 10 iterations: the
    /// attempts that fail at the footing's mechanism onset stall for 20–40 iterations.
    pub const DEFAULT: Self = Self {
        after: 25,
        window: 10,
        decrease: 0.5,
    };
}

/// Ends early a solve that shows the signature of a time step past its fold
/// (`docs/solver.md`, 'The step control'): the [`Stall`] rule of `stall`, while the Newton
/// matrix had negative pivots in at least `indefinite` of its window's iterations
/// ([`Status::Folded`](crate::Status::Folded)). Converged non-associative solves also meet
/// negative pivots, but mostly in their first iterations and with a falling merit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fold {
    pub stall: Stall,
    /// Iterations of the window whose factorization had a negative pivot; at least 1.
    pub indefinite: usize,
}

impl Fold {
    /// From iteration 10, a merit not halved over 3 iterations, 2 of them with negative
    /// pivots. Chosen on the 104×48 footing's steps 1–41 (78 converged and 10 failed
    /// solves): it ends 9 of the 10 failures early and none of the converged solves.
    pub const DEFAULT: Self = Self {
        stall: Stall {
            after: 10,
            window: 3,
            decrease: 0.5,
        },
        indefinite: 2,
    };
}

/// Which linear system gives the Newton direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LinearSolver {
    /// Velocity-sized Schur complement for structured operators (`docs/derivations.md`,
    /// 'The Schur step'), stress-sized otherwise.
    #[default]
    Auto,
    /// Always the stress-sized system `J_F d = −F` (for checking the Schur path).
    StressSized,
    /// The Schur system with faer's partial-pivoting LU at every step (for checking the
    /// no-pivot LU that `Auto` uses for non-associative flow).
    SchurPivoting,
    /// The Schur system factorized by MUMPS over `MPI_COMM_WORLD` (cargo feature `mpi`;
    /// `docs/distributed.md`): every rank runs the same solve and calls it together,
    /// each evaluating and linearizing the points of its own METIS groups only (σ and
    /// `z` are whole on every rank after a solve). LU for non-associative flow, LDLᵀ for
    /// associative.
    Distributed(FactorRanks),
}

impl LinearSolver {
    /// MUMPS over the MPI ranks, wherever it factorizes.
    pub fn is_distributed(self) -> bool {
        matches!(self, LinearSolver::Distributed(_))
    }
}

/// Which ranks factorize in a distributed solve (`LinearSolver::Distributed`;
/// `docs/distributed.md`, 'Reproducibility').
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FactorRanks {
    /// All of them: the factors' memory and flops are split between the ranks. MUMPS adds
    /// what a front receives from other ranks in the order it arrives, so two runs on the
    /// same ranks differ in the last bits.
    #[default]
    All,
    /// Rank 0 alone, on the entries every rank sends it in rank order: the same ranks give
    /// the same bits on every run. The factorization's memory and time are rank 0's.
    Host,
}

/// The inexact-Newton forcing term `η` of a Krylov solve: the direction must satisfy
/// `‖J_F d + F‖∞ ≤ η ‖F‖∞` (`docs/krylov.md`, 'The forcing term').
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Forcing {
    /// `η` fixed, in `(0, 1e-3]` (1e-3: the accuracy every direction is checked to).
    Fixed(f64),
    /// Eisenstat & Walker (1996, SIAM J. Sci. Comput. 17, 16–32), choice 2:
    /// `η_k = gamma (‖F_k‖ / ‖F_{k−1}‖)^alpha`, safeguarded by `gamma η_{k−1}^alpha` when
    /// that exceeds 0.1, capped at `max` (≤ 1e-3), and never below what the stopping test
    /// needs (a hundredth of `tolerance · scale / ‖F‖`): tight near the solution, where
    /// Newton converges fast, loose far from it.
    EisenstatWalker { gamma: f64, alpha: f64, max: f64 },
}

impl Forcing {
    pub const DEFAULT: Self = Forcing::EisenstatWalker {
        gamma: 0.9,
        alpha: 2.0,
        max: 1e-3,
    };
}

/// Newton directions from restarted GMRES on the velocity-sized Newton system,
/// preconditioned by the factorization of an earlier Newton matrix (this solve's or an
/// earlier one's); a new factorization only when GMRES misses its tolerance within
/// `max_iterations`, or needed more than `degraded_iterations` the last time
/// (`docs/krylov.md`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Krylov {
    /// Krylov vectors per GMRES cycle (memory: `2 · restart` velocity-sized vectors).
    pub restart: usize,
    /// GMRES iterations (solves with the old factors) before refactorizing.
    pub max_iterations: usize,
    /// A GMRES solve that took more iterations than this converged, but the preconditioner
    /// has aged: the next Newton iteration refactorizes without trying GMRES.
    pub degraded_iterations: usize,
    /// Try GMRES on an earlier Newton iteration's factorization first (true). With
    /// `false` every Newton iteration factorizes and GMRES, preconditioned by that fresh
    /// factor, only corrects what its storage precision left (`Single`: iterative
    /// refinement by GMRES, Carson & Higham 2018, SIAM J. Sci. Comput. 40(2)): the
    /// choice where the Newton matrix changes too much between iterations for an old
    /// factor to precondition it (`docs/krylov.md`, 'A fresh f32 factor every iteration').
    pub reuse: bool,
    pub forcing: Forcing,
    /// The precision the factorization is stored in. `Single` (associative flow only: the
    /// Cholesky factor) halves its memory; every direction then comes from GMRES, and a
    /// fresh f32 factor that does not bring GMRES to its tolerance is replaced by an f64
    /// one for that iteration (`docs/krylov.md`, 'A single-precision factor').
    pub precision: Precision,
}

/// Storage precision of the factorization used by [`NewtonSolve::Krylov`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Precision {
    #[default]
    Double,
    Single,
}

impl Krylov {
    /// Restart 20, at most 20 iterations, refactorize after a solve that needed more
    /// than 10, reuse on, Eisenstat–Walker forcing capped at 1e-3.
    pub const DEFAULT: Self = Self {
        restart: 20,
        max_iterations: 20,
        degraded_iterations: 10,
        reuse: true,
        forcing: Forcing::DEFAULT,
        precision: Precision::Double,
    };
}

impl Default for Krylov {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// How the velocity-sized (Schur) Newton system is solved.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum NewtonSolve {
    /// A factorization at every Newton iteration (the behaviour before this setting,
    /// bit for bit).
    #[default]
    Direct,
    /// GMRES preconditioned by a reused factorization ([`Krylov`]).
    Krylov(Krylov),
}

/// Solver settings; the presets [`Settings::reduced`] (the default), [`Settings::fem`] and
/// [`Settings::mpm`] hold the defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Converged when `‖F‖∞ ≤ tolerance · max(1, ‖σ‖∞)`. Default `1e-12`.
    pub tolerance: f64,
    /// Newton iterations before giving up. Default 100.
    pub max_iterations: usize,
    /// Default `PerPointDiagonal { factor: 10.0 }` (see `docs/solver.md` for measurements).
    pub rho: Rho,
    /// Default: Armijo 1e-4, halving, 40 backtracks. `None`: full Newton steps.
    pub line_search: Option<LineSearch>,
    /// Start from the σ passed to `solve` (true, default) or from σ = 0.
    pub warm_start: bool,
    /// Default `None`: iterate until converged, failed or `max_iterations`.
    pub stall: Option<Stall>,
    /// Default `None`: no early end on negative pivots.
    pub fold: Option<Fold>,
    pub linear_solver: LinearSolver,
    /// The no-pivot LU refuses a pivot `|u_jj| ≤ pivot_tolerance · |k_jj|` and solves that
    /// iteration with the pivoting LU (`Report::pivoting_fallbacks`). Default `1e-10`; in
    /// `(0, 1]`.
    pub pivot_tolerance: f64,
    /// Spread per-point work over rayon's pool; results do not depend on it.
    pub parallel: bool,
    /// Fill-reducing ordering of the Schur factorizations. Default AMD; METIS' nested
    /// dissection with the cargo feature `metis` (`docs/krylov.md`, 'Ordering').
    pub ordering: Ordering,
    /// Default [`NewtonSolve::Direct`].
    pub newton_solve: NewtonSolve,
}

/// The one place of the solver's defaults (`docs/solver.md`): every caller (the scenes, the
/// `talus` command line, the Python package) starts from one of these presets.
impl Settings {
    /// A problem read as given (`talus reduced`, Siconos files): `W` unstructured, so ρ is
    /// scaled by its diagonal; 100 iterations.
    pub const fn reduced() -> Self {
        Self {
            tolerance: 1e-12,
            max_iterations: 100,
            rho: Rho::PerPointDiagonal { factor: 10.0 },
            line_search: Some(LineSearch::DEFAULT),
            warm_start: true,
            stall: None,
            fold: None,
            linear_solver: LinearSolver::Auto,
            pivot_tolerance: crate::factorization::DEFAULT_PIVOT_TOLERANCE,
            parallel: true,
            ordering: Ordering::Amd,
            newton_solve: NewtonSolve::Direct,
        }
    }

    /// A time step of a finite-element model: ρ at the return-mapping scale of the
    /// compliance (factor 0.3), 50 iterations, and a stalled solve stopped from iteration
    /// 25 when its merit has not halved over 10 iterations, or from iteration 10 over 3
    /// when the Newton matrix had negative pivots, so that its step is halved early
    /// (`docs/solver.md`, "Non-associative Newton at the mechanism's onset", 'The step
    /// control').
    pub const fn fem() -> Self {
        Self {
            max_iterations: 50,
            rho: Rho::PerPointCompliance { factor: 0.3 },
            stall: Some(Stall::DEFAULT),
            fold: Some(Fold::DEFAULT),
            ..Self::reduced()
        }
    }

    /// A sub-step of the material point method: as [`Settings::fem`], but slow first
    /// friction passes run on (the a = 2 column: 92.2 → 102.4 iterations per step with a
    /// stall window of 10, `docs/mpm-performance.md`).
    pub const fn mpm() -> Self {
        Self {
            stall: None,
            fold: None,
            ..Self::fem()
        }
    }
}

impl Default for Settings {
    /// [`Settings::reduced`].
    fn default() -> Self {
        Self::reduced()
    }
}
