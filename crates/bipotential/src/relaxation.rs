//! Duvaut–Lions relaxation of a point (`docs/derivations.md`, 'Duvaut–Lions relaxation'):
//! the stress may lie outside `K` by an overstress `σ − p = τ C ε̇ᵖ`, `p ∈ K` carrying the
//! rate-independent flow rule. Over a step of length `h`, with the solver's `z = −V Δεᵖ`
//! (`docs/derivations.md`, 'The reduced system') and the point's compliance block
//! `S_i = V S₀`, that is `σ − p = −N z` with `N = (τ/h) S_i⁻¹`.
use nalgebra::{SMatrix, SVector};

use crate::MaterialError;

/// The overstress modulus `N = (τ/h) S_i⁻¹` of one point (Pa per unit of `z`), for an
/// isotropic `S₀`: `N = a (I − e eᵀ) + b e eᵀ` with `a = 2G τ/(h V)`, `b = 3K τ/(h V)`
/// (`e` the unit hydrostatic axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relaxation {
    deviatoric: f64,
    volumetric: f64,
}

fn positive(name: &'static str, value: f64, expected: &'static str) -> Result<f64, MaterialError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(MaterialError::InvalidParameter {
            name,
            value,
            expected,
        })
    }
}

/// The relaxation time `τ` (s) as a material takes it: finite and > 0.
pub(crate) fn check_relaxation_time(tau: f64) -> Result<f64, MaterialError> {
    positive("relaxation_time", tau, "a finite τ > 0 (s)")
}

/// `e = (1, 1, 1, 0, …)/√3` (`mandel::hydrostatic_axis`, without its compile-time check of
/// `D`: a rule of any dimension may carry a relaxation type, only Mandel ones get one).
fn hydrostatic_axis<const D: usize>() -> SVector<f64, D> {
    SVector::from_fn(|i, _| if i < 3 { 1.0 / 3f64.sqrt() } else { 0.0 })
}

impl Relaxation {
    /// `N = a (I − e eᵀ) + b e eᵀ` from its two moduli, each finite and > 0.
    fn try_new(deviatoric: f64, volumetric: f64) -> Result<Self, MaterialError> {
        Ok(Self {
            deviatoric: positive("relaxation.deviatoric", deviatoric, "a finite value > 0")?,
            volumetric: positive("relaxation.volumetric", volumetric, "a finite value > 0")?,
        })
    }

    /// `N = (τ/h) (V S₀)⁻¹` for the isotropic `S₀` of `(E, ν)`: `2G = E/(1+ν)`,
    /// `3K = E/(1−2ν)`. `τ` (s), `h` (s) and `V` (the point's volume, as in its block
    /// `S_i`) finite and > 0.
    pub fn duvaut_lions(
        relaxation_time: f64,
        h: f64,
        volume: f64,
        young_modulus: f64,
        poisson_ratio: f64,
    ) -> Result<Self, MaterialError> {
        let tau = check_relaxation_time(relaxation_time)?;
        let h = positive("h", h, "a finite step > 0 (s)")?;
        let volume = positive("volume", volume, "a finite point volume > 0")?;
        let s = tau / (h * volume);
        Self::try_new(
            s * young_modulus / (1.0 + poisson_ratio),
            s * young_modulus / (1.0 - 2.0 * poisson_ratio),
        )
    }

    /// `a = 2G τ/(h V)`.
    pub fn deviatoric(&self) -> f64 {
        self.deviatoric
    }

    /// `b = 3K τ/(h V)`.
    pub fn volumetric(&self) -> f64 {
        self.volumetric
    }

    /// `N z = a z + (b − a)(e·z) e`.
    #[inline]
    pub fn apply<const D: usize>(&self, z: &SVector<f64, D>) -> SVector<f64, D> {
        let e = hydrostatic_axis::<D>();
        z * self.deviatoric + e * ((self.volumetric - self.deviatoric) * e.dot(z))
    }

    /// `N` as a matrix.
    pub fn matrix<const D: usize>(&self) -> SMatrix<f64, D, D> {
        let e = hydrostatic_axis::<D>();
        SMatrix::<f64, D, D>::identity() * self.deviatoric
            + e * e.transpose() * (self.volumetric - self.deviatoric)
    }
}
