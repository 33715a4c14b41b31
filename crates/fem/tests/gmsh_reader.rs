//! Gmsh `.msh` 4.1 reader on small hand-written files.
//!
//! ```text
//!  P1 (Tri3)                 P2 (Tri6)
//!  4-----------3             4-----7-----3
//!  | \   e4  / |             |       ⁄   |
//!  |  \     /  |             8     9     6
//!  |e5  5     e3             |  ⁄        |
//!  |  /     \  |             1-----5-----2
//!  | /  e2   \ |
//!  1-----------2       "bottom" = edge 1–2 (dim 1), "domain" = the square (dim 2)
//! ```
use talus_fem::{Assembly, DofMap, ElementOrder, Mesh, MeshError};

use crate::common;
use common::gmsh_square::{binary_square, p1_file, p2_file, P1_TRIANGLES};

#[test]
fn gmsh_tri3_square_gives_p1_mesh_with_named_sets() {
    let mesh = Mesh::from_msh_bytes(p1_file(P1_TRIANGLES).as_bytes()).unwrap();
    assert_eq!(mesh.order, ElementOrder::P1);
    assert_eq!(mesh.nodes.len(), 5);
    assert_eq!(mesh.nodes[4], [0.5, 0.5]);
    assert_eq!(
        mesh.triangles,
        vec![vec![0, 1, 4], vec![1, 2, 4], vec![2, 3, 4], vec![3, 0, 4]]
    );
    assert_eq!(mesh.node_sets["bottom"], vec![0, 1]);
    assert_eq!(mesh.node_sets["corner"], vec![1]);
    assert_eq!(mesh.edge_sets["bottom"].len(), 1);
    assert_eq!(mesh.edge_sets["bottom"][0].nodes, vec![0, 1]);
    assert!(!mesh.node_sets.contains_key("domain"));
    let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
    let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
    assert!((asm.gauss_volumes.iter().sum::<f64>() - 1.0).abs() < 1e-15);
}

#[test]
fn gmsh_tri6_square_gives_p2_mesh() {
    let mesh = Mesh::from_msh_bytes(p2_file().as_bytes()).unwrap();
    assert_eq!(mesh.order, ElementOrder::P2);
    assert_eq!(mesh.nodes.len(), 9);
    assert_eq!(mesh.triangles[1], vec![0, 2, 3, 8, 6, 7]);
    assert_eq!(mesh.edge_sets["bottom"][0].nodes, vec![0, 1, 4]);
    assert_eq!(mesh.node_sets["bottom"], vec![0, 1, 4]);
    let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
    let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
    assert!((asm.gauss_volumes.iter().sum::<f64>() - 1.0).abs() < 1e-15);
}

#[test]
fn gmsh_file_on_disk() {
    let path = std::env::temp_dir().join(format!("talus_fem_square_{}.msh", std::process::id()));
    std::fs::write(&path, p1_file(P1_TRIANGLES)).unwrap();
    let mesh = Mesh::from_msh(&path);
    std::fs::remove_file(&path).ok();
    assert_eq!(mesh.unwrap().triangles.len(), 4);
    let missing = Mesh::from_msh(std::path::Path::new("/nonexistent/square.msh")).unwrap_err();
    assert!(matches!(missing, MeshError::Io { .. }), "{missing}");
}

#[test]
fn gmsh_inverted_element_is_named_by_tag() {
    // element 4 listed clockwise
    let tris = P1_TRIANGLES.replace("4 3 4 5", "4 4 3 5");
    let err = Mesh::from_msh_bytes(p1_file(&tris).as_bytes()).unwrap_err();
    assert!(err.to_string().contains("Gmsh element 4"), "{err}");
    assert!(err.to_string().contains("inverted"), "{err}");
    // zero area: node 5 moved onto the edge 1–2
    let flat = p1_file(P1_TRIANGLES).replace("0.5 0.5 0\n", "0.5 0 0\n");
    let err = Mesh::from_msh_bytes(flat.as_bytes()).unwrap_err();
    assert!(err.to_string().contains("Gmsh element 2"), "{err}");
}

#[test]
fn gmsh_missing_node_is_named() {
    let tris = P1_TRIANGLES.replace("3 2 3 5", "3 2 3 7");
    let err = Mesh::from_msh_bytes(p1_file(&tris).as_bytes()).unwrap_err();
    assert!(
        err.to_string().contains("Gmsh element 3") && err.to_string().contains("node 7"),
        "{err}"
    );
}

#[test]
fn gmsh_repeated_node_tags_are_errors() {
    // Within a block: tags 1 2 3 4 4.
    let text = p1_file(P1_TRIANGLES).replace("1\n2\n3\n4\n5\n", "1\n2\n3\n4\n4\n");
    let err = Mesh::from_msh_bytes(text.as_bytes()).unwrap_err();
    assert!(
        err.to_string().contains("node tag 4 is given twice"),
        "{err}"
    );
    // Across blocks: the square's five nodes, then a point block re-using tag 2.
    let text = p1_file(P1_TRIANGLES)
        .replace("$Nodes\n1 5 1 5\n", "$Nodes\n2 6 1 5\n")
        .replace(
            "0.5 0.5 0\n$EndNodes",
            "0.5 0.5 0\n0 1 0 1\n2\n1 0 0\n$EndNodes",
        );
    let err = Mesh::from_msh_bytes(text.as_bytes()).unwrap_err();
    assert!(
        err.to_string().contains("node tag 2 is given twice"),
        "{err}"
    );
}

#[test]
fn gmsh_mixed_orders_are_rejected() {
    // a Tri6 block after the Tri3 block (reusing nodes; only the type matters)
    let text = p1_file(P1_TRIANGLES)
        .replace("3 6 1 6", "4 7 1 7")
        .replace("$EndElements", "2 1 9 1\n7 1 2 3 4 5 1\n$EndElements");
    let err = Mesh::from_msh_bytes(text.as_bytes()).unwrap_err();
    assert!(err.to_string().contains("mixed"), "{err}");
    assert!(err.to_string().contains("Gmsh element 7"), "{err}");
}

#[test]
fn gmsh_truncated_file_is_an_error_not_a_panic() {
    let text = p1_file(P1_TRIANGLES);
    let bytes = text.as_bytes();
    // every prefix that cuts into the last section
    for len in 0..bytes.len() - 1 {
        let r = Mesh::from_msh_bytes(&bytes[..len]);
        assert!(r.is_err(), "prefix of {len} bytes parsed");
    }
    let err = Mesh::from_msh_bytes(&bytes[..bytes.len() / 2]).unwrap_err();
    assert!(matches!(err, MeshError::Msh { .. }), "{err}");
}

#[test]
fn gmsh_bad_headers_are_errors() {
    for text in [
        "",
        "hello",
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n",
        "$MeshFormat\n4.1 7 8\n$EndMeshFormat\n",
        "$MeshFormat\n4.1 0 3\n$EndMeshFormat\n",
        "$MeshFormat\n4.1 0\n$EndMeshFormat\n",
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n",
    ] {
        assert!(Mesh::from_msh_bytes(text.as_bytes()).is_err(), "{text:?}");
    }
    let z = p1_file(P1_TRIANGLES).replace("0.5 0.5 0\n", "0.5 0.5 0.25\n");
    let err = Mesh::from_msh_bytes(z.as_bytes()).unwrap_err();
    assert!(err.to_string().contains("z = 0.25"), "{err}");
}

/// Found by `fuzz_msh_reader.rs`: P2 triangles whose corners run clockwise passed when
/// det J was positive at the vertices and Gauss points (the mid-edge nodes bend the element
/// over itself). Here the coordinates of the square's nodes 3..8 are shifted by one line, as
/// by a line deleted and another duplicated.
#[test]
fn gmsh_p2_triangle_with_clockwise_corners_is_named() {
    let coordinates = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0 0\n1 0.5 0\n0.5 1 0\n0 0.5 0\n0.5 0.5 0\n";
    assert!(p2_file().contains(coordinates), "test setup");
    let lines: Vec<&str> = coordinates.lines().collect();
    let mut accepted = Vec::new();
    for dup in 0..9 {
        for del in 0..9 {
            let mut l: Vec<&str> = lines.clone();
            l.insert(dup + 1, lines[dup]);
            l.remove(if del > dup { del + 1 } else { del });
            let shifted = l.join("\n") + "\n";
            let text = p2_file().replace(coordinates, &shifted);
            if let Ok(mesh) = Mesh::from_msh_bytes(text.as_bytes()) {
                for t in &mesh.triangles {
                    let [a, b, c] = [mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]]];
                    let area = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
                    if area.is_nan() || area <= 0.0 {
                        accepted.push((dup, del, area / 2.0));
                    }
                }
            }
        }
    }
    assert!(
        accepted.is_empty(),
        "(duplicated, deleted, corner area): {accepted:?}"
    );
    // Node 2's line deleted, node 9's duplicated: element 3's corners (0,0), (0,1), (0.5,0).
    let shifted = "0 0 0\n1 1 0\n0 1 0\n0.5 0 0\n1 0.5 0\n0.5 1 0\n0 0.5 0\n0.5 0.5 0\n0.5 0.5 0\n";
    let err = Mesh::from_msh_bytes(p2_file().replace(coordinates, shifted).as_bytes())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("Gmsh element 3") && err.contains("counter-clockwise"),
        "{err}"
    );
}

/// Found by `fuzz_msh_reader.rs`: the centre node of the P1 square moved to
/// (0.5, 4.9e-324) left element 2 with an area of 2.5e-324 m², positive in det J but below
/// the round-off of its sides.
#[test]
fn gmsh_triangle_with_an_area_below_round_off_is_refused() {
    let text = p1_file(P1_TRIANGLES).replace("0.5 0.5 0\n", "0.5 4.9e-324 0\n");
    let err = Mesh::from_msh_bytes(text.as_bytes())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("Gmsh element 2") && err.contains("round-off"),
        "{err}"
    );
    // A thin but honest triangle (height 1e-6 of its base) is kept.
    let text = p1_file(P1_TRIANGLES).replace("0.5 0.5 0\n", "0.5 1e-6 0\n");
    assert!(Mesh::from_msh_bytes(text.as_bytes()).is_ok());
}

/// Found by `fuzz_msh_reader.rs`: node 1 moved to (0, -0.5) and the mid-edge node 6 to
/// x = 2147483647 gave a P2 triangle with det J > 0 at its vertices and stiffness points but
/// not at a mass quadrature point: read, then refused by the assembly ("det J ≤ 0 at mass
/// quadrature point").
#[test]
fn gmsh_p2_triangle_folded_at_a_mass_point_is_refused_by_the_reader() {
    let text = p2_file()
        .replace("\n0 0 0\n1 0 0\n", "\n0 -0.5 0\n1 0 0\n")
        .replace("1 0.5 0\n", "2147483647 0.5 0\n");
    if let Ok(mesh) = Mesh::from_msh_bytes(text.as_bytes()) {
        let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
        panic!(
            "read; assembly: {:?}",
            Assembly::new(&mesh, &dofs, 1.0).map(|_| ())
        );
    }
    let err = Mesh::from_msh_bytes(text.as_bytes())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("Gmsh element") && err.contains("inverted or degenerate"),
        "{err}"
    );
}

/// Found by `fuzz_msh_reader.rs`: an `$EndPhysicalNames` line before `$PhysicalNames`
/// panicked (a slice from the start of the section to an end before it).
#[test]
fn gmsh_physical_names_end_before_start_is_an_error() {
    let text = p1_file(P1_TRIANGLES).replacen(
        "$EndMeshFormat\n$PhysicalNames\n",
        "$EndMeshFormat\n$EndPhysicalNames\n$PhysicalNames\n",
        1,
    );
    // The real end follows; the stray line is then refused by the section parser.
    assert!(Mesh::from_msh_bytes(text.as_bytes()).is_err());
    let text = text.replacen("$EndPhysicalNames\n$Entities", "$Entities", 1);
    let err = Mesh::from_msh_bytes(text.as_bytes())
        .unwrap_err()
        .to_string();
    assert!(err.contains("no $EndPhysicalNames after it"), "{err}");
}

/// Found by `fuzz_msh_reader.rs`: a node at x = 1e300 was accepted, and the assembly then
/// failed with "node 0 has mass inf (does it belong to a triangle?)".
#[test]
fn gmsh_huge_or_non_finite_coordinates_are_named() {
    for (x, shown) in [
        ("1e300", "1e300"),
        ("-1e101", "-1e101"),
        ("inf", "inf"),
        ("nan", "NaN"),
    ] {
        let text = p1_file(P1_TRIANGLES).replace("0.5 0.5 0\n", &format!("{x} 0.5 0\n"));
        let err = Mesh::from_msh_bytes(text.as_bytes())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(&format!("node 5 has (x, y) = ({shown}, 5e-1)")) && err.contains("1e100"),
            "{x}: {err}"
        );
    }
}

/// The P1 square in binary (`common::gmsh_square::binary_square`) reads as the ASCII one.
#[test]
fn gmsh_binary_square_matches_ascii() {
    let b = binary_square();
    let binary = Mesh::from_msh_bytes(&b).unwrap();
    let ascii = Mesh::from_msh_bytes(p1_file(P1_TRIANGLES).as_bytes()).unwrap();
    assert_eq!(binary.nodes, ascii.nodes);
    assert_eq!(binary.triangles, ascii.triangles);
    assert_eq!(binary.edge_sets["bottom"], ascii.edge_sets["bottom"]);
    // a truncated binary file is an error too
    for len in [b.len() / 3, b.len() / 2, b.len() - 20] {
        assert!(Mesh::from_msh_bytes(&b[..len]).is_err());
    }
}
