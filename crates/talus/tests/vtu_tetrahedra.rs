//! 3D VTU snapshots (issue 25: "VTU with tetrahedra (VTK types 10 and 24)"), read back
//! from the ASCII file:
//! - a P2 block's cells are VTK quadratic tetrahedra whose mid-edge points sit at the
//!   midpoints of VTK's edges `(0,1), (1,2), (2,0), (0,3), (1,3), (2,3)` (VTK's
//!   `vtkQuadraticTetra` node order, *VTK User's Guide*, 11th ed., Fig. 19-20), whatever
//!   Gmsh's order was; a P1 block's are VTK tetrahedra;
//! - points, displacements and velocities keep their z;
//! - the Mandel 6-vector `(xx, yy, zz, √2 yz, √2 xz, √2 xy)` is written as the plain
//!   tensor in VTK's order `XX, YY, ZZ, XY, YZ, XZ`;
//! - the principal stresses of a rotated diagonal tensor are its diagonal, von Mises of a
//!   pure shear is `√3 τ`;
//! - mismatched dimensions and wrong element node counts are refused naming the field.
use crate::common;
use std::f64::consts::SQRT_2;
use std::path::PathBuf;

use common::{array, attr, field_of, target_tmp_dir};
use nalgebra::{Matrix3, Rotation3, Vector3};
use talus::output::{principal_stresses, von_mises, write_vtu, FieldSnapshot, MeshView};
use talus_fem::{ElementOrder, TetrahedralMesh};

fn path(name: &str) -> PathBuf {
    let dir = target_tmp_dir("vtu_tetrahedra", name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(format!("{name}.vtu"))
}

/// Writes `mesh` with displacement `u(x) = (x, 2y, 3z)` and `stress` in every element.
fn write_block(mesh: &TetrahedralMesh, stress: [f64; 6], name: &str) -> String {
    let u: Vec<[f64; 3]> = mesh
        .nodes
        .iter()
        .map(|x| [x[0], 2.0 * x[1], 3.0 * x[2]])
        .collect();
    let stress = vec![stress; mesh.tetrahedra.len()];
    let plastic = vec![0.0; mesh.tetrahedra.len()];
    let file = path(name);
    write_vtu(
        &file,
        &FieldSnapshot {
            mesh: MeshView {
                nodes: &mesh.nodes,
                elements: &mesh.tetrahedra,
            },
            time: 1.5,
            displacement: &u,
            velocity: &u,
            stress: &stress,
            plastic_strain: &plastic,
            material: None,
            pore_pressure: None,
        },
    )
    .unwrap();
    std::fs::read_to_string(file).unwrap()
}

#[test]
fn p2_cells_are_vtk_quadratic_tetrahedra_with_vtk_mid_edge_order() {
    let mesh = TetrahedralMesh::block(
        &[0.0, 1.0, 2.5],
        &[0.0, 0.7],
        &[0.0, 0.4, 1.0],
        ElementOrder::P2,
    )
    .unwrap();
    let xml = write_block(&mesh, [0.0; 6], "p2");
    let cells = mesh.tetrahedra.len();
    assert_eq!(attr(&xml, "NumberOfCells"), cells.to_string());
    assert!(array(&xml, "types").iter().all(|&t| t == 24.0));
    let offsets = array(&xml, "offsets");
    assert_eq!(offsets.last().copied(), Some(10.0 * cells as f64));
    let points = array(&xml, "Points");
    let connectivity = array(&xml, "connectivity");
    let point = |k: f64| Vector3::from_column_slice(&points[3 * k as usize..3 * k as usize + 3]);
    const VTK_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];
    for cell in connectivity.chunks_exact(10) {
        for (m, (i, j)) in VTK_EDGES.iter().enumerate() {
            let mid = (point(cell[*i]) + point(cell[*j])) / 2.0;
            assert!(
                (point(cell[4 + m]) - mid).norm() < 1e-12,
                "cell {cell:?}: point {} is not the midpoint of VTK edge {i}{j}",
                4 + m
            );
        }
        // VTK's tetrahedron is positively oriented: (x1 − x0) × (x2 − x0) · (x3 − x0) > 0.
        let (a, b, c) = (
            point(cell[1]) - point(cell[0]),
            point(cell[2]) - point(cell[0]),
            point(cell[3]) - point(cell[0]),
        );
        assert!(a.cross(&b).dot(&c) > 0.0, "cell {cell:?} is inverted");
    }
    // Points and point vectors keep z: u = (x, 2y, 3z).
    let u = array(&xml, "displacement");
    for (k, x) in mesh.nodes.iter().enumerate() {
        assert_eq!(&points[3 * k..3 * k + 3], x);
        assert_eq!(&u[3 * k..3 * k + 3], &[x[0], 2.0 * x[1], 3.0 * x[2]]);
    }
    assert_eq!(array(&xml, "TimeValue"), [1.5]);
}

#[test]
fn p1_cells_are_vtk_tetrahedra_and_mandel_shears_go_to_their_vtk_slots() {
    let mesh =
        TetrahedralMesh::block(&[0.0, 1.0], &[0.0, 1.0], &[0.0, 1.0], ElementOrder::P1).unwrap();
    // Plain tensor xx = 1, yy = 2, zz = 3, yz = 4, xz = 5, xy = 6 (Pa).
    let mandel = [1.0, 2.0, 3.0, SQRT_2 * 4.0, SQRT_2 * 5.0, SQRT_2 * 6.0];
    let xml = write_block(&mesh, mandel, "p1");
    assert_eq!(array(&xml, "types"), vec![10.0; 6]);
    let sigma = array(&xml, "stress");
    // VTK order XX, YY, ZZ, XY, YZ, XZ.
    let want = [1.0, 2.0, 3.0, 6.0, 4.0, 5.0];
    for (got, want) in sigma[..6].iter().zip(want) {
        assert!((got - want).abs() < 1e-14, "{:?} vs {want:?}", &sigma[..6]);
    }
    // Principal stresses: the eigenvalues of that tensor, descending (nalgebra's
    // symmetric eigensolver on the matrix built here, independently of the writer).
    let m = Matrix3::new(1.0, 6.0, 5.0, 6.0, 2.0, 4.0, 5.0, 4.0, 3.0);
    let mut e: Vec<f64> = m.symmetric_eigenvalues().iter().copied().collect();
    e.sort_by(|a, b| b.total_cmp(a));
    let principal = array(&xml, "principal_stress");
    for k in 0..3 {
        assert!(
            (principal[k] - e[k]).abs() < 1e-12 * 12.0,
            "{principal:?} vs {e:?}"
        );
    }
    // Trace invariance: the principal stresses sum to tr σ = 6.
    assert!((principal[..3].iter().sum::<f64>() - 6.0).abs() < 1e-12);
}

/// A diagonal stress turned by a rotation has that diagonal as principal stresses, and
/// its von Mises stress is that of the diagonal, `√(((s1−s2)² + (s2−s3)² + (s3−s1)²)/2)`.
#[test]
fn principal_stresses_of_a_rotated_diagonal_tensor_are_its_diagonal() {
    let s = [30.0e3, -12.0e3, -85.0e3];
    let r = Rotation3::from_euler_angles(0.3, -0.7, 1.1);
    let t = r.matrix() * Matrix3::from_diagonal(&Vector3::from(s)) * r.matrix().transpose();
    let mandel = [
        t[(0, 0)],
        t[(1, 1)],
        t[(2, 2)],
        SQRT_2 * t[(1, 2)],
        SQRT_2 * t[(0, 2)],
        SQRT_2 * t[(0, 1)],
    ];
    let p = principal_stresses(&mandel);
    for (got, want) in p.iter().zip(s) {
        assert!((got - want).abs() < 1e-9 * 85.0e3, "{p:?} vs {s:?}");
    }
    let vm = (((s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2)) / 2.0).sqrt();
    assert!((von_mises(&mandel) - vm).abs() < 1e-9 * vm);
    // Pure shear τ_yz: von Mises √3 τ, principal (τ, 0, −τ).
    let tau = 20.0e3;
    let shear = [0.0, 0.0, 0.0, SQRT_2 * tau, 0.0, 0.0];
    assert!((von_mises(&shear) - 3f64.sqrt() * tau).abs() < 1e-9 * tau);
    let p = principal_stresses(&shear);
    assert!((p[0] - tau).abs() < 1e-9 * tau && p[1].abs() < 1e-9 * tau);
    assert!((p[2] + tau).abs() < 1e-9 * tau);
}

#[test]
fn mismatched_dimensions_and_node_counts_are_refused() {
    let mesh =
        TetrahedralMesh::block(&[0.0, 1.0], &[0.0, 1.0], &[0.0, 1.0], ElementOrder::P1).unwrap();
    let zero = vec![[0.0; 3]; mesh.nodes.len()];
    let n = mesh.tetrahedra.len();
    let plastic = vec![0.0; n];
    // A 2D Mandel stress on a 3D mesh.
    let stress4 = vec![[0.0; 4]; n];
    let file = path("refused");
    let bad = FieldSnapshot {
        mesh: MeshView {
            nodes: &mesh.nodes,
            elements: &mesh.tetrahedra,
        },
        time: 0.0,
        displacement: &zero,
        velocity: &zero,
        stress: &stress4,
        plastic_strain: &plastic,
        material: None,
        pore_pressure: None,
    };
    assert_eq!(field_of(write_vtu(&file, &bad).unwrap_err()), "stress");
    // A 6-node element (a P2 triangle's count) on a 3D mesh.
    let stress6 = vec![[0.0; 6]; 1];
    let six = vec![vec![0, 1, 2, 3, 4, 5]];
    let bad = FieldSnapshot {
        mesh: MeshView {
            nodes: &mesh.nodes,
            elements: &six,
        },
        time: 0.0,
        displacement: &zero,
        velocity: &zero,
        stress: &stress6,
        plastic_strain: &plastic[..1],
        material: None,
        pore_pressure: None,
    };
    let err = write_vtu(&file, &bad).unwrap_err();
    assert!(err.to_string().contains("expected 4 or 10"), "{err}");
    assert_eq!(field_of(err), "mesh.elements");
    assert!(!file.exists(), "a refused snapshot wrote a file");
}
