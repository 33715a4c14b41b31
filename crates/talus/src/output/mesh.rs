//! The mesh snapshot shared by the VTU writer and the field plot, and the input checks
//! every writer runs before touching a file.
use super::OutputError;

/// A mesh snapshot, node coordinates in m: triangles in the plane (`N = 2`, the default)
/// or tetrahedra in space (`N = 3`).
///
/// Each triangle is P1 (3 nodes) or P2 (6 nodes, Gmsh order: corners 0, 1, 2, then the
/// mid-edge nodes of edges 01, 12, 20), counter-clockwise; each tetrahedron P1 (4 nodes)
/// or P2 (10 nodes, Gmsh order: vertices, then edges 01, 12, 20, 30, 32, 31). Orders may be
/// mixed.
#[derive(Debug, Clone, Copy)]
pub struct MeshView<'a, const N: usize = 2> {
    pub nodes: &'a [[f64; N]],
    pub elements: &'a [Vec<usize>],
}

impl<const N: usize> MeshView<'_, N> {
    /// The node counts of a P1 and a P2 element: triangles in 2D, tetrahedra in 3D.
    pub(crate) const NODES_PER_ELEMENT: [usize; 2] = if N == 3 { [4, 10] } else { [3, 6] };

    /// Non-empty, finite coordinates, a P1 or P2 element's node count of in-range node
    /// indices per element.
    pub(crate) fn validate(&self) -> Result<(), OutputError> {
        let kind = if N == 3 { "tetrahedr" } else { "triangle" };
        let [p1, p2] = Self::NODES_PER_ELEMENT;
        if self.nodes.is_empty() {
            return Err(OutputError::invalid("mesh.nodes", "the mesh has no nodes"));
        }
        if self.elements.is_empty() {
            return Err(OutputError::invalid(
                "mesh.elements",
                "the mesh has no elements",
            ));
        }
        check_finite("mesh.nodes", self.nodes)?;
        for (e, element) in self.elements.iter().enumerate() {
            if element.len() != p1 && element.len() != p2 {
                return Err(OutputError::invalid(
                    "mesh.elements",
                    format!(
                        "element {e} has {} nodes (expected {p1} or {p2}: {kind}{})",
                        element.len(),
                        if N == 3 { "a" } else { "s" }
                    ),
                ));
            }
            if let Some(&n) = element.iter().find(|&&n| n >= self.nodes.len()) {
                return Err(OutputError::invalid(
                    "mesh.elements",
                    format!(
                        "element {e} refers to node {n} but the mesh has {} nodes",
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
