//! Quadratic (6-node) triangle on the reference triangle, nodes in Gmsh `Tri6` order:
//! vertices (0,0), (1,0), (0,1), then the mid-edge nodes of edges 01, 12, 20.
//! With barycentric `λ = (1 − ξ − η, ξ, η)`: `N_v = λ_v (2λ_v − 1)`, `N_ij = 4 λ_i λ_j`.

/// Shape functions `N_a(ξ, η)`.
pub fn shape(xi: [f64; 2]) -> [f64; 6] {
    let [x, y] = xi;
    let l = [1.0 - x - y, x, y];
    [
        l[0] * (2.0 * l[0] - 1.0),
        l[1] * (2.0 * l[1] - 1.0),
        l[2] * (2.0 * l[2] - 1.0),
        4.0 * l[0] * l[1],
        4.0 * l[1] * l[2],
        4.0 * l[2] * l[0],
    ]
}

/// Reference gradients `∂N_a/∂(ξ, η)` (linear in ξ, η).
pub fn reference_gradients(xi: [f64; 2]) -> [[f64; 2]; 6] {
    let [x, y] = xi;
    let l0 = 1.0 - x - y;
    // dλ/dξ = (−1, 1, 0), dλ/dη = (−1, 0, 1).
    [
        [1.0 - 4.0 * l0, 1.0 - 4.0 * l0],
        [4.0 * x - 1.0, 0.0],
        [0.0, 4.0 * y - 1.0],
        [4.0 * (l0 - x), -4.0 * x],
        [4.0 * y, 4.0 * x],
        [-4.0 * y, 4.0 * (l0 - y)],
    ]
}
