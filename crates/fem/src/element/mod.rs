//! Reference triangles (P1, P2) and the isoparametric map to physical coordinates;
//! reference tetrahedra for 3D meshes in [`tetrahedron`].
//!
//! Coordinates in metres. A triangle's nodes are counter-clockwise, so the Jacobian
//! determinant `det J = det ∂x/∂ξ` is positive on a valid element; its area is
//! `∫ det J dξ` over the reference triangle (area 1/2).
pub mod edge;
pub mod p1;
pub mod p2;
pub mod tet10;
pub mod tet4;
pub mod tetrahedron;

/// Polynomial order of the (isoparametric) triangles or tetrahedra of a mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ElementOrder {
    /// Linear 3-node triangle (Gmsh `Tri3`), constant strain.
    P1,
    /// Quadratic 6-node triangle (Gmsh `Tri6`), linear strain.
    P2,
}

impl ElementOrder {
    /// Nodes per triangle: 3 or 6.
    pub fn nodes_per_triangle(self) -> usize {
        match self {
            ElementOrder::P1 => 3,
            ElementOrder::P2 => 6,
        }
    }

    /// Nodes per boundary edge: 2 or 3 (end points first, then the mid point).
    pub fn nodes_per_edge(self) -> usize {
        match self {
            ElementOrder::P1 => 2,
            ElementOrder::P2 => 3,
        }
    }

    /// Shape functions at a reference point `ξ` (any point, e.g. for plots); length
    /// [`nodes_per_triangle`](Self::nodes_per_triangle).
    pub fn shape_functions(self, xi: [f64; 2]) -> Vec<f64> {
        match self {
            ElementOrder::P1 => p1::shape(xi).to_vec(),
            ElementOrder::P2 => p2::shape(xi).to_vec(),
        }
    }

    /// Gradients `∂N_a/∂(ξ, η)` at a reference point.
    pub fn reference_gradients(self, xi: [f64; 2]) -> Vec<[f64; 2]> {
        match self {
            ElementOrder::P1 => p1::reference_gradients(xi).to_vec(),
            ElementOrder::P2 => p2::reference_gradients(xi).to_vec(),
        }
    }

    /// Reference coordinates of the element's nodes, in node order.
    pub fn reference_nodes(self) -> &'static [[f64; 2]] {
        match self {
            ElementOrder::P1 => &[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            ElementOrder::P2 => &[
                [0.0, 0.0],
                [1.0, 0.0],
                [0.0, 1.0],
                [0.5, 0.0],
                [0.5, 0.5],
                [0.0, 0.5],
            ],
        }
    }
}

/// The isoparametric map of one triangle evaluated at a reference point.
#[derive(Debug, Clone, PartialEq)]
pub struct MappedPoint {
    /// Physical position `x(ξ) = Σ N_a(ξ) x_a` (m).
    pub position: [f64; 2],
    /// Shape function values `N_a(ξ)`.
    pub shape: Vec<f64>,
    /// Physical gradients `∂N_a/∂x` (1/m).
    pub gradients: Vec<[f64; 2]>,
    /// `det ∂x/∂ξ` (m²; twice the area for an affine triangle).
    pub det_j: f64,
}

/// Evaluates the map of the triangle with node coordinates `coords` (length 3 or 6, in
/// the order of `order`) at `xi`. Returns `None` if `det J` is not positive and finite,
/// i.e. the element is inverted or degenerate there.
pub fn map_point(order: ElementOrder, coords: &[[f64; 2]], xi: [f64; 2]) -> Option<MappedPoint> {
    let shape = order.shape_functions(xi);
    let dref = order.reference_gradients(xi);
    let mut position = [0.0; 2];
    // J[i][j] = ∂x_i/∂ξ_j
    let mut j = [[0.0; 2]; 2];
    for ((x, n), g) in coords.iter().zip(&shape).zip(&dref) {
        for i in 0..2 {
            position[i] += n * x[i];
            for k in 0..2 {
                j[i][k] += x[i] * g[k];
            }
        }
    }
    let det_j = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    if !(det_j.is_finite() && det_j > 0.0) {
        return None;
    }
    // ∂N/∂x = J⁻ᵀ ∂N/∂ξ
    let gradients = dref
        .iter()
        .map(|g| {
            [
                (j[1][1] * g[0] - j[1][0] * g[1]) / det_j,
                (-j[0][1] * g[0] + j[0][0] * g[1]) / det_j,
            ]
        })
        .collect();
    Some(MappedPoint {
        position,
        shape,
        gradients,
        det_j,
    })
}

/// `det J` at `xi` without the rest of the map (may be ≤ 0 or NaN).
pub fn jacobian_determinant(order: ElementOrder, coords: &[[f64; 2]], xi: [f64; 2]) -> f64 {
    let dref = order.reference_gradients(xi);
    let mut j = [[0.0; 2]; 2];
    for (x, g) in coords.iter().zip(&dref) {
        for i in 0..2 {
            for k in 0..2 {
                j[i][k] += x[i] * g[k];
            }
        }
    }
    j[0][0] * j[1][1] - j[0][1] * j[1][0]
}

#[cfg(test)]
mod tests {
    use super::*;

    const POINTS: [[f64; 2]; 4] = [[0.2, 0.3], [0.0, 0.0], [0.7, 0.1], [1.0 / 3.0, 1.0 / 3.0]];

    #[test]
    fn shape_functions_are_nodal_and_partition_unity() {
        for order in [ElementOrder::P1, ElementOrder::P2] {
            for (a, xa) in order.reference_nodes().iter().enumerate() {
                let n = order.shape_functions(*xa);
                for (b, nb) in n.iter().enumerate() {
                    assert_eq!(
                        *nb,
                        if a == b { 1.0 } else { 0.0 },
                        "{order:?} N_{b} at node {a}"
                    );
                }
            }
            for xi in POINTS {
                let s: f64 = order.shape_functions(xi).iter().sum();
                assert!((s - 1.0).abs() < 1e-15);
                let g = order.reference_gradients(xi);
                assert!(g.iter().map(|g| g[0]).sum::<f64>().abs() < 1e-14);
                assert!(g.iter().map(|g| g[1]).sum::<f64>().abs() < 1e-14);
            }
        }
    }

    #[test]
    fn reference_gradients_match_finite_differences() {
        let h = 1e-6;
        for order in [ElementOrder::P1, ElementOrder::P2] {
            for xi in POINTS {
                let g = order.reference_gradients(xi);
                for k in 0..2 {
                    let mut p = xi;
                    let mut m = xi;
                    p[k] += h;
                    m[k] -= h;
                    let (np, nm) = (order.shape_functions(p), order.shape_functions(m));
                    for a in 0..g.len() {
                        let fd = (np[a] - nm[a]) / (2.0 * h);
                        assert!((fd - g[a][k]).abs() < 1e-8, "{order:?} dN_{a}/dξ_{k}");
                    }
                }
            }
        }
    }

    #[test]
    fn clockwise_triangle_has_no_map() {
        let cw = [[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]];
        assert!(map_point(ElementOrder::P1, &cw, [0.3, 0.3]).is_none());
        let ccw = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let m = map_point(ElementOrder::P1, &ccw, [0.3, 0.3]).unwrap();
        assert_eq!(m.det_j, 1.0);
        assert_eq!(m.gradients, vec![[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]]);
    }
}
