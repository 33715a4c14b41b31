//! Linear (3-node) triangle on the reference triangle `{ξ ≥ 0, η ≥ 0, ξ + η ≤ 1}`,
//! nodes at (0,0), (1,0), (0,1).

/// Shape functions `N_a(ξ, η)`: the barycentric coordinates.
pub fn shape(xi: [f64; 2]) -> [f64; 3] {
    let [x, y] = xi;
    [1.0 - x - y, x, y]
}

/// Reference gradients `∂N_a/∂(ξ, η)` (constant).
pub fn reference_gradients(_xi: [f64; 2]) -> [[f64; 2]; 3] {
    [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]]
}
