//! Boundary-edge (1D) shape functions on `s ∈ [0, 1]`, nodes in Gmsh `Lin2` / `Lin3` order:
//! the two end points, then (Lin3) the mid point. Used for traction integrals.

/// Shape functions of a 2-node (`n_nodes = 2`) or 3-node edge at `s`, and their
/// derivatives `dN/ds`; entries past `n_nodes` are 0.
pub fn shape_and_derivative(n_nodes: usize, s: f64) -> ([f64; 3], [f64; 3]) {
    if n_nodes == 2 {
        ([1.0 - s, s, 0.0], [-1.0, 1.0, 0.0])
    } else {
        (
            [
                (1.0 - s) * (1.0 - 2.0 * s),
                s * (2.0 * s - 1.0),
                4.0 * s * (1.0 - s),
            ],
            [4.0 * s - 3.0, 4.0 * s - 1.0, 4.0 - 8.0 * s],
        )
    }
}
