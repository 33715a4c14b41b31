//! The associative Siconos problem as Clarabel's QP
//! `min ½σᵀWσ + qᵀσ, Aσ + s = 0, s ∈ Π SOC(3)`, `A_i = −diag(η_i, 1, 1)`, so that
//! `s_i = (η_i σ_i0, σ_i1, σ_i2) ∈ SOC ⇔ ‖σ_iT‖ ≤ η_i σ_i0`. Shared by the agreement test
//! and the benchmark (included with `#[path]`).
use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSettingsBuilder, SupportedConeT};
use talus_ssn::siconos::{SiconosModel, SiconosProblem};

/// The QP data of an associative Drucker-Prager problem in Clarabel's form.
pub struct Qp {
    pub p: CscMatrix<f64>,
    pub q: Vec<f64>,
    pub a: CscMatrix<f64>,
    pub b: Vec<f64>,
    pub cones: Vec<SupportedConeT<f64>>,
}

pub fn qp(p: &SiconosProblem) -> Qp {
    let n = p.n();
    let d = p.cone_dimension;
    let eta = match &p.model {
        SiconosModel::DruckerPrager { eta, theta } => {
            assert!(
                theta.iter().all(|&t| t == 0.0),
                "associative problem expected"
            );
            eta.clone()
        }
        other => panic!("Drucker-Prager expected, found {other:?}"),
    };
    // upper triangle of the symmetric part of W, column by column
    let mut colptr = vec![0usize];
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    for j in 0..n {
        for i in 0..=j {
            let v = 0.5 * (p.matrix_entry(i, j) + p.matrix_entry(j, i));
            if v != 0.0 {
                rowval.push(i);
                nzval.push(v);
            }
        }
        colptr.push(rowval.len());
    }
    // A_i = −diag(η_i, 1, 1), b = 0: s_i = (η_i σ_i0, σ_i1, σ_i2)
    let a_diag: Vec<f64> = (0..n)
        .map(|k| if k % d == 0 { -eta[k / d] } else { -1.0 })
        .collect();
    Qp {
        p: CscMatrix::new(n, n, colptr, rowval, nzval),
        q: p.q.clone(),
        a: CscMatrix::new(n, n, (0..=n).collect(), (0..n).collect(), a_diag),
        b: vec![0.0; n],
        cones: vec![SupportedConeT::SecondOrderConeT(d); p.n_cones],
    }
}

/// Clarabel's defaults (1e-8) for `None`; gap and feasibility tolerances `t` otherwise.
pub fn clarabel_settings(tol: Option<f64>) -> DefaultSettings<f64> {
    let mut b = DefaultSettingsBuilder::default();
    b.verbose(false);
    if let Some(t) = tol {
        b.tol_gap_abs(t)
            .tol_gap_rel(t)
            .tol_feas(t)
            .tol_ktratio(1e-10)
            .max_iter(200);
    }
    b.build().unwrap()
}
