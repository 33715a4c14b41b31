//! Linear (4-node) tetrahedron on the reference tetrahedron
//! `{ξ, η, ζ ≥ 0, ξ + η + ζ ≤ 1}`, nodes in Gmsh `Tet4` order: (0,0,0), (1,0,0), (0,1,0),
//! (0,0,1).

/// Shape functions `N_a(ξ, η, ζ)`: the barycentric coordinates.
pub fn shape(xi: [f64; 3]) -> [f64; 4] {
    let [x, y, z] = xi;
    [1.0 - x - y - z, x, y, z]
}

/// Reference gradients `∂N_a/∂(ξ, η, ζ)` (constant).
pub fn reference_gradients(_xi: [f64; 3]) -> [[f64; 3]; 4] {
    [
        [-1.0, -1.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ]
}
