//! Plane strain or axisymmetry: what the 2D mesh stands for (`docs/axisymmetry.md`).
//!
//! - Plane strain: a slice of unit thickness; integrals are per metre of thickness.
//! - Axisymmetric: `x` is the radius `r ≥ 0`, `y` the axis; the mesh is a meridian section
//!   and integrals are per radian of circumference, `∫ (·) r dr dy`. The out-of-plane
//!   strain (Mandel component 3, `zz` in plane strain) is the hoop strain `ε_θθ = u_r / r`.
//!   A whole-circumference force is `2π` times the per-radian one.
//!
//! Nodes on the axis (`r = 0`) must have `u_r = 0` (a radial motion there would tear a hole
//! or overlap the body): [`Geometry::axis_nodes`] lists them and the assembly refuses a
//! free radial dof on the axis. Gauss points of the rules used lie strictly inside the
//! triangles, so `r > 0` at each of them and `u_r / r` is never `0/0`; the assembly checks
//! it (a curved element bulging across the axis is refused).
use crate::error::MeshError;
use crate::mesh::Mesh;

/// What the plane of the mesh represents.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Geometry {
    /// Plane strain, unit thickness (`ε_zz = 0`).
    #[default]
    PlaneStrain,
    /// Axisymmetric about the `y` axis, `x = r ≥ 0`, quantities per radian.
    Axisymmetric,
    /// A 3D body on a tetrahedral mesh (`docs/3d.md`), quantities per body.
    ThreeDimensional,
}

/// Nodes closer to the axis than this fraction of the mesh size are on it (Gmsh writes
/// `-1e-17` for a point it placed at 0).
const AXIS_TOLERANCE: f64 = 1e-12;

impl Geometry {
    /// The weight of an integrand at `x`: `1` (per metre of thickness, or in 3D) or
    /// `r = x[0]` (per radian). Every volume, mass, load and stiffness integral carries it.
    pub fn weight(self, x: impl AsRef<[f64]>) -> f64 {
        match self {
            Geometry::PlaneStrain | Geometry::ThreeDimensional => 1.0,
            Geometry::Axisymmetric => x.as_ref()[0],
        }
    }

    /// From the integrals' unit (per metre, per radian) to the whole body's: `1` or `2π`.
    pub fn whole_body_factor(self) -> f64 {
        match self {
            Geometry::PlaneStrain | Geometry::ThreeDimensional => 1.0,
            Geometry::Axisymmetric => std::f64::consts::TAU,
        }
    }

    /// Refuses an axisymmetric mesh with a node at `r < 0` (beyond the axis tolerance).
    pub fn check_mesh(self, mesh: &Mesh) -> Result<(), MeshError> {
        if self != Geometry::Axisymmetric {
            return Ok(());
        }
        let tol = axis_tolerance(mesh);
        match mesh
            .nodes
            .iter()
            .position(|p| !(p[0].is_finite() && p[0] >= -tol))
        {
            Some(n) => Err(MeshError::invalid(
                "mesh",
                format!(
                    "node {n} lies at x = r = {:e} m: an axisymmetric mesh must lie in r ≥ 0 \
                     (x is the radius, y the axis)",
                    mesh.nodes[n][0]
                ),
            )),
            None => Ok(()),
        }
    }

    /// The nodes on the axis `r = 0` (within `1e-12 ×` the mesh size), whose radial
    /// velocity is 0; none in plane strain.
    pub fn axis_nodes(self, mesh: &Mesh) -> Vec<usize> {
        if self != Geometry::Axisymmetric {
            return Vec::new();
        }
        let tol = axis_tolerance(mesh);
        (0..mesh.nodes.len())
            .filter(|&n| mesh.nodes[n][0].abs() <= tol)
            .collect()
    }
}

/// `AXIS_TOLERANCE ×` the larger side of the mesh's bounding box.
fn axis_tolerance(mesh: &Mesh) -> f64 {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in &mesh.nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    if size.is_finite() {
        AXIS_TOLERANCE * size
    } else {
        0.0
    }
}
