//! Gauss points of a mesh: where stresses live. Each carries its volume
//! `V_p = w_p · det J(ξ_p) · 1 m` (plane strain, unit thickness) or `w_p · det J(ξ_p) · r_p`
//! (axisymmetric, per radian: `docs/axisymmetry.md`), which weights its row block of `B` and
//! its compliance block (`docs/derivations.md`, 'Volume weights'), and the shape functions
//! and physical gradients of its element's nodes.
use crate::element::map_point;
use crate::error::MeshError;
use crate::geometry::Geometry;
use crate::mesh::Mesh;
use crate::quadrature::stiffness_rule;

/// Per-point data, flat: point `p` owns entries `p·npe .. (p+1)·npe` of `nodes`, `shape`
/// and `gradients` (`npe` nodes per element).
#[derive(Debug, Clone)]
pub(crate) struct GaussData {
    pub geometry: Geometry,
    pub npe: usize,
    pub positions: Vec<[f64; 2]>,
    pub volumes: Vec<f64>,
    pub elements: Vec<usize>,
    pub nodes: Vec<usize>,
    pub shape: Vec<f64>,
    pub gradients: Vec<[f64; 2]>,
}

impl GaussData {
    /// Maps every stiffness quadrature point of every triangle (mesh already validated).
    /// Axisymmetric: refuses a point at `r ≤ 0` (the rules' points are interior, so only a
    /// curved element crossing the axis has one).
    pub fn new(mesh: &Mesh, geometry: Geometry) -> Result<Self, MeshError> {
        let rule = stiffness_rule(mesh.order);
        let npe = mesh.order.nodes_per_triangle();
        let n = mesh.triangles.len() * rule.points.len();
        let mut g = GaussData {
            geometry,
            npe,
            positions: Vec::with_capacity(n),
            volumes: Vec::with_capacity(n),
            elements: Vec::with_capacity(n),
            nodes: Vec::with_capacity(n * npe),
            shape: Vec::with_capacity(n * npe),
            gradients: Vec::with_capacity(n * npe),
        };
        for (e, tri) in mesh.triangles.iter().enumerate() {
            let coords = mesh.triangle_coordinates(e);
            for (xi, w) in rule.points.iter().zip(rule.weights) {
                let m = map_point(mesh.order, &coords, *xi).ok_or_else(|| {
                    MeshError::element(
                        format!("triangle {e}"),
                        format!("det J ≤ 0 at quadrature point {xi:?}"),
                    )
                })?;
                let weight = geometry.weight(m.position);
                if !(weight.is_finite() && weight > 0.0) {
                    return Err(MeshError::element(
                        format!("triangle {e}"),
                        format!(
                            "its Gauss point {xi:?} lies at r = {:e} m: an axisymmetric \
                             element must lie in r > 0 inside",
                            m.position[0]
                        ),
                    ));
                }
                g.positions.push(m.position);
                g.volumes.push(w * m.det_j * weight);
                g.elements.push(e);
                g.nodes.extend_from_slice(tri);
                g.shape.extend_from_slice(&m.shape);
                g.gradients.extend_from_slice(&m.gradients);
            }
        }
        Ok(g)
    }

    pub fn len(&self) -> usize {
        self.volumes.len()
    }

    /// `(node, N_a, ∂N_a/∂x)` of point `p`.
    pub fn point(&self, p: usize) -> impl Iterator<Item = (usize, f64, [f64; 2])> + '_ {
        let r = p * self.npe..(p + 1) * self.npe;
        self.nodes[r.clone()]
            .iter()
            .zip(&self.shape[r.clone()])
            .zip(&self.gradients[r])
            .map(|((&n, &s), &g)| (n, s, g))
    }
}
