//! Mandel-vector helpers (tension positive): the dot product of two Mandel vectors is the
//! double contraction of the tensors, so projections need no metric weights.
use nalgebra::{SMatrix, SVector};

/// Rejects at compile time stress spaces other than plane strain (4) and 3D (6).
pub(crate) const fn assert_mandel_dimension<const D: usize>() {
    assert!(
        D == 4 || D == 6,
        "Mandel stress vectors have 4 (plane strain) or 6 (3D) components"
    );
}

/// `m = (1, 1, 1, 0, …)`: the identity tensor.
pub fn identity<const D: usize>() -> SVector<f64, D> {
    const { assert_mandel_dimension::<D>() };
    SVector::from_fn(|i, _| if i < 3 { 1.0 } else { 0.0 })
}

/// `e = m / √3`: the unit hydrostatic axis.
pub fn hydrostatic_axis<const D: usize>() -> SVector<f64, D> {
    identity::<D>() / 3f64.sqrt()
}

/// `tr τ`.
pub fn trace<const D: usize>(tau: &SVector<f64, D>) -> f64 {
    tau.dot(&identity::<D>())
}

/// `dev τ = τ − (tr τ / 3) m`.
pub fn deviator<const D: usize>(tau: &SVector<f64, D>) -> SVector<f64, D> {
    tau - identity::<D>() * (trace(tau) / 3.0)
}

/// Isotropic elastic compliance `S = ((1+ν) I − ν m mᵀ) / E` (strain per stress, 1/Pa).
pub fn isotropic_compliance<const D: usize>(
    young_modulus: f64,
    poisson_ratio: f64,
) -> SMatrix<f64, D, D> {
    let m = identity::<D>();
    (SMatrix::<f64, D, D>::identity() * (1.0 + poisson_ratio) - m * m.transpose() * poisson_ratio)
        / young_modulus
}
