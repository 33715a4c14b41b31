//! Reproduces the Siconos associative footing problem `plasticity_2d_footing_100_theta0.dat`
//! as the second-order-cone QP `min ½σᵀWσ + qᵀσ, σ_i ∈ K_i` solved by Clarabel, and checks
//! that talus-ssn (default settings, σ = 0) finds the same σ and satisfies the KKT conditions.
//!
//! Sign reasoning for the KKT check (the QP is convex: W is PSD, K = Π K_i a closed convex
//! cone). The minimiser σ of f(σ) = ½σᵀWσ + qᵀσ over K satisfies ∇f(σ) = Wσ + q = z with
//! −z ∈ N_K(σ) = {v : v·τ ≤ 0 ∀τ ∈ K, v·σ = 0}, i.e. z·τ ≥ 0 for all τ ∈ K (z ∈ K*) and
//! z·σ = 0. Since σ_i·z_i ≥ 0 for every cone, the sum vanishes only if each term does:
//! complementarity holds per cone. For K_i = {‖σ_T‖ ≤ η σ_0}, K_i* = {‖z_T‖ ≤ z_0 / η}
//! (σ·z ≥ σ_0 z_0 − ‖σ_T‖‖z_T‖ ≥ σ_0 z_0 − ησ_0 z_0/η = 0). This is also the fixed point of
//! the natural map σ = P_K(σ − ρz) that the ssn solves (σ − ρz − σ ∈ N_K(σ)); with the
//! opposite sign (−z ∈ K*) the check fails on every plastic cone, and the test requires
//! plastic cones with z_i well away from 0 so that the sign is actually exercised.

use std::path::PathBuf;

use clarabel::solver::{DefaultSolver, IPSolver, SolverStatus};
use talus_ssn::siconos::{SiconosModel, SiconosProblem};
use talus_ssn::{reduced_system_from_siconos, Settings, Solver};

#[path = "common/clarabel_qp.rs"]
mod clarabel_qp;
use clarabel_qp::{clarabel_settings, qp};

const FILE: &str = "plasticity_2d_footing_100_theta0.dat";

fn load() -> SiconosProblem {
    let path = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/siconos-plasticity/"
    ))
    .join(FILE);
    SiconosProblem::from_path(&path).unwrap_or_else(|e| panic!("{FILE}: {e}"))
}

fn eta_of(p: &SiconosProblem) -> Vec<f64> {
    match &p.model {
        SiconosModel::DruckerPrager { eta, theta } => {
            assert!(
                theta.iter().all(|&t| t == 0.0),
                "{FILE} must be associative"
            );
            eta.clone()
        }
        other => panic!("{FILE}: Drucker-Prager expected, found {other:?}"),
    }
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m: f64, x| m.max(x.abs()))
}

struct ClarabelResult {
    x: Vec<f64>,
    status: SolverStatus,
    iterations: u32,
    res_primal: f64,
    res_dual: f64,
    gap_abs: f64,
    gap_rel: f64,
}

fn solve_clarabel(p: &SiconosProblem, tol: f64) -> ClarabelResult {
    let data = qp(p);
    let settings = clarabel_settings((tol != 1e-8).then_some(tol));
    let mut solver =
        DefaultSolver::new(&data.p, &data.q, &data.a, &data.b, &data.cones, settings).unwrap();
    solver.solve();
    ClarabelResult {
        x: solver.solution.x.clone(),
        status: solver.solution.status,
        iterations: solver.solution.iterations,
        res_primal: solver.info.res_primal,
        res_dual: solver.info.res_dual,
        gap_abs: solver.info.gap_abs,
        gap_rel: solver.info.gap_rel,
    }
}

fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0, |m: f64, (x, y)| m.max((x - y).abs()));
    diff / inf_norm(b)
}

/// Accept Clarabel only if it reports Solved, or AlmostSolved with its own residuals and
/// gap ≤ 1e-10 (never silently loosened).
fn accept(r: &ClarabelResult, tol: f64) {
    println!(
        "clarabel tol {tol:e}: status {:?}, {} iterations, res_primal {:e}, res_dual {:e}, gap_abs {:e}, gap_rel {:e}",
        r.status, r.iterations, r.res_primal, r.res_dual, r.gap_abs, r.gap_rel
    );
    match r.status {
        SolverStatus::Solved => {}
        SolverStatus::AlmostSolved => {
            let limit = tol.max(1e-10);
            assert!(
                r.res_primal <= limit && r.res_dual <= limit && r.gap_abs.min(r.gap_rel) <= limit,
                "Clarabel AlmostSolved with residuals above {limit:e}"
            );
        }
        s => panic!("Clarabel did not solve {FILE}: {s:?}"),
    }
}

#[test]
fn ssn_matches_clarabel_and_satisfies_kkt() {
    let p = load();
    let n = p.n();
    let d = p.cone_dimension;
    let eta = eta_of(&p);

    // --- ssn, default settings, from σ = 0
    let system = reduced_system_from_siconos::<3>(&p).unwrap();
    let mut solver = Solver::new(system, Settings::default()).unwrap();
    let mut sigma = vec![0.0; n];
    let report = solver
        .solve(&mut sigma)
        .unwrap_or_else(|e| panic!("ssn failed on {FILE}: {e}"));
    println!(
        "ssn: {} iterations, residual {:e}, {:.3} ms",
        report.iterations,
        report.residual,
        report.seconds * 1e3
    );

    // --- Clarabel at 1e-12 (asserted) and at its 1e-8 defaults (reported)
    let tight = solve_clarabel(&p, 1e-12);
    accept(&tight, 1e-12);
    let rel12 = rel_diff(&sigma, &tight.x);
    let loose = solve_clarabel(&p, 1e-8);
    accept(&loose, 1e-8);
    let rel8 = rel_diff(&sigma, &loose.x);
    println!("‖σ_ssn − σ_clarabel‖∞ / ‖σ_clarabel‖∞: {rel12:e} (tol 1e-12), {rel8:e} (tol 1e-8)");
    assert!(
        rel12 <= 1e-6,
        "ssn and Clarabel (1e-12) differ by {rel12:e} relative"
    );

    // --- independent KKT check of the ssn solution: z = Wσ + q from the file's entries
    let mut z = p.q.clone();
    // magnitude of the terms summed into z_k: the scale rounding and residuals act on
    let mut zmag: Vec<f64> = p.q.iter().map(|v| v.abs()).collect();
    for i in 0..n {
        for (j, sj) in sigma.iter().enumerate().take(n) {
            let w = p.matrix_entry(i, j);
            z[i] += w * sj;
            zmag[i] += (w * sj).abs();
        }
    }
    let s_sigma = inf_norm(&sigma);
    let s_z = inf_norm(&zmag);
    println!(
        "scales: ‖σ‖∞ = {s_sigma:e}, ‖|W||σ| + |q|‖∞ = {s_z:e}, ‖z‖∞ = {:e}",
        inf_norm(&z)
    );
    assert!(
        s_sigma > 0.0,
        "trivial solution σ = 0 would not test anything"
    );

    // Tolerances, relative to the scales ‖σ‖∞ and s_z = ‖|W||σ| + |q|‖∞:
    //   primal  ‖σ_T‖ − ησ_0 ≤ (√2 + η_max)·1e-12·‖σ‖∞: the ssn stops at
    //           ‖F‖∞ ≤ 1e-12·max(1, ‖σ‖∞) and σ − F = P_K(·) ∈ K, so a perturbation of at
    //           most ‖F‖∞ per component moves ‖σ_T‖ − ησ_0 by at most (√2 + η)‖F‖∞ (d = 3);
    //   dual    η‖z_T‖ − z_0 ≤ 1e-11·s_z;
    //   complementarity |σ_i·z_i| ≤ 1e-11·‖σ‖∞·s_z per cone.
    let eta_max = eta.iter().fold(0.0f64, |m, v| m.max(*v));
    let tol_primal = (2f64.sqrt() + eta_max) * 1e-12 * s_sigma;
    let tol_dual = 1e-11 * s_z;
    let tol_comp = 1e-11 * s_sigma * s_z;
    let (mut worst_primal, mut worst_dual, mut worst_comp) = (0.0f64, 0.0f64, 0.0f64);
    // the opposite sign (−z ∈ K*: η‖z_T‖ + z_0 ≤ 0), to show the dual check discriminates
    let mut worst_wrong_sign = 0.0f64;
    let mut plastic = 0;
    for c in 0..p.n_cones {
        let s = &sigma[d * c..d * c + d];
        let zc = &z[d * c..d * c + d];
        let e = eta[c];
        let s_t = s[1..].iter().map(|v| v * v).sum::<f64>().sqrt();
        let z_t = zc[1..].iter().map(|v| v * v).sum::<f64>().sqrt();
        // σ_i ∈ K_i: ‖σ_T‖ − η σ_0 ≤ 0
        worst_primal = worst_primal.max(s_t - e * s[0]);
        // z_i ∈ K_i*: η‖z_T‖ − z_0 ≤ 0   (‖z_T‖ ≤ z_0/η, multiplied by η > 0)
        worst_dual = worst_dual.max(e * z_t - zc[0]);
        worst_wrong_sign = worst_wrong_sign.max(e * z_t + zc[0]);
        // σ_i · z_i = 0
        let dot: f64 = s.iter().zip(zc).map(|(a, b)| a * b).sum();
        worst_comp = worst_comp.max(dot.abs());
        let z_norm = zc.iter().map(|v| v * v).sum::<f64>().sqrt();
        if z_norm > 1e-6 * s_z {
            plastic += 1;
        }
    }
    println!(
        "KKT: max(‖σ_T‖ − ησ_0) = {worst_primal:e} (tol {tol_primal:e}), \
         max(η‖z_T‖ − z_0) = {worst_dual:e} (tol {tol_dual:e}), \
         max|σ_i·z_i| = {worst_comp:e} (tol {tol_comp:e}), \
         {plastic}/{} cones with ‖z_i‖ > 1e-6·s_z; opposite sign would give {worst_wrong_sign:e}",
        p.n_cones
    );
    assert!(
        worst_wrong_sign > 1e3 * tol_dual,
        "the dual-cone check would not tell z ∈ K* from −z ∈ K*"
    );
    assert!(
        plastic > 0,
        "no plastic cone: the dual-cone sign would be untested"
    );
    assert!(
        worst_primal <= tol_primal,
        "σ outside K by {worst_primal:e}"
    );
    assert!(worst_dual <= tol_dual, "z outside K* by {worst_dual:e}");
    assert!(
        worst_comp <= tol_comp,
        "complementarity violated by {worst_comp:e}"
    );
}
