//! Shared by the flow-rule tests: a one-point implicit return by the natural map, the
//! natural map's Jacobian blocks by central differences.
use talus_bipotential::{DruckerPrager, FlowRule, NaturalMapLinearization, SMatrix, SVector};

/// Solves `F(σ) = σ − P_K(σ − ρ y(z)) = 0` with `z = S (σ − σ_trial)` (one material point,
/// `W = S`, `q = −S σ_trial`) by semi-smooth Newton, as `talus-ssn` does globally.
/// Returns `(σ, z)`; `−z` is the plastic strain increment.
pub fn return_map<const D: usize>(
    material: &DruckerPrager,
    rule: &FlowRule<D>,
    sigma_trial: &SVector<f64, D>,
) -> (SVector<f64, D>, SVector<f64, D>) {
    let s: SMatrix<f64, D, D> = material.compliance();
    let rho = 2.0 * material.shear_modulus();
    let mut sigma = *sigma_trial;
    for _ in 0..100 {
        let z = s * (sigma - sigma_trial);
        let lin = rule.natural_map_linearization(&sigma, &z, rho);
        let scale = sigma_trial.norm().max(material.parameters().cohesion);
        if lin.residual.amax() <= 1e-15 * scale {
            return (sigma, z);
        }
        let jac =
            SMatrix::<f64, D, D>::identity() - lin.projection_jacobian + lin.coupling * s * rho;
        // Dynamic LU: nalgebra's fixed-size LU needs typenum bounds on a generic D.
        let step = nalgebra::DMatrix::from_column_slice(D, D, jac.as_slice())
            .lu()
            .solve(&nalgebra::DVector::from_column_slice(
                (-lin.residual).as_slice(),
            ))
            .expect("local Jacobian is regular");
        sigma += SVector::<f64, D>::from_column_slice(step.as_slice());
    }
    let z = s * (sigma - sigma_trial);
    let res = rule.natural_map_residual(&sigma, &z, rho).amax();
    assert!(
        res <= 1e-10 * sigma_trial.norm(),
        "local return did not converge: {res:e}"
    );
    (sigma, z)
}

/// `(∂F/∂σ, ∂F/∂z)` of the natural-map residual `F(σ, z)` at `(σ, z, ρ)` by central
/// differences of steps `h_s` (in σ) and `h_z` (in z), column by column.
pub fn central_differences<const D: usize>(
    rule: &FlowRule<D>,
    sigma: SVector<f64, D>,
    z: SVector<f64, D>,
    rho: f64,
    h_s: f64,
    h_z: f64,
) -> (SMatrix<f64, D, D>, SMatrix<f64, D, D>) {
    let mut d_sigma = SMatrix::<f64, D, D>::zeros();
    let mut d_z = SMatrix::<f64, D, D>::zeros();
    for j in 0..D {
        let mut e = SVector::<f64, D>::zeros();
        e[j] = 1.0;
        let fp = rule.natural_map_residual(&(sigma + e * h_s), &z, rho);
        let fm = rule.natural_map_residual(&(sigma - e * h_s), &z, rho);
        d_sigma.set_column(j, &((fp - fm) / (2.0 * h_s)));
        let fp = rule.natural_map_residual(&sigma, &(z + e * h_z), rho);
        let fm = rule.natural_map_residual(&sigma, &(z - e * h_z), rho);
        d_z.set_column(j, &((fp - fm) / (2.0 * h_z)));
    }
    (d_sigma, d_z)
}

/// The natural map's blocks `∂F/∂σ = I − D` and `∂F/∂z = ρ G` (eq. 25) against
/// [`central_differences`] of steps `h_s`, `h_z`: asserts the σ block (dimensionless) to
/// 1e-6 and returns `(linearization, ∂F/∂z by differences, ρ G)` for the caller's z check,
/// whose scale depends on the rule.
pub fn check_sigma_block<const D: usize>(
    rule: &FlowRule<D>,
    sigma: SVector<f64, D>,
    z: SVector<f64, D>,
    rho: f64,
    h_s: f64,
    h_z: f64,
) -> (
    NaturalMapLinearization<D>,
    SMatrix<f64, D, D>,
    SMatrix<f64, D, D>,
) {
    let lin = rule.natural_map_linearization(&sigma, &z, rho);
    let (d_sigma, d_z) = central_differences(rule, sigma, z, rho, h_s, h_z);
    let expected_sigma = SMatrix::<f64, D, D>::identity() - lin.projection_jacobian;
    assert!(
        (d_sigma - expected_sigma).amax() <= 1e-6,
        "dF/dσ ({:?}):\n{d_sigma}\nvs\n{expected_sigma}",
        lin.region
    );
    let expected_z = lin.coupling * rho;
    (lin, d_z, expected_z)
}
