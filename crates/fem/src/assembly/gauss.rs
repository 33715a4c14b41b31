//! Gauss points of a mesh: where stresses live. Each carries its volume
//! `V_p = w_p · det J(ξ_p) · 1 m` (plane strain, unit thickness), `w_p · det J(ξ_p) · r_p`
//! (axisymmetric, per radian: `docs/axisymmetry.md`) or `w_p · det J(ξ_p)` (3D), which
//! weights its row block of `B` and its compliance block (`docs/derivations.md`, 'Volume
//! weights'), and the shape functions and physical gradients of its element's nodes.
use crate::dimension::ElementMesh;
use crate::error::MeshError;
use crate::geometry::Geometry;

/// Per-point data, flat: point `p` owns entries `p·npe .. (p+1)·npe` of `nodes`, `shape`
/// and `gradients` (`npe` nodes per element). Positions and gradients carry three
/// coordinates, the third 0 in 2D.
#[derive(Debug, Clone)]
pub(crate) struct GaussData {
    pub geometry: Geometry,
    pub npe: usize,
    pub positions: Vec<[f64; 3]>,
    pub volumes: Vec<f64>,
    pub elements: Vec<usize>,
    pub nodes: Vec<usize>,
    pub shape: Vec<f64>,
    pub gradients: Vec<[f64; 3]>,
}

impl GaussData {
    /// Maps every stiffness quadrature point of every element (mesh already checked).
    /// Axisymmetric: refuses a point at `r ≤ 0` (the rules' points are interior, so only a
    /// curved element crossing the axis has one).
    pub fn new<M: ElementMesh>(mesh: &M, geometry: Geometry) -> Result<Self, MeshError> {
        let elements = mesh.elements();
        let npe = elements.first().map_or(0, Vec::len);
        let mut g = GaussData {
            geometry,
            npe,
            positions: Vec::new(),
            volumes: Vec::new(),
            elements: Vec::new(),
            nodes: Vec::new(),
            shape: Vec::new(),
            gradients: Vec::new(),
        };
        for (e, element) in elements.iter().enumerate() {
            for m in mesh.stress_points(e)? {
                let weight = geometry.weight(m.position);
                if !(weight.is_finite() && weight > 0.0) {
                    return Err(MeshError::element(
                        format!("element {e}"),
                        format!(
                            "its Gauss point at {:?} lies at r = {:e} m: an axisymmetric \
                             element must lie in r > 0 inside",
                            &m.position[..2],
                            m.position[0]
                        ),
                    ));
                }
                g.positions.push(m.position);
                g.volumes.push(m.measure * weight);
                g.elements.push(e);
                g.nodes.extend_from_slice(element);
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
    pub fn point(&self, p: usize) -> impl Iterator<Item = (usize, f64, [f64; 3])> + '_ {
        let r = p * self.npe..(p + 1) * self.npe;
        self.nodes[r.clone()]
            .iter()
            .zip(&self.shape[r.clone()])
            .zip(&self.gradients[r])
            .map(|((&n, &s), &g)| (n, s, g))
    }
}
