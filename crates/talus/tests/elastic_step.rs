//! One implicit step of an elastic body (eqs. 15–16 with no plastic flow) equals the direct
//! velocity solve `(M + h² K) v = M vₙ + h (f − Bᵀσₙ) − h² K_fD v_D` (paper notes §4), with
//! `K = Bᵀ S⁻¹ B` assembled here independently of the solver's Schur complement.
use nalgebra::{DMatrix, DVector, SMatrix};
use talus::scene::Scene;
use talus::simulation::{Model, State, Stepper};
use talus_ssn::Settings;

const SCENE: &str = r#"
gravity = [0.0, -9.81]
[mesh.rectangle]
x = [0.0, 1.0]
y = [0.0, 0.5]
cells = [4, 3]
order = "P2"
[material]
young_modulus = 5.0e7
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 1.0e12          # elastic: the cone is far away
cone_fit = "plane_strain"
density = 1800.0
[[boundary]]
nodes = "bottom"
fix = "xy"
[[boundary]]
name = "plate"
nodes = "top"
fix = "y"
velocity = [0.0, -2.0e-3]
[time]
step = 0.02
steps = 1
"#;

fn csc_dense(m: &talus_ssn::faer::sparse::SparseColMat<usize, f64>) -> DMatrix<f64> {
    let mut d = DMatrix::zeros(m.nrows(), m.ncols());
    let (cp, ri, v) = (m.symbolic().col_ptr(), m.symbolic().row_idx(), m.val());
    for j in 0..m.ncols() {
        for k in cp[j]..cp[j + 1] {
            d[(ri[k], j)] += v[k];
        }
    }
    d
}

#[test]
fn elastic_step_equals_direct_velocity_solve() {
    let scene = Scene::parse(SCENE, None).unwrap();
    let model = Model::from_scene(&scene).unwrap();
    let asm = &model.assembly;
    let (n_f, n_p) = (asm.dofs().n_free(), asm.dofs().n_prescribed());
    let mut state = State::at_rest(asm.n_points(), n_f, n_p, model.mesh.nodes.len());
    // A non-trivial start: some stress and velocity already.
    for (k, s) in state.sigma.iter_mut().enumerate() {
        *s = -1.0e4 * (1.0 + (k % 7) as f64);
    }
    for (k, v) in state.velocity_free.iter_mut().enumerate() {
        *v = 1.0e-4 * ((k % 5) as f64 - 2.0);
    }
    let sigma_n = state.sigma.clone();
    let v_n = state.velocity_free.clone();
    let h = scene.spec.time.step;

    let mut stepper = Stepper::new(&model, Settings::default(), 0);
    let record = stepper
        .advance(&mut state, h)
        .expect("elastic step converges");

    // Independent assembly: S⁻¹ blocks = C₀ / V_p.
    let bf = csc_dense(&asm.b_free);
    let bp = csc_dense(&asm.b_prescribed);
    let c0: SMatrix<f64, 4, 4> = model.compliance.try_inverse().unwrap();
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
    let k_ff = bf.transpose() * &s_inv * &bf;
    let k_fp = bf.transpose() * &s_inv * &bp;
    let v_d = DVector::from_vec(model.prescribed_velocity.clone());
    let f = DVector::from_vec(model.force_free.clone());
    let sig_n = DVector::from_vec(sigma_n);
    let lhs = &m + &k_ff * (h * h);
    let rhs = &m * DVector::from_vec(v_n) + (f - bf.transpose() * &sig_n) * h
        - k_fp * v_d.clone() * (h * h);
    let v = lhs.lu().solve(&rhs).unwrap();
    let sigma = &sig_n + &s_inv * (&bf * &v + &bp * &v_d) * h;

    let dv = (DVector::from_vec(state.velocity_free.clone()) - &v).amax() / v.amax();
    let ds = (DVector::from_vec(state.sigma.clone()) - &sigma).amax() / sigma.amax();
    assert!(dv < 1e-9, "velocity differs by {dv:e} (relative)");
    assert!(ds < 1e-9, "stress differs by {ds:e} (relative)");
    assert!(
        record.max_newton_iterations <= 2,
        "an elastic step is one linear solve"
    );
    assert!(v.amax() > 1e-5, "the test must move something");
}
