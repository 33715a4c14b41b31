//! Elastic checks of the time stepper (no plastic flow: the cone is far away).
use nalgebra::{DMatrix, DVector, SMatrix};
use talus_ssn::faer::sparse::SparseColMat;
use talus_ssn::Settings;

use super::{CaseResult, Check};
use crate::model::fem::FromScene;
use crate::model::fem::{Model, State};
use crate::scene::Scene;
use talus_engine::{StepSettings, Stepper};

fn elastic_scene(order: &str, fix_all: bool, gravity: bool) -> String {
    let boundary = if fix_all {
        ["bottom", "top", "left", "right"]
            .iter()
            .map(|s| format!("[[boundary]]\nnodes = \"{s}\"\nfix = \"xy\"\n"))
            .collect::<String>()
    } else {
        "[[boundary]]\nnodes = \"bottom\"\nfix = \"xy\"\n[[boundary]]\nname = \"plate\"\nnodes = \"top\"\nfix = \"y\"\nvelocity = [0.0, -2.0e-3]\n".into()
    };
    format!(
        "{}[mesh.rectangle]\nx = [0.0, 1.0]\ny = [0.0, 0.5]\ncells = [5, 4]\norder = \"{order}\"\nfocus = [0.3, 0.1]\nratio = [1.3, 1.2]\n\
[material]\nyoung_modulus = 5.0e7\npoisson_ratio = 0.3\nfriction_angle = 30.0\ncohesion = 1.0e12\ncone_fit = \"plane_strain\"\ndensity = 1800.0\n\
{boundary}[time]\nstep = 0.02\nsteps = 1\n",
        if gravity { "gravity = [0.0, -9.81]\n" } else { "" }
    )
}

/// Patch test: a velocity field `v = G x` on a graded (irregular) mesh, imposed on the
/// boundary and started in the interior, is kept exactly by one implicit step, and every
/// Gauss point sees the uniform strain rate `sym G`.
pub fn elastic_patch_test() -> Vec<CaseResult> {
    let g = [[1.0e-3, 0.4e-3], [-0.7e-3, 0.2e-3]];
    ["P1", "P2"]
        .into_iter()
        .map(|order| {
            let computed = (|| {
                let scene = Scene::parse(&elastic_scene(order, true, false), None).ok()?;
                let mut model = Model::from_scene(&scene).ok()?;
                let affine = |x: [f64; 2], c: usize| g[c][0] * x[0] + g[c][1] * x[1];
                let dofs = model.assembly.dofs().clone();
                for (j, &(node, c)) in dofs.prescribed_dofs().iter().enumerate() {
                    model.prescribed_velocity[j] = affine(model.mesh.nodes[node], c);
                }
                let asm = &model.assembly;
                let mut state = State::at_rest(
                    asm.n_points(),
                    dofs.n_free(),
                    dofs.n_prescribed(),
                    model.mesh.nodes.len(),
                );
                state
                    .velocity_prescribed
                    .clone_from(&model.prescribed_velocity);
                for (node, x) in model.mesh.nodes.iter().enumerate() {
                    for c in 0..2 {
                        if let Some(j) = dofs.free(node, c) {
                            state.velocity_free[j] = affine(*x, c);
                        }
                    }
                }
                let mut stepper =
                    Stepper::new(&model, StepSettings::with_solver(Settings::default(), 0));
                stepper.advance(&mut state, scene.spec.time.step).ok()?;
                let rates = asm
                    .strain(&state.velocity_free, &state.velocity_prescribed)
                    .ok()?;
                let exact = [
                    g[0][0],
                    g[1][1],
                    0.0,
                    (g[0][1] + g[1][0]) / 2.0 * 2f64.sqrt(),
                ];
                let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                Some(
                    rates
                        .iter()
                        .flat_map(|r| (0..4).map(move |k| (r[k] - exact[k]).abs()))
                        .fold(0.0f64, f64::max)
                        / scale,
                )
            })()
            .unwrap_or(f64::NAN);
            CaseResult {
                case: format!("elastic_patch_test_{}", order.to_lowercase()),
                quantity: "max |ε̇ − sym G| / |sym G| over Gauss points".into(),
                reference: 0.0,
                computed,
                tolerance: 1e-10,
                check: Check::Absolute,
                seconds: 0.0,
                source: "uniform strain reproduced exactly (patch test)".into(),
            }
        })
        .collect()
}

pub(crate) fn dense(m: &SparseColMat<usize, f64>) -> DMatrix<f64> {
    let mut d = DMatrix::zeros(m.nrows(), m.ncols());
    let (cp, ri, v) = (m.symbolic().col_ptr(), m.symbolic().row_idx(), m.val());
    for j in 0..m.ncols() {
        for k in cp[j]..cp[j + 1] {
            d[(ri[k], j)] += v[k];
        }
    }
    d
}

/// One implicit elastic step equals `(M + h² K) v = M vₙ + h (f − Bᵀσₙ) − h² K_fD v_D`,
/// `K = Bᵀ S⁻¹ B` assembled densely here (`docs/derivations.md`, 'The reduced system').
pub fn elastic_step_identity() -> Vec<CaseResult> {
    let computed = (|| {
        let scene = Scene::parse(&elastic_scene("P2", false, true), None).ok()?;
        let model = Model::from_scene(&scene).ok()?;
        let asm = &model.assembly;
        let (n_f, n_p) = (asm.dofs().n_free(), asm.dofs().n_prescribed());
        let mut state = State::at_rest(asm.n_points(), n_f, n_p, model.mesh.nodes.len());
        for (k, s) in state.sigma.iter_mut().enumerate() {
            *s = -1.0e4 * (1.0 + (k % 7) as f64);
        }
        for (k, v) in state.velocity_free.iter_mut().enumerate() {
            *v = 1.0e-4 * ((k % 5) as f64 - 2.0);
        }
        let (sigma_n, v_n) = (state.sigma.clone(), state.velocity_free.clone());
        let h = scene.spec.time.step;
        Stepper::new(&model, StepSettings::with_solver(Settings::default(), 0))
            .advance(&mut state, h)
            .ok()?;

        let (bf, bp) = (dense(&asm.b_free), dense(&asm.b_prescribed));
        let c0: SMatrix<f64, 4, 4> = model.compliances[0].try_inverse()?;
        let n_s = 4 * asm.n_points();
        let mut s_inv = DMatrix::zeros(n_s, n_s);
        for (p, v) in asm.gauss_volumes.iter().enumerate() {
            for a in 0..4 {
                for b in 0..4 {
                    s_inv[(4 * p + a, 4 * p + b)] = c0[(a, b)] / v;
                }
            }
        }
        let m = DMatrix::from_diagonal(&DVector::from_vec(asm.lumped_mass_free.clone()));
        let v_d = DVector::from_vec(model.prescribed_velocity.clone());
        let lhs = &m + bf.transpose() * &s_inv * &bf * (h * h);
        let rhs = &m * DVector::from_vec(v_n)
            + (DVector::from_vec(model.force_free.clone())
                - bf.transpose() * DVector::from_vec(sigma_n))
                * h
            - bf.transpose() * &s_inv * &bp * v_d * (h * h);
        let v = lhs.lu().solve(&rhs)?;
        Some((DVector::from_vec(state.velocity_free.clone()) - &v).amax() / v.amax())
    })()
    .unwrap_or(f64::NAN);
    vec![CaseResult {
        case: "elastic_step_identity".into(),
        quantity: "‖v − v_direct‖∞ / ‖v_direct‖∞".into(),
        reference: 0.0,
        computed,
        tolerance: 1e-9,
        check: Check::Absolute,
        seconds: 0.0,
        source: "direct solve of (M + h²K) v = M vₙ + h (f − Bᵀσₙ) (docs/derivations.md, The reduced system)".into(),
    }]
}
