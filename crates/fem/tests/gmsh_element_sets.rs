//! Gmsh physical surfaces become element sets (`Mesh::element_sets`): the two-layer square
//! of `common/gmsh_layers.rs` ("sand" below y = 0.5, "clay" above, an unnamed physical
//! surface 7 over both), read from ASCII and from binary; the sets are checked by the
//! centroids of their triangles, so a set built from the wrong blocks or entities fails.
use std::collections::BTreeMap;

use talus_fem::{ElementOrder, Mesh, MeshError};

use crate::common;
use crate::gmsh_layers;
use common::gmsh_square::{binary_square, p1_file, p2_file, P1_TRIANGLES};

/// Centroids of the triangles of `set`, sorted, rounded to 1e-12 m.
fn centroids(mesh: &Mesh, set: &[usize]) -> Vec<[i64; 2]> {
    let mut c: Vec<[i64; 2]> = set
        .iter()
        .map(|&e| {
            let t = &mesh.triangles[e];
            let mean = |k: usize| t[..3].iter().map(|&n| mesh.nodes[n][k]).sum::<f64>() / 3.0;
            [
                (mean(0) * 1e12).round() as i64,
                (mean(1) * 1e12).round() as i64,
            ]
        })
        .collect();
    c.sort_unstable();
    c
}

fn expected(points: &[[f64; 2]]) -> Vec<[i64; 2]> {
    let mut c: Vec<[i64; 2]> = points
        .iter()
        .map(|p| [(p[0] * 1e12).round() as i64, (p[1] * 1e12).round() as i64])
        .collect();
    c.sort_unstable();
    c
}

/// The centroids of the lower half's four triangles (drawing in `gmsh_layers.rs`); the
/// upper half's are these shifted up by 0.5.
const SAND: [[f64; 2]; 4] = [
    [1.0 / 3.0, 1.0 / 6.0],
    [1.0 / 6.0, 1.0 / 3.0],
    [5.0 / 6.0, 1.0 / 6.0],
    [2.0 / 3.0, 1.0 / 3.0],
];

fn check_layers(mesh: &Mesh, encoding: &str) {
    assert_eq!(mesh.order, ElementOrder::P1, "{encoding}");
    assert_eq!(mesh.triangles.len(), 8, "{encoding}");
    let names: Vec<&str> = mesh.element_sets.keys().map(String::as_str).collect();
    assert_eq!(names, ["clay", "physical_2_7", "sand"], "{encoding}");
    // File order: sand block (2 triangles), clay block (4), sand block (2).
    assert_eq!(mesh.element_sets["sand"], vec![0, 1, 6, 7], "{encoding}");
    assert_eq!(mesh.element_sets["clay"], vec![2, 3, 4, 5], "{encoding}");
    // The unnamed group holds both surfaces: every triangle is in two sets.
    assert_eq!(
        mesh.element_sets["physical_2_7"],
        (0..8).collect::<Vec<_>>(),
        "{encoding}"
    );
    let clay: Vec<[f64; 2]> = SAND.iter().map(|p| [p[0], p[1] + 0.5]).collect();
    assert_eq!(
        centroids(mesh, &mesh.element_sets["sand"]),
        expected(&SAND),
        "{encoding}: sand"
    );
    assert_eq!(
        centroids(mesh, &mesh.element_sets["clay"]),
        expected(&clay),
        "{encoding}: clay"
    );
    // The 1D group is still a node and an edge set, and no 2D group is a node set.
    assert_eq!(mesh.node_sets.keys().collect::<Vec<_>>(), ["bottom"]);
    assert_eq!(mesh.edge_sets["bottom"].len(), 2, "{encoding}");
    mesh.validate().unwrap();
}

#[test]
fn gmsh_physical_surfaces_become_element_sets_ascii() {
    let mesh = Mesh::from_msh_bytes(gmsh_layers::layers().ascii().as_bytes()).unwrap();
    check_layers(&mesh, "ASCII");
}

#[test]
fn gmsh_physical_surfaces_become_element_sets_binary() {
    let fixture = gmsh_layers::layers();
    let binary = Mesh::from_msh_bytes(&fixture.binary()).unwrap();
    check_layers(&binary, "binary");
    let ascii = Mesh::from_msh_bytes(fixture.ascii().as_bytes()).unwrap();
    assert_eq!(binary, ascii);
}

/// A surface in no physical group leaves its triangles in no set; a surface listed in a
/// group twice does not repeat them.
#[test]
fn gmsh_surface_without_group_gives_no_set_and_repeats_are_merged() {
    let mut fixture = gmsh_layers::layers();
    fixture.surfaces[1].1.clear(); // clay: no physical group
    fixture.surfaces[0].1 = vec![1, 1, 7]; // sand listed twice in group 1
    for mesh in [
        Mesh::from_msh_bytes(fixture.ascii().as_bytes()).unwrap(),
        Mesh::from_msh_bytes(&fixture.binary()).unwrap(),
    ] {
        assert_eq!(mesh.triangles.len(), 8);
        assert_eq!(
            mesh.element_sets,
            BTreeMap::from([
                ("physical_2_7".to_string(), vec![0, 1, 6, 7]),
                ("sand".to_string(), vec![0, 1, 6, 7]),
            ])
        );
    }
}

/// The reader tests' square (`common/gmsh_square.rs`) has the physical surface "domain"
/// over its one surface (P1 and P2 files); the binary square's surface has none.
#[test]
fn gmsh_square_domain_is_an_element_set() {
    let p1 = Mesh::from_msh_bytes(p1_file(P1_TRIANGLES).as_bytes()).unwrap();
    assert_eq!(
        p1.element_sets,
        BTreeMap::from([("domain".to_string(), vec![0, 1, 2, 3])])
    );
    let p2 = Mesh::from_msh_bytes(p2_file().as_bytes()).unwrap();
    assert_eq!(
        p2.element_sets,
        BTreeMap::from([("domain".to_string(), vec![0, 1])])
    );
    assert!(Mesh::from_msh_bytes(&binary_square())
        .unwrap()
        .element_sets
        .is_empty());
}

#[test]
fn rectangle_has_no_element_sets() {
    for order in [ElementOrder::P1, ElementOrder::P2] {
        let mesh = Mesh::rectangle(&[0.0, 1.0, 2.0], &[0.0, 1.0], order).unwrap();
        assert!(mesh.element_sets.is_empty(), "{order:?}");
    }
}

/// `validate` refuses an element set naming a triangle the mesh does not have.
#[test]
fn element_set_out_of_range_is_refused_by_validate() {
    let mut mesh = Mesh::rectangle(&[0.0, 1.0, 2.0], &[0.0, 1.0], ElementOrder::P1).unwrap();
    mesh.element_sets.insert("clay".to_string(), vec![0, 3]);
    mesh.validate().unwrap();
    mesh.element_sets.insert("clay".to_string(), vec![0, 4]);
    let err = mesh.validate().unwrap_err();
    assert!(
        matches!(
            err,
            MeshError::InvalidInput {
                field: "element_sets",
                ..
            }
        ),
        "{err}"
    );
    assert!(
        err.to_string().contains("\"clay\"") && err.to_string().contains("triangle 4"),
        "{err}"
    );
}
