//! Reference tetrahedra (P1: Gmsh `Tet4`, P2: Gmsh `Tet10`) and their isoparametric map
//! to physical coordinates (m), for 3D meshes.
//!
//! A tetrahedron's nodes are ordered so that `(x₁ − x₀, x₂ − x₀, x₃ − x₀)` is a direct
//! triad (Gmsh's convention): `det J = det ∂x/∂ξ` is positive on a valid element, and its
//! volume is `∫ det J dξ` over the reference tetrahedron (volume 1/6).
//!
//! Strain rates are Mandel 6-vectors `(xx, yy, zz, √2 yz, √2 xz, √2 xy)`, tension
//! positive: the cone of `talus-cone` at `D = 6`.
use super::{tet10, tet4, ElementOrder};

/// Mandel rows of a 3D stress or strain.
pub const MANDEL_3D: usize = 6;

impl ElementOrder {
    /// Nodes per tetrahedron: 4 or 10.
    pub fn nodes_per_tetrahedron(self) -> usize {
        match self {
            ElementOrder::P1 => 4,
            ElementOrder::P2 => 10,
        }
    }

    /// Tetrahedron shape functions at a reference point `ξ`; length
    /// [`nodes_per_tetrahedron`](Self::nodes_per_tetrahedron).
    pub fn tetrahedron_shape_functions(self, xi: [f64; 3]) -> Vec<f64> {
        match self {
            ElementOrder::P1 => tet4::shape(xi).to_vec(),
            ElementOrder::P2 => tet10::shape(xi).to_vec(),
        }
    }

    /// Tetrahedron gradients `∂N_a/∂(ξ, η, ζ)` at a reference point.
    pub fn tetrahedron_reference_gradients(self, xi: [f64; 3]) -> Vec<[f64; 3]> {
        match self {
            ElementOrder::P1 => tet4::reference_gradients(xi).to_vec(),
            ElementOrder::P2 => tet10::reference_gradients(xi).to_vec(),
        }
    }

    /// Reference coordinates of the tetrahedron's nodes, in node order.
    pub fn tetrahedron_reference_nodes(self) -> Vec<[f64; 3]> {
        let vertices = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let mut nodes = vertices.to_vec();
        if self == ElementOrder::P2 {
            for (i, j) in tet10::EDGES {
                nodes.push(std::array::from_fn(|k| {
                    0.5 * (vertices[i][k] + vertices[j][k])
                }));
            }
        }
        nodes
    }
}

/// The isoparametric map of one tetrahedron evaluated at a reference point.
#[derive(Debug, Clone, PartialEq)]
pub struct MappedPoint3 {
    /// Physical position `x(ξ) = Σ N_a(ξ) x_a` (m).
    pub position: [f64; 3],
    /// Shape function values `N_a(ξ)`.
    pub shape: Vec<f64>,
    /// Physical gradients `∂N_a/∂x` (1/m).
    pub gradients: Vec<[f64; 3]>,
    /// `det ∂x/∂ξ` (m³; six times the volume for an affine tetrahedron).
    pub det_j: f64,
}

/// `J[i][k] = ∂x_i/∂ξ_k` from the reference gradients `dref` at a point.
fn jacobian(coords: &[[f64; 3]], dref: &[[f64; 3]]) -> [[f64; 3]; 3] {
    let mut j = [[0.0; 3]; 3];
    for (x, g) in coords.iter().zip(dref) {
        for i in 0..3 {
            for k in 0..3 {
                j[i][k] += x[i] * g[k];
            }
        }
    }
    j
}

fn determinant(j: &[[f64; 3]; 3]) -> f64 {
    j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0])
}

/// `det J` at `xi` without the rest of the map (may be ≤ 0 or NaN: an inverted or flat
/// tetrahedron).
pub fn tetrahedron_jacobian_determinant(
    order: ElementOrder,
    coords: &[[f64; 3]],
    xi: [f64; 3],
) -> f64 {
    determinant(&jacobian(
        coords,
        &order.tetrahedron_reference_gradients(xi),
    ))
}

/// Evaluates the map of the tetrahedron with node coordinates `coords` (length 4 or 10, in
/// the order of `order`) at `xi`. `None` if `det J` is not positive and finite there.
pub fn map_tetrahedron_point(
    order: ElementOrder,
    coords: &[[f64; 3]],
    xi: [f64; 3],
) -> Option<MappedPoint3> {
    let shape = order.tetrahedron_shape_functions(xi);
    let dref = order.tetrahedron_reference_gradients(xi);
    let j = jacobian(coords, &dref);
    let det_j = determinant(&j);
    if !(det_j.is_finite() && det_j > 0.0) {
        return None;
    }
    let mut position = [0.0; 3];
    for (x, n) in coords.iter().zip(&shape) {
        for i in 0..3 {
            position[i] += n * x[i];
        }
    }
    // ∂N/∂x = J⁻ᵀ ∂N/∂ξ, with J⁻¹ = adj(J) / det J: (J⁻ᵀ)[i][k] = cof(J)[i][k] / det J.
    let cof = |r: usize, c: usize| {
        let (r1, r2, c1, c2) = ((r + 1) % 3, (r + 2) % 3, (c + 1) % 3, (c + 2) % 3);
        j[r1][c1] * j[r2][c2] - j[r1][c2] * j[r2][c1]
    };
    let inv_t: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|k| cof(i, k) / det_j));
    // ∂N/∂x_i = Σ_k ∂N/∂ξ_k ∂ξ_k/∂x_i = Σ_k (J⁻¹)[k][i] g_k = Σ_k (J⁻ᵀ)[i][k] g_k.
    let gradients = dref
        .iter()
        .map(|g| std::array::from_fn(|i| (0..3).map(|k| inv_t[i][k] * g[k]).sum()))
        .collect();
    Some(MappedPoint3 {
        position,
        shape,
        gradients,
        det_j,
    })
}

/// The Mandel strain-rate rows fed by velocity component `component` (0: x, 1: y, 2: z)
/// of a node whose shape function has physical gradient `g`: `(row, coefficient)` with
/// `ε̇ = sym ∇v`, so `ε̇_row += coefficient · v_component`.
pub fn mandel_strain_rows(g: [f64; 3], component: usize) -> [(usize, f64); 3] {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    match component {
        // ε̇xx; √2 ε̇xz = (∂vx/∂z + ∂vz/∂x)/√2; √2 ε̇xy = (∂vx/∂y + ∂vy/∂x)/√2.
        0 => [(0, g[0]), (4, s * g[2]), (5, s * g[1])],
        // ε̇yy; √2 ε̇yz; √2 ε̇xy.
        1 => [(1, g[1]), (3, s * g[2]), (5, s * g[0])],
        // ε̇zz; √2 ε̇yz; √2 ε̇xz.
        _ => [(2, g[2]), (3, s * g[1]), (4, s * g[0])],
    }
}
