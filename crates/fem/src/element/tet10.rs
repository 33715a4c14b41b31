//! Quadratic (10-node) tetrahedron, nodes in Gmsh `Tet10` order: the vertices of
//! [`tet4`](super::tet4), then the mid-edge nodes of edges 01, 12, 20, 30, 32, 31 (Gmsh's
//! order; VTK's quadratic tetrahedron swaps the last two). With barycentric
//! `λ = (1 − ξ − η − ζ, ξ, η, ζ)`: `N_v = λ_v (2λ_v − 1)`, `N_ij = 4 λ_i λ_j`.

/// The vertices `(i, j)` of each mid-edge node `4 + k`, in node order.
pub const EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)];

/// Shape functions `N_a(ξ, η, ζ)`.
pub fn shape(xi: [f64; 3]) -> [f64; 10] {
    let l = barycentric(xi);
    let mut n = [0.0; 10];
    for v in 0..4 {
        n[v] = l[v] * (2.0 * l[v] - 1.0);
    }
    for (k, (i, j)) in EDGES.iter().enumerate() {
        n[4 + k] = 4.0 * l[*i] * l[*j];
    }
    n
}

/// Reference gradients `∂N_a/∂(ξ, η, ζ)` (linear).
pub fn reference_gradients(xi: [f64; 3]) -> [[f64; 3]; 10] {
    let l = barycentric(xi);
    // ∂λ_v/∂ξ_k: λ_0 = 1 − ξ − η − ζ, λ_{k+1} = ξ_k.
    let dl = |v: usize, k: usize| -> f64 {
        match v {
            0 => -1.0,
            _ if v == k + 1 => 1.0,
            _ => 0.0,
        }
    };
    std::array::from_fn(|a| {
        std::array::from_fn(|k| match a {
            0..4 => (4.0 * l[a] - 1.0) * dl(a, k),
            _ => {
                let (i, j) = EDGES[a - 4];
                4.0 * (dl(i, k) * l[j] + l[i] * dl(j, k))
            }
        })
    })
}

fn barycentric(xi: [f64; 3]) -> [f64; 4] {
    let [x, y, z] = xi;
    [1.0 - x - y - z, x, y, z]
}
