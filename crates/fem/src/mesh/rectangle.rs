//! Structured rectangle meshes.
use std::collections::BTreeMap;

use super::{BoundaryEdge, Mesh};
use crate::element::ElementOrder;
use crate::error::MeshError;

/// Checks that a coordinate list is finite, strictly increasing and has ≥ 2 entries.
pub(crate) fn check_coordinates(field: &'static str, c: &[f64]) -> Result<(), MeshError> {
    if c.len() < 2 {
        return Err(MeshError::invalid(
            field,
            format!("needs at least 2 coordinates, got {}", c.len()),
        ));
    }
    if let Some((i, v)) = c.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(MeshError::invalid(field, format!("entry {i} is {v}")));
    }
    if let Some(i) = (1..c.len()).find(|&i| c[i] <= c[i - 1]) {
        return Err(MeshError::invalid(
            field,
            format!(
                "must be strictly increasing: entry {i} = {} after {}",
                c[i],
                c[i - 1]
            ),
        ));
    }
    Ok(())
}

impl Mesh {
    /// Structured mesh of `[xs₀, xs_last] × [ys₀, ys_last]` on the grid of the given
    /// (strictly increasing, metres) coordinates. Each cell is cut into two triangles along
    /// a diagonal that alternates like a chequerboard, so a mesh with an even number of
    /// columns is mirror-symmetric about its vertical mid line (a footing centred there
    /// sees no spurious asymmetry). P2 mid nodes sit at edge mid points.
    ///
    /// Node sets and edge sets `"left"`, `"right"`, `"bottom"`, `"top"` hold the nodes and
    /// edges of each side (corners belong to two sides); edges run counter-clockwise.
    /// There are no element sets.
    pub fn rectangle(xs: &[f64], ys: &[f64], order: ElementOrder) -> Result<Mesh, MeshError> {
        check_coordinates("xs", xs)?;
        check_coordinates("ys", ys)?;
        let (nx, ny) = (xs.len() - 1, ys.len() - 1);
        // P2 uses the grid refined by cell mid points; vertex (i, j) is refined (2i, 2j),
        // the mid point of any cell edge or diagonal is the mean of the refined indices.
        let s = match order {
            ElementOrder::P1 => 1,
            ElementOrder::P2 => 2,
        };
        let refine = |c: &[f64]| -> Vec<f64> {
            if s == 1 {
                return c.to_vec();
            }
            let mut r = Vec::with_capacity(2 * c.len() - 1);
            for w in c.windows(2) {
                r.push(w[0]);
                r.push(0.5 * (w[0] + w[1]));
            }
            r.push(c[c.len() - 1]);
            r
        };
        let (rx, ry) = (refine(xs), refine(ys));
        let cols = rx.len();
        let id = |i: usize, j: usize| j * cols + i;
        let nodes: Vec<[f64; 2]> = ry
            .iter()
            .flat_map(|&y| rx.iter().map(move |&x| [x, y]))
            .collect();
        // vertex grid index (i, j) -> refined (s·i, s·j); mid node of (a, b) by averaging.
        let vertex = |i: usize, j: usize| (s * i, s * j);
        let triangle = |v: [(usize, usize); 3]| -> Vec<usize> {
            let mut t: Vec<usize> = v.iter().map(|&(i, j)| id(i, j)).collect();
            if s == 2 {
                for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                    t.push(id((v[a].0 + v[b].0) / 2, (v[a].1 + v[b].1) / 2));
                }
            }
            t
        };
        let mut triangles = Vec::with_capacity(2 * nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                let (p00, p10, p11, p01) = (
                    vertex(i, j),
                    vertex(i + 1, j),
                    vertex(i + 1, j + 1),
                    vertex(i, j + 1),
                );
                if (i + j) % 2 == 0 {
                    // diagonal p00–p11
                    triangles.push(triangle([p00, p10, p11]));
                    triangles.push(triangle([p00, p11, p01]));
                } else {
                    // diagonal p10–p01
                    triangles.push(triangle([p00, p10, p01]));
                    triangles.push(triangle([p10, p11, p01]));
                }
            }
        }

        // Sides, each as a counter-clockwise polyline of refined indices.
        let (ci, cj) = (rx.len() - 1, ry.len() - 1);
        let sides: [(&str, Vec<(usize, usize)>); 4] = [
            ("bottom", (0..=ci).map(|i| (i, 0)).collect()),
            ("right", (0..=cj).map(|j| (ci, j)).collect()),
            ("top", (0..=ci).rev().map(|i| (i, cj)).collect()),
            ("left", (0..=cj).rev().map(|j| (0, j)).collect()),
        ];
        let mut node_sets = BTreeMap::new();
        let mut edge_sets = BTreeMap::new();
        for (name, line) in sides {
            let ids: Vec<usize> = line.iter().map(|&(i, j)| id(i, j)).collect();
            let mut sorted = ids.clone();
            sorted.sort_unstable();
            node_sets.insert(name.to_string(), sorted);
            let edges = ids
                .windows(s + 1)
                .step_by(s)
                .map(|w| BoundaryEdge {
                    // end points first, then the mid point (Gmsh Lin3 order)
                    nodes: if s == 1 {
                        vec![w[0], w[1]]
                    } else {
                        vec![w[0], w[2], w[1]]
                    },
                })
                .collect();
            edge_sets.insert(name.to_string(), edges);
        }
        Ok(Mesh {
            order,
            nodes,
            triangles,
            node_sets,
            edge_sets,
            element_sets: BTreeMap::new(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_sets() {
        let m = Mesh::rectangle(&[0.0, 1.0, 3.0], &[0.0, 2.0], ElementOrder::P1).unwrap();
        assert_eq!((m.nodes.len(), m.triangles.len()), (6, 4));
        assert_eq!(m.node_sets["bottom"], vec![0, 1, 2]);
        assert_eq!(m.node_sets["left"], vec![0, 3]);
        assert_eq!(m.edge_sets["top"].len(), 2);
        m.validate().unwrap();
        let m2 = Mesh::rectangle(&[0.0, 1.0, 3.0], &[0.0, 2.0], ElementOrder::P2).unwrap();
        assert_eq!((m2.nodes.len(), m2.triangles.len()), (15, 4));
        assert_eq!(m2.edge_sets["bottom"][1].nodes, vec![2, 4, 3]);
        m2.validate().unwrap();
    }

    #[test]
    fn even_columns_are_mirror_symmetric() {
        let xs = [0.0, 1.0, 2.0, 3.0, 4.0];
        let m = Mesh::rectangle(&xs, &[0.0, 1.0, 2.0], ElementOrder::P1).unwrap();
        let mirror = |p: [f64; 2]| [4.0 - p[0], p[1]];
        let key = |t: &[usize], f: &dyn Fn([f64; 2]) -> [f64; 2]| {
            let mut c: Vec<[i64; 2]> = t
                .iter()
                .map(|&n| {
                    let p = f(m.nodes[n]);
                    [(p[0] * 1e6).round() as i64, (p[1] * 1e6).round() as i64]
                })
                .collect();
            c.sort_unstable();
            c
        };
        let mut a: Vec<_> = m.triangles.iter().map(|t| key(t, &|p| p)).collect();
        let mut b: Vec<_> = m.triangles.iter().map(|t| key(t, &mirror)).collect();
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b);
    }

    #[test]
    fn rejects_bad_coordinates() {
        for xs in [&[0.0][..], &[0.0, 0.0], &[1.0, 0.0], &[0.0, f64::NAN]] {
            let e = Mesh::rectangle(xs, &[0.0, 1.0], ElementOrder::P1).unwrap_err();
            assert!(
                matches!(e, MeshError::InvalidInput { field: "xs", .. }),
                "{e}"
            );
        }
    }
}
