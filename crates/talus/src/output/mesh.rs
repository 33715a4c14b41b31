//! The mesh snapshot shared by the VTU writer and the field plot, and the input checks
//! every writer runs before touching a file.
use super::OutputError;

/// A triangle mesh snapshot, node coordinates in m.
///
/// Each triangle is P1 (3 nodes) or P2 (6 nodes, Gmsh order: corners 0, 1, 2, then the
/// mid-edge nodes of edges 01, 12, 20), counter-clockwise. P1 and P2 may be mixed.
#[derive(Debug, Clone, Copy)]
pub struct MeshView<'a> {
    pub nodes: &'a [[f64; 2]],
    pub triangles: &'a [Vec<usize>],
}

impl MeshView<'_> {
    /// Non-empty, finite coordinates, 3 or 6 in-range node indices per triangle.
    pub(crate) fn validate(&self) -> Result<(), OutputError> {
        if self.nodes.is_empty() {
            return Err(OutputError::invalid("mesh.nodes", "the mesh has no nodes"));
        }
        if self.triangles.is_empty() {
            return Err(OutputError::invalid(
                "mesh.triangles",
                "the mesh has no triangles",
            ));
        }
        check_finite("mesh.nodes", self.nodes)?;
        for (e, tri) in self.triangles.iter().enumerate() {
            if tri.len() != 3 && tri.len() != 6 {
                return Err(OutputError::invalid(
                    "mesh.triangles",
                    format!("triangle {e} has {} nodes (expected 3 or 6)", tri.len()),
                ));
            }
            if let Some(&n) = tri.iter().find(|&&n| n >= self.nodes.len()) {
                return Err(OutputError::invalid(
                    "mesh.triangles",
                    format!(
                        "triangle {e} refers to node {n} but the mesh has {} nodes",
                        self.nodes.len()
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// The corner triangles to fill for one element: itself (P1), or its 4 sub-triangles
/// through the mid-edge nodes (P2), so that a curved deformed edge is followed.
pub(crate) fn linear_pieces(tri: &[usize]) -> Vec<[usize; 3]> {
    match *tri {
        [a, b, c, ab, bc, ca] => vec![[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]],
        [a, b, c, ..] => vec![[a, b, c]],
        _ => Vec::new(),
    }
}

/// `Invalid` unless `len == expected`; `what` names the unit ("nodes", "elements").
pub(crate) fn check_len(
    field: &'static str,
    len: usize,
    expected: usize,
    what: &str,
) -> Result<(), OutputError> {
    if len == expected {
        Ok(())
    } else {
        Err(OutputError::invalid(
            field,
            format!("has {len} entries, expected one per {what} ({expected})"),
        ))
    }
}

/// `Invalid` naming the first non-finite entry.
pub(crate) fn check_finite<const N: usize>(
    field: &'static str,
    data: &[[f64; N]],
) -> Result<(), OutputError> {
    match data.iter().position(|v| v.iter().any(|x| !x.is_finite())) {
        None => Ok(()),
        Some(i) => Err(OutputError::invalid(
            field,
            format!("entry {i} is not finite: {:?}", data[i]),
        )),
    }
}

/// `Invalid` naming the first non-finite scalar.
pub(crate) fn check_finite_scalars(field: &'static str, data: &[f64]) -> Result<(), OutputError> {
    match data.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(i) => Err(OutputError::invalid(
            field,
            format!("entry {i} is not finite: {}", data[i]),
        )),
    }
}

/// `Invalid` unless the single value `v` is finite.
pub(crate) fn check_finite_value(field: &'static str, v: f64) -> Result<(), OutputError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(OutputError::invalid(field, format!("is not finite: {v}")))
    }
}
