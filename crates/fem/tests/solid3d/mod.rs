//! Shared helpers of the 3D elasticity tests (`lame_sphere.rs`, `patch_test_3d.rs`,
//! `face_loads.rs`): the static stiffness `K = Bᵀ blockdiag((V_p S₀)⁻¹) B` assembled
//! sparse from the operators of an `Assembly<6>` and solved by faer's sparse Cholesky,
//! nodal fields split into free and prescribed dofs, and distorted tetrahedral blocks.
#![allow(dead_code)]
use faer::linalg::solvers::Solve;
use faer::prelude::Reborrow;
use faer::sparse::linalg::matmul::sparse_sparse_matmul;
use faer::sparse::{SparseColMat, Triplet};
use faer::{MatMut, Par, Side};
use nalgebra::SMatrix;
use talus_fem::assembly::add_mul;
use talus_fem::element::tet10::EDGES;
use talus_fem::{Assembly, Dof, DofMap, ElementOrder, TetrahedralMesh};

pub type Sparse = SparseColMat<usize, f64>;

/// `(K_ff, K_fp) = B_fᵀ D (B_f, B_p)` with `D = blockdiag(S_p⁻¹)`, `S_p = V_p S₀` the
/// compliance blocks of the assembly: the elastic stiffness `Σ_p V_p B̂_pᵀ C B̂_p` (`B̂` the
/// unweighted strain rows), since `B` carries `V_p` once on each side.
pub fn stiffness(asm: &Assembly<6>, s0: &SMatrix<f64, 6, 6>) -> (Sparse, Sparse) {
    let blocks = asm.compliance_blocks(s0);
    let n = 6 * blocks.len();
    let mut triplets = Vec::with_capacity(36 * blocks.len());
    for (p, s) in blocks.iter().enumerate() {
        let d = s.try_inverse().expect("compliance blocks are SPD");
        for i in 0..6 {
            for j in 0..6 {
                triplets.push(Triplet::new(6 * p + i, 6 * p + j, d[(i, j)]));
            }
        }
    }
    let d = Sparse::try_new_from_triplets(n, n, &triplets).unwrap();
    let bt = asm.b_free.transpose().to_col_major().unwrap();
    let db_f = sparse_sparse_matmul(d.rb(), asm.b_free.rb(), 1.0, Par::Seq).unwrap();
    let db_p = sparse_sparse_matmul(d.rb(), asm.b_prescribed.rb(), 1.0, Par::Seq).unwrap();
    let k_ff = sparse_sparse_matmul(bt.rb(), db_f.rb(), 1.0, Par::Seq).unwrap();
    let k_fp = sparse_sparse_matmul(bt.rb(), db_p.rb(), 1.0, Par::Seq).unwrap();
    (k_ff, k_fp)
}

/// `x` with `K x = rhs`, `K` symmetric positive definite (its lower triangle is read).
pub fn solve_spd(k: &Sparse, rhs: &[f64]) -> Vec<f64> {
    let llt = k.sp_cholesky(Side::Lower).expect("K is SPD");
    let mut x = rhs.to_vec();
    let n = x.len();
    llt.solve_in_place(MatMut::from_column_major_slice_mut(&mut x, n, 1));
    x
}

/// `A x`.
pub fn mul(a: &Sparse, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; a.nrows()];
    add_mul(a, x, &mut y);
    y
}

/// The nodal field `u(node, component)` split into free and prescribed values.
pub fn split(dofs: &DofMap, u: impl Fn(usize, usize) -> f64) -> (Vec<f64>, Vec<f64>) {
    let mut free = vec![0.0; dofs.n_free()];
    let mut prescribed = vec![0.0; dofs.n_prescribed()];
    for n in 0..dofs.n_nodes() {
        for c in 0..3 {
            match dofs.dof(n, c).unwrap() {
                Dof::Free(i) => free[i] = u(n, c),
                Dof::Prescribed(j) => prescribed[j] = u(n, c),
            }
        }
    }
    (free, prescribed)
}

/// Forces on every node `[fx, fy, fz]`, free and prescribed dofs together.
pub fn nodal(dofs: &DofMap, f: &(Vec<f64>, Vec<f64>)) -> Vec<[f64; 3]> {
    dofs.nodal_vectors::<3>(&f.0, &f.1).unwrap()
}

/// A pseudo-random sequence in `[−1, 1)` (a 64-bit LCG, as `common::distorted_rectangle`).
pub fn jitter(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// The uneven grid of the distorted blocks: a box `[0, 3] × [0, 2] × [0, 1.5]` of
/// 4 × 3 × 3 cells, no two alike.
pub const XS: [f64; 5] = [0.0, 0.7, 1.5, 2.2, 3.0];
pub const YS: [f64; 4] = [0.0, 0.6, 1.3, 2.0];
pub const ZS: [f64; 4] = [0.0, 0.4, 0.9, 1.5];
pub const BOX_VOLUME: f64 = 3.0 * 2.0 * 1.5;

/// `TetrahedralMesh::block` on [`XS`] × [`YS`] × [`ZS`] with every vertex moved
/// pseudo-randomly by up to `amplitude` (m) along each axis *within the sides it lies on*:
/// interior vertices in any direction, a vertex on one side within that side's plane, on an
/// edge of the box along that edge, corners not at all. The sides stay flat and keep their
/// node and face sets, no two tetrahedra are alike, and P2 mid-edge nodes are put back at
/// their edge's mid-point, so every element stays affine.
pub fn distorted_block(order: ElementOrder, amplitude: f64) -> TetrahedralMesh {
    let mut mesh = TetrahedralMesh::block(&XS, &YS, &ZS, order).unwrap();
    let ends = [(XS[0], XS[4]), (YS[0], YS[3]), (ZS[0], ZS[3])];
    let mut next = jitter(0x9E37_79B9_7F4A_7C15);
    let vertices = vertex_flags(&mesh);
    for (p, &vertex) in mesh.nodes.iter_mut().zip(&vertices) {
        if vertex {
            for (c, (lo, hi)) in ends.iter().enumerate() {
                let d = amplitude * next();
                if p[c] != *lo && p[c] != *hi {
                    p[c] += d;
                }
            }
        }
    }
    if order == ElementOrder::P2 {
        place_mid_edge_nodes(&mut mesh);
    }
    mesh.check_elements().unwrap();
    mesh
}

/// Whether each node is a vertex of some tetrahedron (P1: all).
pub fn vertex_flags(mesh: &TetrahedralMesh) -> Vec<bool> {
    let mut vertex = vec![false; mesh.nodes.len()];
    for t in &mesh.tetrahedra {
        for &n in &t[..4] {
            vertex[n] = true;
        }
    }
    vertex
}

/// Puts every P2 mid-edge node at the mid-point of its edge's vertices.
pub fn place_mid_edge_nodes(mesh: &mut TetrahedralMesh) {
    for e in 0..mesh.tetrahedra.len() {
        let t = mesh.tetrahedra[e].clone();
        for (m, (a, b)) in EDGES.iter().enumerate() {
            let (xa, xb) = (mesh.nodes[t[*a]], mesh.nodes[t[*b]]);
            mesh.nodes[t[4 + m]] = std::array::from_fn(|c| 0.5 * (xa[c] + xb[c]));
        }
    }
}

/// Volume of the straight tetrahedron on the first four nodes of element `e`.
pub fn tetrahedron_volume(mesh: &TetrahedralMesh, e: usize) -> f64 {
    let x: Vec<[f64; 3]> = mesh.tetrahedra[e][..4]
        .iter()
        .map(|&n| mesh.nodes[n])
        .collect();
    let d = |i: usize| -> [f64; 3] { std::array::from_fn(|c| x[i][c] - x[0][c]) };
    let (a, b, c) = (d(1), d(2), d(3));
    (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0]))
        / 6.0
}

pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
