//! A structured tetrahedral block written as a Gmsh 4.1 ASCII file, for the 3D reader's
//! tests (`msh_tetrahedra.rs`, `fuzz_msh_reader.rs`).
use std::fmt::Write;

use talus_fem::element::ElementOrder;
use talus_fem::TetrahedralMesh;

/// Gmsh's tag of node `i`: sparse, so that `mshio` keeps the tags.
pub fn node_tag(i: usize) -> usize {
    10 + 2 * i
}

/// The ASCII `.msh` of `mesh`: every node in volume 1 ("soil"), the tetrahedra in volume 1,
/// the `top` faces in surface 1 ("top") with their first two vertices swapped (inward).
pub fn to_msh(mesh: &TetrahedralMesh, tetrahedra: &[Vec<usize>]) -> String {
    let (tet_type, tri_type) = match mesh.order {
        ElementOrder::P1 => (4, 2),
        ElementOrder::P2 => (11, 9),
    };
    let top = &mesh.face_sets["top"];
    let mut s = String::new();
    writeln!(s, "$MeshFormat\n4.1 0 8\n$EndMeshFormat").unwrap();
    writeln!(
        s,
        "$PhysicalNames\n2\n2 1 \"top\"\n3 2 \"soil\"\n$EndPhysicalNames"
    )
    .unwrap();
    writeln!(s, "$Entities\n0 0 1 1").unwrap();
    writeln!(s, "1 -1 -1 0 2 0 2 1 1 0").unwrap();
    writeln!(s, "1 -1 -1 0 2 0 2 1 2 1 1").unwrap();
    writeln!(s, "$EndEntities").unwrap();
    let n = mesh.nodes.len();
    writeln!(
        s,
        "$Nodes\n1 {n} {} {}\n3 1 0 {n}",
        node_tag(0),
        node_tag(n - 1)
    )
    .unwrap();
    for i in 0..n {
        writeln!(s, "{}", node_tag(i)).unwrap();
    }
    for p in &mesh.nodes {
        writeln!(s, "{:.17e} {:.17e} {:.17e}", p[0], p[1], p[2]).unwrap();
    }
    writeln!(s, "$EndNodes").unwrap();
    let total = tetrahedra.len() + top.len();
    writeln!(s, "$Elements\n2 {total} 1 {total}").unwrap();
    writeln!(s, "3 1 {tet_type} {}", tetrahedra.len()).unwrap();
    let mut tag = 1;
    for t in tetrahedra {
        let nodes: Vec<String> = t.iter().map(|&i| node_tag(i).to_string()).collect();
        writeln!(s, "{tag} {}", nodes.join(" ")).unwrap();
        tag += 1;
    }
    writeln!(s, "2 1 {tri_type} {}", top.len()).unwrap();
    for f in top {
        // inward: vertices 0 ↔ 1, and the mid nodes of edges 12 ↔ 20 follow.
        let mut v = f.nodes.clone();
        v.swap(0, 1);
        if v.len() == 6 {
            v.swap(4, 5);
        }
        let nodes: Vec<String> = v.iter().map(|&i| node_tag(i).to_string()).collect();
        writeln!(s, "{tag} {}", nodes.join(" ")).unwrap();
        tag += 1;
    }
    writeln!(s, "$EndElements").unwrap();
    s
}

pub fn block(order: ElementOrder) -> TetrahedralMesh {
    TetrahedralMesh::block(
        &[-1.0, 0.0, 2.0],
        &[-1.0, -0.5, 0.0],
        &[0.0, 1.0, 2.0],
        order,
    )
    .unwrap()
}
