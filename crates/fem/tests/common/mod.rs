//! Shared helpers for the integration tests.
#![allow(dead_code)]
pub mod footing;
pub mod gmsh_block;
pub mod gmsh_square;
use faer::sparse::SparseColMat;
use nalgebra::{DMatrix, SVector};
use talus_fem::{ElementOrder, Mesh};

/// A 4 × 3-cell rectangle [0, 3] × [0, 2] on an uneven grid whose interior nodes are
/// moved pseudo-randomly (up to 12 % of the smallest spacing), so that no two triangles
/// are alike; P2 mid nodes move too, making curved (isoparametric) triangles. The
/// boundary stays straight, so the area is exactly 6 m².
///
/// ```text
///  y=2 +----+-----+----+-----+
///      | /  |  \  | /  |  \  |   interior nodes jittered
///  y=0 +----+-----+----+-----+
///      x=0                  x=3
/// ```
pub fn distorted_rectangle(order: ElementOrder) -> Mesh {
    let xs = [0.0, 0.7, 1.5, 2.2, 3.0];
    let ys = [0.0, 0.6, 1.3, 2.0];
    let mut mesh = Mesh::rectangle(&xs, &ys, order).unwrap();
    let amplitude = 0.12 * 0.3; // P2 node spacing is half the cell size
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    for p in mesh.nodes.iter_mut() {
        let on_boundary = p[0] == 0.0 || p[0] == 3.0 || p[1] == 0.0 || p[1] == 2.0;
        if !on_boundary {
            p[0] += amplitude * next();
            p[1] += amplitude * next();
        }
    }
    mesh.validate().unwrap();
    mesh
}

pub const AREA: f64 = 6.0;

/// Dense copy of a faer sparse matrix.
pub fn dense(a: &SparseColMat<usize, f64>) -> DMatrix<f64> {
    let mut m = DMatrix::zeros(a.nrows(), a.ncols());
    let (cp, ri, v) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    for j in 0..a.ncols() {
        for k in cp[j]..cp[j + 1] {
            m[(ri[k], j)] += v[k];
        }
    }
    m
}

/// Mandel vector `(xx, yy, zz, √2 xy)` of the symmetric part of a 2 × 2 gradient.
pub fn mandel_sym(g: [[f64; 2]; 2]) -> SVector<f64, 4> {
    SVector::from([
        g[0][0],
        g[1][1],
        0.0,
        std::f64::consts::SQRT_2 * 0.5 * (g[0][1] + g[1][0]),
    ])
}

/// Nodal values of the affine field `u(x) = u0 + G x`, split into (free, prescribed).
pub fn affine_field(
    mesh: &Mesh,
    dofs: &talus_fem::DofMap,
    u0: [f64; 2],
    g: [[f64; 2]; 2],
) -> (Vec<f64>, Vec<f64>) {
    let mut free = vec![0.0; dofs.n_free()];
    let mut prescribed = vec![0.0; dofs.n_prescribed()];
    for (n, x) in mesh.nodes.iter().enumerate() {
        for c in 0..2 {
            let u = u0[c] + g[c][0] * x[0] + g[c][1] * x[1];
            match dofs.dof(n, c).unwrap() {
                talus_fem::Dof::Free(i) => free[i] = u,
                talus_fem::Dof::Prescribed(j) => prescribed[j] = u,
            }
        }
    }
    (free, prescribed)
}
