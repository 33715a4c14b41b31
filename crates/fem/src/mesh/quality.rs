//! Consistency and quality checks: every triangle has the right node count, refers to
//! existing nodes with finite coordinates, and has `det J > 0` at its vertices and at
//! every stiffness and (P2) mass quadrature point (a P2 triangle with a misplaced mid node
//! can fold over inside while its vertices stay counter-clockwise); edge, node and element
//! sets refer to existing nodes and triangles.
use super::Mesh;
use crate::element::jacobian_determinant;
use crate::element::ElementOrder;
use crate::error::MeshError;
use crate::quadrature::{mass_rule, stiffness_rule};

impl Mesh {
    /// Checks the whole mesh; errors name the first bad triangle (by index) or set.
    pub fn validate(&self) -> Result<(), MeshError> {
        self.validate_labelled(&|e| format!("triangle {e}"))
    }

    /// Same, naming triangles through `label` (e.g. by their Gmsh tag).
    pub(crate) fn validate_labelled(
        &self,
        label: &dyn Fn(usize) -> String,
    ) -> Result<(), MeshError> {
        if let Some((i, p)) = self
            .nodes
            .iter()
            .enumerate()
            .find(|(_, p)| !(p[0].is_finite() && p[1].is_finite()))
        {
            return Err(MeshError::invalid(
                "nodes",
                format!("node {i} has non-finite coordinates {p:?}"),
            ));
        }
        if self.triangles.is_empty() {
            return Err(MeshError::invalid("triangles", "the mesh has no triangles"));
        }
        let npe = self.order.nodes_per_triangle();
        let rule = stiffness_rule(self.order);
        let vertices = &self.order.reference_nodes()[..3];
        let mass_points: &[[f64; 2]] = match self.order {
            ElementOrder::P1 => &[],
            ElementOrder::P2 => mass_rule().points,
        };
        for (e, tri) in self.triangles.iter().enumerate() {
            if tri.len() != npe {
                return Err(MeshError::element(
                    label(e),
                    format!(
                        "has {} nodes, a {:?} triangle has {npe}",
                        tri.len(),
                        self.order
                    ),
                ));
            }
            if let Some(&n) = tri.iter().find(|&&n| n >= self.nodes.len()) {
                return Err(MeshError::element(
                    label(e),
                    format!(
                        "refers to node {n}, the mesh has {} nodes",
                        self.nodes.len()
                    ),
                ));
            }
            let coords = self.triangle_coordinates(e);
            // The assembly evaluates det J at these points: the mesh is valid where it does.
            for xi in vertices.iter().chain(rule.points).chain(mass_points) {
                let det = jacobian_determinant(self.order, &coords, *xi);
                if !(det.is_finite() && det > 0.0) {
                    return Err(MeshError::element(
                        label(e),
                        format!(
                            "is inverted or degenerate: det J = {det:e} at reference point {xi:?} \
                             (nodes must be counter-clockwise)"
                        ),
                    ));
                }
            }
            // P2: det J can be positive at every point sampled above while the corners run
            // clockwise (mid-edge nodes folding the element over itself). And an area below
            // the round-off of its own computation (ε times the longest side squared, here
            // 16 ε) is no area: `4.9e-324` for a coordinate of the unit square gave one.
            let [a, b, c] = [coords[0], coords[1], coords[2]];
            let twice_area = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
            let side2 = |p: [f64; 2], q: [f64; 2]| (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
            let longest2 = side2(a, b).max(side2(b, c)).max(side2(c, a));
            if twice_area.is_nan() || twice_area <= 16.0 * f64::EPSILON * longest2 {
                return Err(MeshError::element(
                    label(e),
                    format!(
                        "is inverted or degenerate: its corners {a:?}, {b:?}, {c:?} enclose the \
                         signed area {:e}, at most the round-off of its sides (corners must be \
                         counter-clockwise and not aligned)",
                        twice_area / 2.0
                    ),
                ));
            }
        }
        let npe_edge = self.order.nodes_per_edge();
        for (name, edges) in &self.edge_sets {
            for edge in edges {
                if edge.nodes.len() != npe_edge || edge.nodes.iter().any(|&n| n >= self.nodes.len())
                {
                    return Err(MeshError::invalid(
                        "edge_sets",
                        format!(
                            "edge set \"{name}\": edge {:?} must have {npe_edge} nodes below {}",
                            edge.nodes,
                            self.nodes.len()
                        ),
                    ));
                }
            }
        }
        for (name, nodes) in &self.node_sets {
            if let Some(n) = nodes.iter().find(|&&n| n >= self.nodes.len()) {
                return Err(MeshError::invalid(
                    "node_sets",
                    format!(
                        "node set \"{name}\" refers to node {n}, the mesh has {} nodes",
                        self.nodes.len()
                    ),
                ));
            }
        }
        for (name, elements) in &self.element_sets {
            if let Some(e) = elements.iter().find(|&&e| e >= self.triangles.len()) {
                return Err(MeshError::invalid(
                    "element_sets",
                    format!(
                        "element set \"{name}\" refers to triangle {e}, the mesh has {}",
                        self.triangles.len()
                    ),
                ));
            }
        }
        Ok(())
    }
}
