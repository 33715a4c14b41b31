//! Gmsh 4.1 tetrahedral meshes (`TetrahedralMesh::from_msh_bytes`): a structured block
//! written as an ASCII `.msh` (sparse node tags, a physical volume, a physical surface whose
//! triangles are written inward) reads back as the same mesh, with the surface's faces
//! turned outward; inverted tetrahedra, mixed orders and 2D files are refused by name.
use std::fmt::Write;

use talus_fem::element::ElementOrder;
use talus_fem::{MeshError, TetrahedralMesh};

use crate::common;
use common::gmsh_block::{block, node_tag, to_msh};

#[test]
fn a_block_written_as_msh_reads_back_as_itself() {
    for order in [ElementOrder::P1, ElementOrder::P2] {
        let mesh = block(order);
        let read =
            TetrahedralMesh::from_msh_bytes(to_msh(&mesh, &mesh.tetrahedra).as_bytes()).unwrap();
        assert_eq!(read.order, order);
        assert_eq!(read.nodes, mesh.nodes);
        assert_eq!(read.tetrahedra, mesh.tetrahedra);
        assert_eq!(
            read.element_sets["soil"],
            (0..mesh.tetrahedra.len()).collect::<Vec<_>>()
        );
        assert_eq!(read.node_sets["top"], mesh.node_sets["top"]);
        // The faces were written inward; they come back outward, each as the block has it.
        assert_eq!(read.face_sets["top"], mesh.face_sets["top"], "{order:?}");
    }
}

#[test]
fn inverted_tetrahedra_are_refused_with_their_gmsh_tag() {
    let mesh = block(ElementOrder::P1);
    let mut tetrahedra = mesh.tetrahedra.clone();
    tetrahedra[4].swap(0, 1);
    let err = TetrahedralMesh::from_msh_bytes(to_msh(&mesh, &tetrahedra).as_bytes()).unwrap_err();
    assert!(
        matches!(&err, MeshError::BadElement { element, .. } if element == "Gmsh element 5"),
        "{err}"
    );
}

#[test]
fn mixed_orders_and_triangle_meshes_are_refused() {
    let p1 = block(ElementOrder::P1);
    let text = to_msh(&p1, &p1.tetrahedra);
    // One tetrahedron block declared Tet10 with 4 nodes cannot be read; a file whose
    // volume elements are replaced by nothing is a 2D mesh.
    let only_faces: String = {
        let start = text.find("$Elements").unwrap();
        let faces = &p1.face_sets["top"];
        let mut s = text[..start].to_string();
        writeln!(s, "$Elements\n1 {0} 1 {0}\n2 1 2 {0}", faces.len()).unwrap();
        for (k, f) in faces.iter().enumerate() {
            let nodes: Vec<String> = f.nodes.iter().map(|&i| node_tag(i).to_string()).collect();
            writeln!(s, "{} {}", k + 1, nodes.join(" ")).unwrap();
        }
        writeln!(s, "$EndElements").unwrap();
        s
    };
    let err = TetrahedralMesh::from_msh_bytes(only_faces.as_bytes()).unwrap_err();
    assert!(err.to_string().contains("2D mesh"), "{err}");

    let mixed = {
        let mut s = to_msh(&p1, &p1.tetrahedra);
        let start = s.find("$Elements").unwrap();
        s.truncate(start);
        writeln!(s, "$Elements\n2 2 1 2\n3 1 4 1").unwrap();
        let t: Vec<String> = p1.tetrahedra[0]
            .iter()
            .map(|&i| node_tag(i).to_string())
            .collect();
        writeln!(s, "1 {}", t.join(" ")).unwrap();
        writeln!(s, "3 1 11 1").unwrap();
        // a Tet10 on the P1 nodes of two tetrahedra (its geometry does not matter here)
        let mut t10: Vec<usize> = p1.tetrahedra[0].clone();
        t10.extend(&p1.tetrahedra[1]);
        t10.extend(&p1.tetrahedra[2][..2]);
        let t10: Vec<String> = t10.iter().map(|&i| node_tag(i).to_string()).collect();
        writeln!(s, "2 {}", t10.join(" ")).unwrap();
        writeln!(s, "$EndElements").unwrap();
        s
    };
    let err = TetrahedralMesh::from_msh_bytes(mixed.as_bytes()).unwrap_err();
    assert!(err.to_string().contains("mixed element orders"), "{err}");
    assert!(err.to_string().contains("Gmsh element 2"), "{err}");
}
