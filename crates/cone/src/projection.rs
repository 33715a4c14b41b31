use nalgebra::{SMatrix, SVector};

/// Where a point fell relative to the set it was projected on (eq. 23's three cases).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Region {
    /// Inside the set (boundary included): the projection is the identity.
    Interior,
    /// Outside, projected onto the smooth lateral surface.
    Boundary,
    /// In the polar cone translated to the apex: projected onto the apex.
    Polar,
}

/// The projection of one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection<const D: usize> {
    pub point: SVector<f64, D>,
    pub region: Region,
}

/// A closed convex set with an explicit Euclidean projection and Clarke Jacobian.
pub trait Projector<const D: usize> {
    /// `P(x)`, the closest point of the set to `x`.
    fn project(&self, x: &SVector<f64, D>) -> Projection<D>;

    /// `P(x)` and one element of the Clarke Jacobian `∂P(x)` (eq. 24). On a boundary
    /// between regions it is the Jacobian of the region reported, a limit of neighbouring
    /// smooth Jacobians and so an element of the Clarke hull.
    fn project_with_jacobian(&self, x: &SVector<f64, D>) -> (Projection<D>, SMatrix<f64, D, D>);

    /// Whether `x` lies in the set up to `tol` times the scale of `x`.
    fn contains(&self, x: &SVector<f64, D>, tol: f64) -> bool;
}

/// Splits `x` into its axial part `x·n` and its transverse part `x − (x·n) n`.
#[inline]
pub(crate) fn split<const D: usize>(
    x: &SVector<f64, D>,
    axis: &SVector<f64, D>,
) -> (f64, SVector<f64, D>) {
    let xn = x.dot(axis);
    (xn, x - axis * xn)
}

pub(crate) fn unit_axis<const D: usize>(
    axis: SVector<f64, D>,
) -> Result<SVector<f64, D>, crate::ConeError> {
    let norm = axis.norm();
    if !norm.is_finite() || norm == 0.0 {
        return Err(crate::ConeError::InvalidParameter {
            name: "axis norm",
            value: norm,
            expected: "a finite, non-zero axis",
        });
    }
    Ok(axis / norm)
}
