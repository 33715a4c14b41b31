//! Dirichlet bookkeeping and box selections.
use talus_fem::{Assembly, Constraint, Dof, DofMap, ElementOrder, FemError, Mesh, MeshError};

/// A 3 × 2-cell box with a smooth base (FixY), rollers on both sides (FixX): the corners
/// are fully fixed, and the prescribed columns of `B` are exactly the constrained dofs.
#[test]
fn dofmap_counts_fixed_and_rollers() {
    for (order, nodes_per_side_x, nodes_per_side_y) in
        [(ElementOrder::P1, 4, 3), (ElementOrder::P2, 7, 5)]
    {
        let mesh = Mesh::rectangle(&[0.0, 1.0, 2.0, 3.0], &[0.0, 1.0, 2.0], order).unwrap();
        let n = mesh.nodes.len();
        let dofs = DofMap::new(
            n,
            &[
                (mesh.node_sets["bottom"].clone(), Constraint::FixY),
                (mesh.node_sets["left"].clone(), Constraint::FixX),
                (mesh.node_sets["right"].clone(), Constraint::FixX),
            ],
        )
        .unwrap();
        // y fixed on the base, x on both sides (corners counted once per component)
        let n_prescribed = nodes_per_side_x + 2 * nodes_per_side_y;
        assert_eq!(dofs.n_prescribed(), n_prescribed, "{order:?}");
        assert_eq!(dofs.n_free() + dofs.n_prescribed(), 2 * n);
        let corner = mesh.node_sets["bottom"][0];
        assert!(dofs.prescribed(corner, 0).is_some() && dofs.prescribed(corner, 1).is_some());
        let side = mesh.node_sets["left"][1];
        assert!(dofs.prescribed(side, 0).is_some() && dofs.free(side, 1).is_some());
        assert_eq!(dofs.dof(n, 0), None);
        assert_eq!(dofs.dof(0, 2), None);

        // Prescribed column j of B is the column of (node, comp) in the unconstrained B.
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        let all = DofMap::new(n, &[]).unwrap();
        let full = Assembly::new(&mesh, &all, 1.0).unwrap();
        let column = |b: &faer::sparse::SparseColMat<usize, f64>, j: usize| -> Vec<(usize, f64)> {
            let (cp, ri, v) = (b.symbolic().col_ptr(), b.symbolic().row_idx(), b.val());
            (cp[j]..cp[j + 1]).map(|k| (ri[k], v[k])).collect()
        };
        assert_eq!(asm.b_prescribed.ncols(), dofs.n_prescribed());
        assert_eq!(asm.b_free.ncols(), dofs.n_free());
        for node in 0..n {
            for comp in 0..2 {
                let reference = column(&full.b_free, all.free(node, comp).unwrap());
                let mine = match dofs.dof(node, comp).unwrap() {
                    Dof::Free(i) => column(&asm.b_free, i),
                    Dof::Prescribed(j) => {
                        assert_eq!(dofs.prescribed_dofs()[j], (node, comp));
                        column(&asm.b_prescribed, j)
                    }
                };
                assert_eq!(mine, reference, "{order:?}: node {node}, comp {comp}");
            }
        }
    }
}

#[test]
fn dofmap_rejects_unknown_nodes_and_assembly_checks_sizes() {
    let err = DofMap::new(4, &[(vec![1, 7], Constraint::Fixed)]).unwrap_err();
    assert!(err.to_string().contains("node 7"), "{err}");
    let mesh = Mesh::rectangle(&[0.0, 1.0], &[0.0, 1.0], ElementOrder::P1).unwrap();
    let dofs = DofMap::new(3, &[]).unwrap();
    assert!(matches!(
        Assembly::new(&mesh, &dofs, 1.0),
        Err(FemError::InvalidInput { field: "dofs", .. })
    ));
    let dofs = DofMap::new(4, &[]).unwrap();
    for density in [0.0, -1.0, f64::NAN] {
        let err = Assembly::new(&mesh, &dofs, density).unwrap_err();
        assert!(
            matches!(
                err,
                FemError::InvalidInput {
                    field: "density",
                    ..
                }
            ),
            "{err}"
        );
    }
}

#[test]
fn assembly_rejects_inverted_and_orphan_nodes() {
    let mut mesh = Mesh::rectangle(&[0.0, 1.0], &[0.0, 1.0], ElementOrder::P1).unwrap();
    mesh.triangles[1].swap(0, 1);
    let dofs = DofMap::new(4, &[]).unwrap();
    let err = Assembly::new(&mesh, &dofs, 1.0).unwrap_err();
    assert!(err.to_string().contains("triangle 1"), "{err}");

    // a P2 mid node pushed across the opposite vertex folds the element inside
    let mut p2 = Mesh::rectangle(&[0.0, 1.0], &[0.0, 1.0], ElementOrder::P2).unwrap();
    let mid = p2.triangles[0][3];
    p2.nodes[mid] = [0.5, 0.9];
    assert!(p2.validate().is_err());

    let mut orphan = Mesh::rectangle(&[0.0, 1.0], &[0.0, 1.0], ElementOrder::P1).unwrap();
    orphan.nodes.push([5.0, 5.0]);
    let dofs = DofMap::new(5, &[]).unwrap();
    let err = Assembly::new(&orphan, &dofs, 1.0).unwrap_err();
    assert!(err.to_string().contains("node 4"), "{err}");

    let mut nan = Mesh::rectangle(&[0.0, 1.0], &[0.0, 1.0], ElementOrder::P1).unwrap();
    nan.nodes[2][0] = f64::NAN;
    assert!(Assembly::new(&nan, &DofMap::new(4, &[]).unwrap(), 1.0).is_err());
}

#[test]
fn boxes_select_nodes_and_boundary_edges() {
    let mesh = Mesh::rectangle(&[0.0, 0.5, 1.0, 2.0], &[0.0, 1.0, 2.0], ElementOrder::P2).unwrap();
    // a footing on the top, 0 ≤ x ≤ 1
    let nodes = mesh.nodes_in_box([0.0, 2.0], [1.0, 2.0]).unwrap();
    assert_eq!(nodes.len(), 5);
    assert!(nodes
        .iter()
        .all(|&n| mesh.nodes[n][1] == 2.0 && mesh.nodes[n][0] <= 1.0));
    let edges = mesh.boundary_edges_in_box([0.0, 2.0], [1.0, 2.0]).unwrap();
    assert_eq!(edges.len(), 2);
    assert_eq!(mesh.boundary_edges().len(), 2 * (3 + 2));
    // counter-clockwise: the top runs from right to left
    for e in &edges {
        assert!(mesh.nodes[e.nodes[0]][0] > mesh.nodes[e.nodes[1]][0]);
    }
    assert!(matches!(
        mesh.nodes_in_box([5.0, 5.0], [6.0, 6.0]),
        Err(MeshError::EmptyBox { .. })
    ));
    assert!(matches!(
        mesh.nodes_in_box([1.0, 0.0], [0.0, 1.0]),
        Err(MeshError::InvalidInput { field: "box", .. })
    ));
    assert!(mesh.nodes_in_box([f64::NAN, 0.0], [1.0, 1.0]).is_err());
    // interior segment: nodes but no boundary edge
    assert!(mesh.boundary_edges_in_box([0.0, 1.0], [2.0, 1.0]).is_err());
}

/// A 3D box (`TetrahedralMesh::block`) with rollers on its six sides, as a slab in plane
/// strain or a soil box has: every combination of `Constraint` fixes exactly its axes,
/// counts match the sides' node sets, and the numbering stays node-major.
#[test]
fn dofmap_in_3d_fixes_exactly_the_named_axes() {
    use talus_fem::TetrahedralMesh;
    let mesh = TetrahedralMesh::block(
        &[0.0, 1.0, 2.0],
        &[0.0, 1.0],
        &[0.0, 0.5, 1.0],
        ElementOrder::P2,
    )
    .unwrap();
    let n = mesh.nodes.len();
    let set = |name: &str| mesh.node_sets[name].clone();
    let cases: [(Constraint, [bool; 3]); 7] = [
        (Constraint::Fixed, [true, true, true]),
        (Constraint::FixX, [true, false, false]),
        (Constraint::FixY, [false, true, false]),
        (Constraint::FixZ, [false, false, true]),
        (Constraint::FixXY, [true, true, false]),
        (Constraint::FixXZ, [true, false, true]),
        (Constraint::FixYZ, [false, true, true]),
    ];
    for (c, axes) in cases {
        let dofs = DofMap::with_components(n, 3, &[(set("bottom"), c)]).unwrap();
        assert_eq!(dofs.components(), 3);
        assert_eq!(dofs.n_nodes(), n);
        let bottom = set("bottom");
        let fixed = axes.iter().filter(|a| **a).count();
        assert_eq!(dofs.n_prescribed(), fixed * bottom.len(), "{c:?}");
        assert_eq!(dofs.n_free() + dofs.n_prescribed(), 3 * n);
        for &node in &bottom {
            for (comp, &f) in axes.iter().enumerate() {
                assert_eq!(
                    dofs.prescribed(node, comp).is_some(),
                    f,
                    "{c:?} node {node}"
                );
            }
        }
        assert_eq!(dofs.dof(0, 3), None, "no fourth component");
    }
    // Rollers on all six sides: a node on an edge of the box gets both sides' axes.
    let rollers = [
        (set("left"), Constraint::FixX),
        (set("right"), Constraint::FixX),
        (set("bottom"), Constraint::FixY),
        (set("back"), Constraint::FixZ),
        (set("front"), Constraint::FixZ),
    ];
    let dofs = DofMap::with_components(n, 3, &rollers).unwrap();
    let corner = *set("left")
        .iter()
        .find(|i| set("bottom").contains(i) && set("back").contains(i))
        .unwrap();
    assert!((0..3).all(|c| dofs.prescribed(corner, c).is_some()));
    // Node-major numbering of the free dofs: first free node's components come first.
    let free: Vec<usize> = (0..n)
        .flat_map(|node| (0..3).map(move |c| (node, c)))
        .filter_map(|(node, c)| dofs.free(node, c))
        .collect();
    assert!(free.windows(2).all(|w| w[1] == w[0] + 1));
    // Scattering puts each value back on its node and axis.
    let values: Vec<f64> = (0..dofs.n_free()).map(|i| i as f64).collect();
    let prescribed = vec![-1.0; dofs.n_prescribed()];
    let v = dofs.nodal_vectors::<3>(&values, &prescribed).unwrap();
    assert_eq!(v.len(), n);
    for (node, vn) in v.iter().enumerate() {
        for c in 0..3 {
            let expected = dofs.free(node, c).map_or(-1.0, |i| i as f64);
            assert_eq!(vn[c], expected);
        }
    }
    assert!(
        dofs.scatter(&values, &prescribed).is_err(),
        "2D scatter of a 3D map"
    );
}

#[test]
fn a_2d_dofmap_refuses_z_and_other_component_counts() {
    for c in [Constraint::FixZ, Constraint::FixXZ, Constraint::FixYZ] {
        let err = DofMap::new(4, &[(vec![0, 1], c)]).unwrap_err();
        assert!(
            matches!(&err, FemError::InvalidInput { field: "constraints", reason } if reason.contains("fixes z")),
            "{err}"
        );
    }
    // In 2D, FixXY is Fixed.
    let a = DofMap::new(3, &[(vec![1], Constraint::FixXY)]).unwrap();
    let b = DofMap::new(3, &[(vec![1], Constraint::Fixed)]).unwrap();
    assert_eq!(a, b);
    let err = DofMap::with_components(3, 4, &[]).unwrap_err();
    assert!(
        matches!(
            err,
            FemError::InvalidInput {
                field: "components",
                ..
            }
        ),
        "{err}"
    );
}
