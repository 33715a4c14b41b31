//! The plane-strain and axisymmetric mesh of a scene (`[mesh.rectangle]` or a Gmsh file of
//! triangles) and what the scene reads of it ([`SceneMesh`] for triangles): edge sets and
//! boxes, the edge loads, the axis a load may not lie on, the grading a Newton direction
//! suffers from.
use std::collections::BTreeMap;

use talus_fem::{Assembly, BoundaryEdge, Constraint, ElementOrder, Geometry, Mesh};

use super::scene_mesh::{Forces, SceneMesh};
use crate::scene::dimension::three_d_key;
use crate::scene::{Fix, MeshSpec, Order, Scene, SceneError};

impl SceneMesh<4> for Mesh {
    type Piece = BoundaryEdge;
    const PIECES: &'static str = "edges";
    const PIECE: &'static str = "boundary edge";

    fn from_scene(scene: &Scene) -> Result<Self, SceneError> {
        build_mesh(scene)
    }
    fn node_sets(&self) -> &BTreeMap<String, Vec<usize>> {
        &self.node_sets
    }
    fn piece_sets(&self) -> &BTreeMap<String, Vec<BoundaryEdge>> {
        &self.edge_sets
    }
    fn nodes_in_box(&self, corners: &[[f64; 2]; 2]) -> Result<Vec<usize>, String> {
        Mesh::nodes_in_box(self, corners[0], corners[1]).map_err(|e| e.to_string())
    }
    fn pieces_in_box(&self, corners: &[[f64; 2]; 2]) -> Result<Vec<BoundaryEdge>, String> {
        check_box_does_not_cut_edges(self, corners)?;
        self.boundary_edges_in_box(corners[0], corners[1])
            .map_err(|e| e.to_string())
    }
    fn boundary_pieces(&self) -> Vec<BoundaryEdge> {
        self.boundary_edges()
    }
    fn piece_nodes(edge: &BoundaryEdge) -> &[usize] {
        &edge.nodes
    }
    fn check_geometry(&self, geometry: Geometry) -> Result<(), String> {
        geometry.check_mesh(self).map_err(|e| e.to_string())
    }
    fn check_loaded(&self, edges: &[BoundaryEdge], geometry: Geometry) -> Result<(), String> {
        check_off_axis(self, edges, geometry)
    }
    fn constraint(fix: Fix) -> Option<Constraint> {
        match fix {
            Fix::X => Some(Constraint::FixX),
            Fix::Y => Some(Constraint::FixY),
            Fix::Xy => Some(Constraint::Fixed),
            Fix::Z | Fix::Xz | Fix::Yz | Fix::Xyz => None,
        }
    }
    fn smallest_cell(&self) -> f64 {
        (self.triangles.iter())
            .map(|t| {
                let [a, b, c] = [self.nodes[t[0]], self.nodes[t[1]], self.nodes[t[2]]];
                ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
                    .abs()
                    .sqrt()
            })
            .fold(f64::INFINITY, f64::min)
    }
    fn submesh(&self, elements: &[usize]) -> Result<(Self, Vec<Option<usize>>), String> {
        Mesh::submesh(self, elements).map_err(|e| e.to_string())
    }
    fn traction(
        &self,
        asm: &Assembly<4>,
        edges: &[BoundaryEdge],
        t: [f64; 2],
    ) -> Result<Forces, String> {
        asm.traction(self, edges, t).map_err(|e| e.to_string())
    }
    fn pressure(
        &self,
        asm: &Assembly<4>,
        edges: &[BoundaryEdge],
        p: f64,
    ) -> Result<Forces, String> {
        asm.pressure(self, edges, p).map_err(|e| e.to_string())
    }
    fn pressure_with(
        &self,
        asm: &Assembly<4>,
        edges: &[BoundaryEdge],
        p: impl Fn([f64; 2]) -> f64,
    ) -> Result<Forces, String> {
        asm.pressure_with(self, edges, p).map_err(|e| e.to_string())
    }
}

fn build_mesh(scene: &Scene) -> Result<Mesh, SceneError> {
    crate::scene::dimension::check(scene, &scene.source, &scene.spec)?;
    match &scene.spec.mesh {
        MeshSpec::Rectangle {
            x,
            y,
            cells,
            order,
            focus,
            ratio,
        } => {
            // Before any coordinate is allocated: `[4294967295, 0]` has no Gauss point, so
            // the size estimate lets it through, yet its x coordinates alone take 34 GB.
            if cells.contains(&0) {
                return Err(scene.error(
                    "mesh.rectangle.cells",
                    format!("{cells:?}: the number of cells must be ≥ 1 in x and in y"),
                ));
            }
            let focus = focus.unwrap_or([x[0], y[0]]);
            let xs = talus_fem::graded_coordinates(x[0], x[1], cells[0], focus[0], ratio[0])
                .map_err(|e| scene.error("mesh.rectangle.x", e.to_string()))?;
            let ys = talus_fem::graded_coordinates(y[0], y[1], cells[1], focus[1], ratio[1])
                .map_err(|e| scene.error("mesh.rectangle.y", e.to_string()))?;
            warn_of_strong_grading("x", &xs, ratio[0]);
            warn_of_strong_grading("y", &ys, ratio[1]);
            let order = match order {
                Order::P1 => ElementOrder::P1,
                Order::P2 => ElementOrder::P2,
            };
            Mesh::rectangle(&xs, &ys, order)
                .map_err(|e| scene.error("mesh.rectangle", e.to_string()))
        }
        MeshSpec::Box { .. } => Err(three_d_key(scene, "mesh.box", "a box of tetrahedra")),
        MeshSpec::Gmsh { path, order, .. } => {
            // The .msh file named as well as the scene's line: the error is in it.
            let file = scene.resolve(path);
            let mesh = Mesh::from_msh(&file)
                .map_err(|e| scene.error("mesh.gmsh.path", format!("{}: {e}", file.display())))?;
            match (order, mesh.order) {
                (Some(Order::P2), ElementOrder::P1) => mesh
                    .to_p2()
                    .map_err(|e| scene.error("mesh.gmsh.order", e.to_string())),
                (Some(Order::P1), ElementOrder::P2) => Err(scene.error(
                    "mesh.gmsh.order",
                    format!(
                        "\"P1\": {} holds P2 (6-node) triangles; a P2 mesh is not lowered \
                         (mesh it with order 1, or leave `order` out)",
                        file.display()
                    ),
                )),
                _ => Ok(mesh),
            }
        }
    }
}

/// In axisymmetry an edge on the axis r = 0 has no area (`2π r ds`): a load there applies
/// nothing, so selecting one is a mistake to name, not a load to drop silently.
fn check_off_axis(mesh: &Mesh, edges: &[BoundaryEdge], geometry: Geometry) -> Result<(), String> {
    if geometry != Geometry::Axisymmetric {
        return Ok(());
    }
    let axis = geometry.axis_nodes(mesh);
    let on_axis = |n: &usize| axis.binary_search(n).is_ok();
    if let Some(e) = edges.iter().find(|e| e.nodes.iter().all(on_axis)) {
        let [a, b] = [mesh.nodes[e.nodes[0]], mesh.nodes[e.nodes[1]]];
        return Err(format!(
            "selects the edge ({:.4}, {:.4})–({:.4}, {:.4}) on the axis r = 0, where an \
                 axisymmetric load acts on no area and applies nothing: select edges off the \
                 axis",
            a[0], a[1], b[0], b[1]
        ));
    }
    Ok(())
}

/// A traction box whose side falls inside a boundary edge loads part of the surface with no
/// edge to carry it: an error, naming the edge, rather than a silently wrong load.
fn check_box_does_not_cut_edges(mesh: &Mesh, corners: &[[f64; 2]; 2]) -> Result<(), String> {
    let (lo, hi) = (corners[0], corners[1]);
    let size = mesh
        .nodes
        .iter()
        .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()))
        .max(1.0);
    let tol = 1e-9 * size;
    let inside = |p: [f64; 2]| (0..2).all(|k| p[k] >= lo[k] - tol && p[k] <= hi[k] + tol);
    let strictly = |p: [f64; 2]| {
        (0..2).all(|k| p[k] > lo[k] + tol && p[k] < hi[k] - tol) || {
            // On a degenerate (flat) box, "strictly" means strictly between its ends.
            let flat: Vec<usize> = (0..2).filter(|&k| hi[k] - lo[k] <= 2.0 * tol).collect();
            !flat.is_empty()
                && (0..2)
                    .filter(|k| !flat.contains(k))
                    .all(|k| p[k] > lo[k] + tol && p[k] < hi[k] - tol)
                && inside(p)
        }
    };
    for edge in mesh.boundary_edges() {
        let pts: Vec<[f64; 2]> = edge.nodes.iter().map(|&n| mesh.nodes[n]).collect();
        let n_in = pts.iter().filter(|p| inside(**p)).count();
        if n_in > 0 && n_in < pts.len() && pts.iter().any(|p| strictly(*p)) {
            let (a, b) = (pts[0], pts[1]);
            return Err(format!(
                    "the box cuts the boundary edge ({:.4}, {:.4})–({:.4}, {:.4}); put mesh nodes on the box's sides",
                a[0], a[1], b[0], b[1]
            ));
        }
    }
    Ok(())
}

/// The largest cell this many times the smallest draws a warning: the shipped scenes stay
/// below 100 (footing: 1.1 over 14 cells), while the footing's `ratio = 1.1` kept over 152
/// cells (1.9e6) made step 1 fail at every halving with inaccurate Newton directions
/// (`docs/performance.md`, 'The 100k footing's first steps').
const GRADING_WARNING: f64 = 1e3;

/// Warns when the cells along one axis of `[mesh.rectangle]` span more than
/// [`GRADING_WARNING`] in size, with the ratio that would make the span 100.
fn warn_of_strong_grading(axis: &str, coords: &[f64], ratio: f64) {
    let sizes = coords.windows(2).map(|w| w[1] - w[0]);
    let (small, large) = sizes.fold((f64::INFINITY, 0.0f64), |(s, l), d| (s.min(d), l.max(d)));
    let span = large / small;
    if span > GRADING_WARNING {
        // span = ratio^k for k growth steps: ratio' = 100^(1/k).
        let steps = span.ln() / ratio.ln().abs();
        tracing::warn!(
            "mesh.rectangle.ratio: along {axis} the largest cell is {span:.1e} times the \
             smallest (ratio {ratio} over {} cells); Newton directions lose accuracy on such \
             meshes; ratio = {:.4} would make it 100",
            coords.len() - 1,
            if ratio >= 1.0 {
                100f64.powf(1.0 / steps)
            } else {
                100f64.powf(-1.0 / steps)
            }
        );
    }
}
