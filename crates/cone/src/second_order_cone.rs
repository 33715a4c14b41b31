use nalgebra::{SMatrix, SVector};

use crate::projection::{split, unit_axis};
use crate::{ConeError, Projection, Projector, Region};

/// The translated second-order cone `apex + {x : ‖x_t‖ ≤ η x_n}` (half-opening `atan η`).
///
/// For Drucker-Prager in Mandel notation (tension positive): `n = −e`,
/// `apex = √3 (c / tan φ) e` and `η = k_d tan φ / √3`, with `e = (1,1,1,0,…)/√3`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SecondOrderCone<const D: usize> {
    axis: SVector<f64, D>,
    apex: SVector<f64, D>,
    eta: f64,
}

impl<const D: usize> SecondOrderCone<D> {
    /// `axis` is normalised here; `eta` must be finite and positive, `apex` finite.
    pub fn try_new(
        axis: SVector<f64, D>,
        apex: SVector<f64, D>,
        eta: f64,
    ) -> Result<Self, ConeError> {
        if !(eta.is_finite() && eta > 0.0) {
            return Err(ConeError::InvalidParameter {
                name: "eta",
                value: eta,
                expected: "a finite number > 0",
            });
        }
        if let Some(bad) = apex.iter().find(|v| !v.is_finite()) {
            return Err(ConeError::InvalidParameter {
                name: "apex component",
                value: *bad,
                expected: "a finite number",
            });
        }
        Ok(Self {
            axis: unit_axis(axis)?,
            apex,
            eta,
        })
    }

    pub fn axis(&self) -> &SVector<f64, D> {
        &self.axis
    }

    pub fn apex(&self) -> &SVector<f64, D> {
        &self.apex
    }

    pub fn eta(&self) -> f64 {
        self.eta
    }

    /// The region and, when outside the cone and off the polar cone, the pieces of eq. 23:
    /// `(x_n, x_t, ‖x_t‖)` relative to the apex.
    #[inline]
    fn classify(&self, x: &SVector<f64, D>) -> (Region, f64, SVector<f64, D>, f64) {
        let (xn, xt) = split(&(x - self.apex), &self.axis);
        let r = xt.norm();
        let region = if r <= self.eta * xn {
            Region::Interior
        } else if self.eta * r <= -xn {
            Region::Polar
        } else {
            Region::Boundary
        };
        (region, xn, xt, r)
    }
}

impl<const D: usize> Projector<D> for SecondOrderCone<D> {
    #[inline]
    fn project(&self, x: &SVector<f64, D>) -> Projection<D> {
        let (region, xn, xt, r) = self.classify(x);
        let point = match region {
            Region::Interior => *x,
            Region::Polar => self.apex,
            // eq. 23, middle case, written as (x_n + η r)/(1 + η²) · (n + η x_t / r).
            Region::Boundary => {
                let eta = self.eta;
                let scale = (xn + eta * r) / (1.0 + eta * eta);
                self.apex + (self.axis + xt * (eta / r)) * scale
            }
        };
        Projection { point, region }
    }

    #[inline]
    fn project_with_jacobian(&self, x: &SVector<f64, D>) -> (Projection<D>, SMatrix<f64, D, D>) {
        let (region, xn, xt, r) = self.classify(x);
        match region {
            Region::Interior => (Projection { point: *x, region }, SMatrix::identity()),
            Region::Polar => (
                Projection {
                    point: self.apex,
                    region,
                },
                SMatrix::zeros(),
            ),
            Region::Boundary => {
                // eq. 24 regrouped: J = w wᵀ/(1+η²) + η s/r (I − n nᵀ − u uᵀ),
                // u = x_t/r, w = n + η u, s = (x_n + η r)/(1+η²) > 0 off the polar cone.
                let eta = self.eta;
                let u = xt / r;
                let w = self.axis + u * eta;
                let inv = 1.0 / (1.0 + eta * eta);
                let s = (xn + eta * r) * inv;
                let n = &self.axis;
                let transverse =
                    SMatrix::<f64, D, D>::identity() - n * n.transpose() - u * u.transpose();
                let jac = w * w.transpose() * inv + transverse * (eta * s / r);
                (
                    Projection {
                        point: self.apex + w * s,
                        region,
                    },
                    jac,
                )
            }
        }
    }

    fn contains(&self, x: &SVector<f64, D>, tol: f64) -> bool {
        let (xn, xt) = split(&(x - self.apex), &self.axis);
        let scale = x.norm().max(self.apex.norm()).max(f64::MIN_POSITIVE);
        xt.norm() <= self.eta * xn + tol * scale
    }
}
