//! The objective stress update: a particle's stress turns with its spin over the step.

/// `R σ Rᵀ` for a rotation by `angle` in the xy plane (Mandel, σzz unchanged).
pub(crate) fn rotate(t: [f64; 4], angle: f64) -> [f64; 4] {
    let (s, c) = angle.sin_cos();
    let sxy = t[3] * std::f64::consts::FRAC_1_SQRT_2;
    let xx = c * c * t[0] - 2.0 * s * c * sxy + s * s * t[1];
    let yy = s * s * t[0] + 2.0 * s * c * sxy + c * c * t[1];
    let xy = s * c * (t[0] - t[1]) + (c * c - s * s) * sxy;
    [xx, yy, t[2], std::f64::consts::SQRT_2 * xy]
}
