use nalgebra::{SMatrix, SVector};

use crate::projection::{split, unit_axis};
use crate::{ConeError, Projection, Projector, Region};

/// The von Mises cylinder `{x : ‖x_t‖ ≤ R}` around the axis `n` through the origin: the
/// Drucker-Prager cone at φ = 0, which has no apex and no polar region.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VonMisesCylinder<const D: usize> {
    axis: SVector<f64, D>,
    radius: f64,
}

impl<const D: usize> VonMisesCylinder<D> {
    /// `axis` is normalised here; `radius` must be finite and non-negative.
    pub fn try_new(axis: SVector<f64, D>, radius: f64) -> Result<Self, ConeError> {
        if !(radius.is_finite() && radius >= 0.0) {
            return Err(ConeError::InvalidParameter {
                name: "radius",
                value: radius,
                expected: "a finite number >= 0",
            });
        }
        Ok(Self {
            axis: unit_axis(axis)?,
            radius,
        })
    }

    pub fn axis(&self) -> &SVector<f64, D> {
        &self.axis
    }

    pub fn radius(&self) -> f64 {
        self.radius
    }
}

impl<const D: usize> Projector<D> for VonMisesCylinder<D> {
    #[inline]
    fn project(&self, x: &SVector<f64, D>) -> Projection<D> {
        self.project_with_jacobian_opt::<false>(x).0
    }

    #[inline]
    fn project_with_jacobian(&self, x: &SVector<f64, D>) -> (Projection<D>, SMatrix<f64, D, D>) {
        self.project_with_jacobian_opt::<true>(x)
    }

    fn contains(&self, x: &SVector<f64, D>, tol: f64) -> bool {
        let (_, xt) = split(x, &self.axis);
        xt.norm() <= self.radius + tol * x.norm().max(self.radius)
    }
}

impl<const D: usize> VonMisesCylinder<D> {
    #[inline]
    fn project_with_jacobian_opt<const JAC: bool>(
        &self,
        x: &SVector<f64, D>,
    ) -> (Projection<D>, SMatrix<f64, D, D>) {
        let (xn, xt) = split(x, &self.axis);
        let r = xt.norm();
        let n = &self.axis;
        // A zero radius makes the set the axis line: even at r = 0 the map is x ↦ n nᵀ x.
        if r <= self.radius && self.radius > 0.0 {
            let jac = if JAC {
                SMatrix::identity()
            } else {
                SMatrix::zeros()
            };
            return (
                Projection {
                    point: *x,
                    region: Region::Interior,
                },
                jac,
            );
        }
        let nn = n * n.transpose();
        if r == 0.0 {
            let jac = if JAC { nn } else { SMatrix::zeros() };
            return (
                Projection {
                    point: n * xn,
                    region: Region::Boundary,
                },
                jac,
            );
        }
        let u = xt / r;
        let point = n * xn + u * self.radius;
        let jac = if JAC {
            nn + (SMatrix::<f64, D, D>::identity() - nn - u * u.transpose()) * (self.radius / r)
        } else {
            SMatrix::zeros()
        };
        (
            Projection {
                point,
                region: Region::Boundary,
            },
            jac,
        )
    }
}
