//! Consistent nodal loads: totals equal the applied resultant, and the per-node split
//! matches the textbook weights.
use crate::common;

use common::{distorted_rectangle, AREA};
use talus_fem::{
    graded_coordinates, Assembly, BoundaryEdge, Constraint, DofMap, ElementOrder, Mesh,
};

const ORDERS: [ElementOrder; 2] = [ElementOrder::P1, ElementOrder::P2];

fn totals(dofs: &DofMap, f: &(Vec<f64>, Vec<f64>)) -> [f64; 2] {
    let mut t = [0.0; 2];
    for n in 0..dofs.n_nodes() {
        for (c, tc) in t.iter_mut().enumerate() {
            *tc += match dofs.dof(n, c).unwrap() {
                talus_fem::Dof::Free(i) => f.0[i],
                talus_fem::Dof::Prescribed(j) => f.1[j],
            };
        }
    }
    t
}

#[test]
fn body_force_total_equals_weight() {
    let (rho, g) = (1900.0, [0.5, -9.81]);
    for order in ORDERS {
        let mesh = distorted_rectangle(order);
        let dofs = DofMap::new(
            mesh.nodes.len(),
            &[(mesh.node_sets["bottom"].clone(), Constraint::Fixed)],
        )
        .unwrap();
        let asm = Assembly::new(&mesh, &dofs, rho).unwrap();
        let f = asm.body_force(rho, g).unwrap();
        let t = totals(&dofs, &f);
        for c in 0..2 {
            let want = rho * g[c] * AREA;
            assert!((t[c] - want).abs() < 1e-9 * want.abs(), "{order:?}: {t:?}");
        }
        // weightless soil
        let zero = asm.body_force(0.0, g).unwrap();
        assert!(zero.0.iter().chain(&zero.1).all(|v| *v == 0.0));
    }
}

/// Consistent P2 gravity on an affine triangle: 0 at vertices, ρgA/3 at mid nodes.
#[test]
fn p2_body_force_skips_vertices() {
    let mesh = Mesh::rectangle(&[0.0, 2.0], &[0.0, 1.0], ElementOrder::P2).unwrap();
    let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
    let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
    let (f, _) = asm.body_force(1.0, [0.0, -3.0]).unwrap();
    let fy = |x: [f64; 2]| {
        f[dofs
            .free(mesh.nodes.iter().position(|p| *p == x).unwrap(), 1)
            .unwrap()]
    };
    assert!(fy([2.0, 0.0]).abs() < 1e-15);
    assert!((fy([1.0, 0.0]) - (-1.0)).abs() < 1e-14); // one triangle of area 1
    assert!((fy([1.0, 0.5]) - (-2.0)).abs() < 1e-14); // the diagonal: two triangles
}

#[test]
fn traction_total_equals_traction_times_length() {
    let t = [3.0e3, -5.0e3];
    // a graded top edge so that edges differ in length
    let xs = graded_coordinates(0.0, 4.0, 7, 1.0, 1.4).unwrap();
    for order in ORDERS {
        let mesh = Mesh::rectangle(&xs, &[0.0, 1.0, 2.0], order).unwrap();
        let dofs = DofMap::new(
            mesh.nodes.len(),
            &[(mesh.node_sets["top"][..3].to_vec(), Constraint::FixY)],
        )
        .unwrap();
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        let f = asm.traction(&mesh, &mesh.edge_sets["top"], t).unwrap();
        let total = totals(&dofs, &f);
        for c in 0..2 {
            assert!((total[c] - 4.0 * t[c]).abs() < 1e-9, "{order:?}: {total:?}");
        }
        // a box picks the same edges as the named set
        let boxed = mesh.boundary_edges_in_box([-1.0, 2.0], [5.0, 2.0]).unwrap();
        let f_box = asm.traction(&mesh, &boxed, t).unwrap();
        let tb = totals(&dofs, &f_box);
        assert!((tb[1] - 4.0 * t[1]).abs() < 1e-9);
    }
}

/// One straight edge of length L: P1 splits `t L` in halves, P2 as 1/6, 1/6, 2/3.
#[test]
fn traction_edge_weights_p1_halves_p2_sixths() {
    let len = 2.5;
    for (order, weights) in [
        (ElementOrder::P1, vec![0.5, 0.5]),
        (ElementOrder::P2, vec![1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0]),
    ] {
        let mesh = Mesh::rectangle(&[0.0, len], &[0.0, 1.0], order).unwrap();
        let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        let edge = &mesh.edge_sets["bottom"][0];
        let (f, _) = asm
            .traction(&mesh, std::slice::from_ref(edge), [0.0, 2.0])
            .unwrap();
        for (node, w) in edge.nodes.iter().zip(&weights) {
            let fy = f[dofs.free(*node, 1).unwrap()];
            assert!(
                (fy - w * 2.0 * len).abs() < 1e-14,
                "{order:?}: node {node}: {fy}"
            );
        }
    }
}

#[test]
fn loads_reject_bad_input() {
    let mesh = Mesh::rectangle(&[0.0, 1.0], &[0.0, 1.0], ElementOrder::P2).unwrap();
    let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
    let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
    let p1_edge = BoundaryEdge { nodes: vec![0, 1] };
    assert!(asm.traction(&mesh, &[p1_edge], [0.0, 1.0]).is_err());
    let far = BoundaryEdge {
        nodes: vec![0, 1, 999],
    };
    assert!(asm.traction(&mesh, &[far], [0.0, 1.0]).is_err());
    assert!(asm.traction(&mesh, &[], [f64::NAN, 1.0]).is_err());
    assert!(asm.body_force(-1.0, [0.0, -9.81]).is_err());
    assert!(asm.body_force(1.0, [0.0, f64::INFINITY]).is_err());
}

/// A 3-4-5 right triangle: traction on all boundary edges sums to `t` × perimeter (12 m),
/// slanted hypotenuse included (for P2 with its mid node on the edge).
#[test]
fn traction_on_slanted_edges_uses_true_length() {
    for order in ORDERS {
        let (nodes, tri) = match order {
            ElementOrder::P1 => (vec![[0.0, 0.0], [3.0, 0.0], [0.0, 4.0]], vec![0, 1, 2]),
            ElementOrder::P2 => (
                vec![
                    [0.0, 0.0],
                    [3.0, 0.0],
                    [0.0, 4.0],
                    [1.5, 0.0],
                    [1.5, 2.0],
                    [0.0, 2.0],
                ],
                vec![0, 1, 2, 3, 4, 5],
            ),
        };
        let mesh = Mesh {
            order,
            nodes,
            triangles: vec![tri],
            node_sets: Default::default(),
            edge_sets: Default::default(),
            element_sets: Default::default(),
        };
        let dofs = DofMap::new(mesh.nodes.len(), &[]).unwrap();
        let asm = Assembly::new(&mesh, &dofs, 1.0).unwrap();
        let edges = mesh.boundary_edges();
        assert_eq!(edges.len(), 3);
        let f = asm.traction(&mesh, &edges, [1.0, -2.0]).unwrap();
        let t = totals(&dofs, &f);
        assert!(
            (t[0] - 12.0).abs() < 1e-13 && (t[1] + 24.0).abs() < 1e-13,
            "{order:?}: {t:?}"
        );
    }
}
