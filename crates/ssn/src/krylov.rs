//! Restarted, right-preconditioned GMRES (Saad & Schultz 1986; Saad, *Iterative Methods
//! for Sparse Linear Systems*, 2nd ed., alg. 9.5 and 9.6): the Newton system's Krylov
//! solve preconditioned by an earlier factorization (`docs/krylov.md`).
//!
//! Right preconditioning `A P⁻¹ y = b`, `x = P⁻¹ y`, so the residual GMRES minimizes is
//! the true `‖b − A x‖₂`, whatever `P`. The preconditioned vectors `zⱼ = P⁻¹ vⱼ` are
//! kept (as flexible GMRES does, Saad alg. 9.6) so that the update `x += Z y` costs no
//! further solve with `P`: in 3D a solve with the factors is the expensive step.
//! Arnoldi by modified Gram–Schmidt, the least-squares problem by Givens rotations.
//!
//! The stopping test is the caller's: at each restart (and when the Givens estimate says
//! the target is met) the true residual `r = b − A x` is computed and handed to a
//! `verdict`, which accepts `x` or asks for a smaller 2-norm target. The Newton solver
//! uses it to test the residual of the *stress* system that its direction must satisfy
//! (`docs/krylov.md`, 'Which residual'). Sequential and in a fixed order: the answer
//! does not depend on the thread count.
//!
//! ```
//! use talus_ssn::krylov::{Gmres, GmresWorkspace};
//! // [[4, 1], [2, 3]] x = [5, 5], preconditioned by its diagonal.
//! let apply = |x: &[f64], y: &mut [f64]| {
//!     y[0] = 4.0 * x[0] + x[1];
//!     y[1] = 2.0 * x[0] + 3.0 * x[1];
//! };
//! let precondition = |x: &mut [f64]| {
//!     x[0] /= 4.0;
//!     x[1] /= 3.0;
//! };
//! let mut x = vec![0.0; 2];
//! let mut workspace = GmresWorkspace::new(2, 5);
//! let gmres = Gmres { restart: 5, max_iterations: 10, project_after: 0 };
//! let solved = gmres
//!     .solve_relative(&mut workspace, apply, precondition, &[5.0, 5.0], &mut x, 1e-12)
//!     .unwrap();
//! assert!(solved.iterations <= 2);
//! assert!((x[0] - 1.0).abs() < 1e-12 && (x[1] - 1.0).abs() < 1e-12);
//! ```

/// `Gmres::project_after` of the Newton solver's Krylov solves: after 4 iterations the
/// rate of a stale preconditioner is plain (on the 2D and 3D footings a converging solve
/// falls by 1e-1–1e-2 per iteration).
pub const PROJECT_AFTER: usize = 4;

/// Restart length and iteration cap of a GMRES solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Gmres {
    /// Krylov vectors per cycle (the `m` of GMRES(m)); at least 1.
    pub restart: usize,
    /// Products with `A P⁻¹` over all cycles before giving up.
    pub max_iterations: usize,
    /// From this many iterations into a cycle on (0: never), give up early when the
    /// cycle's mean rate of decrease, continued, would not reach the target within twice
    /// `max_iterations`: a stale preconditioner shows itself in the first iterations, and
    /// each iteration is a solve with the factors.
    pub project_after: usize,
}

/// What the caller's verdict says of an iterate whose residual met the current target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Verdict {
    /// `x` is accurate enough.
    Accept,
    /// Not yet: iterate on to this 2-norm of the residual (smaller than the last).
    Continue { target: f64 },
}

/// A converged solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GmresSolved {
    /// Products with `A P⁻¹` (one solve with `P` each).
    pub iterations: usize,
    /// True `‖b − A x‖₂` at the accepted `x`.
    pub residual: f64,
}

/// A solve that did not reach its target; `x` holds the last iterate (of the last
/// restart when given up early: `residual` is then the cycle's estimate).
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum GmresError {
    #[error("GMRES did not converge in {iterations} iterations: ‖r‖₂ = {residual:e} > {target:e}")]
    NotConverged {
        iterations: usize,
        residual: f64,
        target: f64,
    },
    #[error("GMRES met a non-finite value after {iterations} iterations")]
    NonFinite { iterations: usize },
    #[error("GMRES: restart must be ≥ 1 and the workspace sized for it")]
    Settings,
}

/// The Krylov basis, its preconditioned images and the Hessenberg matrix, kept across
/// solves of the same size.
#[derive(Debug, Clone)]
pub struct GmresWorkspace {
    n: usize,
    restart: usize,
    /// `restart + 1` basis vectors `vⱼ`, each `n` long.
    v: Vec<f64>,
    /// `restart` preconditioned vectors `zⱼ = P⁻¹ vⱼ`.
    z: Vec<f64>,
    /// Column-major `(restart + 1) × restart` Hessenberg matrix, rotated in place to `R`.
    h: Vec<f64>,
    cos: Vec<f64>,
    sin: Vec<f64>,
    /// The rotated right-hand side `β e₁`.
    g: Vec<f64>,
    r: Vec<f64>,
}

impl GmresWorkspace {
    pub fn new(n: usize, restart: usize) -> Self {
        Self {
            n,
            restart,
            v: vec![0.0; n * (restart + 1)],
            z: vec![0.0; n * restart],
            h: vec![0.0; (restart + 1) * restart],
            cos: vec![0.0; restart],
            sin: vec![0.0; restart],
            g: vec![0.0; restart + 1],
            r: vec![0.0; n],
        }
    }

    /// Bytes held (the basis and its preconditioned images dominate).
    pub fn bytes(&self) -> usize {
        8 * (self.v.len() + self.z.len() + self.h.len() + self.r.len())
    }

    pub(crate) fn fits(&self, n: usize, restart: usize) -> bool {
        self.n == n && self.restart >= restart
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

impl Gmres {
    /// Solves `A x = b` from the initial `x` until `‖b − A x‖₂ ≤ relative · ‖b‖₂`.
    pub fn solve_relative(
        &self,
        workspace: &mut GmresWorkspace,
        apply: impl FnMut(&[f64], &mut [f64]),
        precondition: impl FnMut(&mut [f64]),
        b: &[f64],
        x: &mut [f64],
        relative: f64,
    ) -> Result<GmresSolved, GmresError> {
        let target = relative * norm(b);
        self.solve(workspace, apply, precondition, b, x, target, |_, _| {
            Verdict::Accept
        })
    }

    /// Solves `A x = b` from the initial `x`: `apply(x, y)` writes `y = A x`,
    /// `precondition(v)` overwrites `v` with `P⁻¹ v`. Whenever the true residual
    /// `r = b − A x` has `‖r‖₂ ≤ target`, `verdict(x, r)` accepts `x` or sets a smaller
    /// target. [`GmresError::NotConverged`] after `max_iterations` products.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &self,
        ws: &mut GmresWorkspace,
        mut apply: impl FnMut(&[f64], &mut [f64]),
        mut precondition: impl FnMut(&mut [f64]),
        b: &[f64],
        x: &mut [f64],
        mut target: f64,
        mut verdict: impl FnMut(&[f64], &[f64]) -> Verdict,
    ) -> Result<GmresSolved, GmresError> {
        let (n, m) = (b.len(), self.restart);
        if m == 0 || x.len() != n || !ws.fits(n, m) {
            return Err(GmresError::Settings);
        }
        let ld = ws.restart + 1; // leading dimension of h
        let mut iterations = 0;
        loop {
            // The true residual at each restart: the Givens estimate drifts from it.
            apply(x, &mut ws.r);
            for (r, b) in ws.r.iter_mut().zip(b) {
                *r = b - *r;
            }
            let beta = norm(&ws.r);
            if !beta.is_finite() {
                return Err(GmresError::NonFinite { iterations });
            }
            if beta <= target {
                match verdict(x, &ws.r) {
                    Verdict::Accept => {
                        return Ok(GmresSolved {
                            iterations,
                            residual: beta,
                        })
                    }
                    // A target that does not shrink would loop: at least halve it.
                    Verdict::Continue { target: t } => target = t.min(0.5 * beta),
                }
            }
            if iterations >= self.max_iterations || beta == 0.0 {
                return Err(GmresError::NotConverged {
                    iterations,
                    residual: beta,
                    target,
                });
            }
            // v₀ = r / β, g = β e₁.
            for (v, r) in ws.v[..n].iter_mut().zip(&ws.r) {
                *v = r / beta;
            }
            ws.g.fill(0.0);
            ws.g[0] = beta;
            let mut k = 0; // columns of this cycle
            while k < m && iterations < self.max_iterations {
                let j = k;
                // zⱼ = P⁻¹ vⱼ, w = A zⱼ into v_{j+1}.
                let (v_head, v_tail) = ws.v.split_at_mut((j + 1) * n);
                let zj = &mut ws.z[j * n..(j + 1) * n];
                zj.copy_from_slice(&v_head[j * n..]);
                precondition(zj);
                let w = &mut v_tail[..n];
                apply(zj, w);
                iterations += 1;
                // Modified Gram–Schmidt against v₀ … vⱼ.
                let hj = &mut ws.h[j * ld..(j + 1) * ld];
                for (i, hij) in hj.iter_mut().enumerate().take(j + 1) {
                    let vi = &v_head[i * n..(i + 1) * n];
                    let c = dot(w, vi);
                    *hij = c;
                    for (w, v) in w.iter_mut().zip(vi) {
                        *w -= c * v;
                    }
                }
                let next = norm(w);
                hj[j + 1] = next;
                if !next.is_finite() {
                    return Err(GmresError::NonFinite { iterations });
                }
                if next > 0.0 {
                    for w in w.iter_mut() {
                        *w /= next;
                    }
                }
                // Earlier rotations on the new column, then the one that zeroes h_{j+1,j}.
                for i in 0..j {
                    let (a, c) = (hj[i], hj[i + 1]);
                    hj[i] = ws.cos[i] * a + ws.sin[i] * c;
                    hj[i + 1] = -ws.sin[i] * a + ws.cos[i] * c;
                }
                let (a, c) = (hj[j], hj[j + 1]);
                let radius = a.hypot(c);
                let (cs, sn) = if radius == 0.0 {
                    (1.0, 0.0)
                } else {
                    (a / radius, c / radius)
                };
                ws.cos[j] = cs;
                ws.sin[j] = sn;
                hj[j] = radius;
                hj[j + 1] = 0.0;
                ws.g[j + 1] = -sn * ws.g[j];
                ws.g[j] *= cs;
                k += 1;
                let estimate = ws.g[j + 1].abs();
                // `next == 0`: the Krylov space is invariant, the solution is in it.
                if estimate <= target || next == 0.0 {
                    break;
                }
                if self.project_after > 0 && k >= self.project_after {
                    let rate = (estimate / beta).powf(1.0 / k as f64);
                    let more = if rate < 1.0 {
                        (target / estimate).ln() / rate.ln()
                    } else {
                        f64::INFINITY
                    };
                    if iterations as f64 + more > 2.0 * self.max_iterations as f64 {
                        return Err(GmresError::NotConverged {
                            iterations,
                            residual: estimate,
                            target,
                        });
                    }
                }
            }
            // y = R⁻¹ g (upper triangular k × k), x += Z y.
            for i in (0..k).rev() {
                let mut s = ws.g[i];
                for c in i + 1..k {
                    s -= ws.h[c * ld + i] * ws.g[c];
                }
                let rii = ws.h[i * ld + i];
                ws.g[i] = if rii == 0.0 { 0.0 } else { s / rii };
            }
            for c in 0..k {
                let yc = ws.g[c];
                for (x, z) in x.iter_mut().zip(&ws.z[c * n..(c + 1) * n]) {
                    *x += yc * z;
                }
            }
        }
    }
}
