//! The 3D mesh of a scene (`[mesh.box]`, a Gmsh file of tetrahedra, or a triangle mesh
//! extruded along z; `docs/3d.md`), refused before it allocates when its Newton step would
//! not fit this machine, and what the scene reads of it ([`SceneMesh`] for tetrahedra):
//! face sets and boxes, the face loads, the supports of `fix`.
use std::collections::BTreeMap;

use talus_fem::{Assembly, BoundaryFace, Constraint, ElementOrder, TetrahedralMesh};

use super::scene_mesh::{Forces, SceneMesh};
use crate::scene::{Fix, MeshSpec, Order, Scene3, SceneError};

impl SceneMesh<6> for TetrahedralMesh {
    type Piece = BoundaryFace;
    const PIECES: &'static str = "faces";
    const PIECE: &'static str = "boundary face";

    fn from_scene(scene: &Scene3) -> Result<Self, SceneError> {
        build_mesh(scene)
    }
    fn node_sets(&self) -> &BTreeMap<String, Vec<usize>> {
        &self.node_sets
    }
    fn piece_sets(&self) -> &BTreeMap<String, Vec<BoundaryFace>> {
        &self.face_sets
    }
    fn nodes_in_box(&self, corners: &[[f64; 3]; 2]) -> Result<Vec<usize>, String> {
        TetrahedralMesh::nodes_in_box(self, corners[0], corners[1]).map_err(|e| e.to_string())
    }
    fn pieces_in_box(&self, corners: &[[f64; 3]; 2]) -> Result<Vec<BoundaryFace>, String> {
        self.boundary_faces_in_box(corners[0], corners[1])
            .map_err(|e| e.to_string())
    }
    fn boundary_pieces(&self) -> Vec<BoundaryFace> {
        self.boundary_faces()
    }
    fn piece_nodes(face: &BoundaryFace) -> &[usize] {
        &face.nodes
    }
    fn constraint(fix: Fix) -> Option<Constraint> {
        Some(match fix {
            Fix::X => Constraint::FixX,
            Fix::Y => Constraint::FixY,
            Fix::Z => Constraint::FixZ,
            Fix::Xy => Constraint::FixXY,
            Fix::Xz => Constraint::FixXZ,
            Fix::Yz => Constraint::FixYZ,
            Fix::Xyz => Constraint::Fixed,
        })
    }
    fn smallest_cell(&self) -> f64 {
        (self.tetrahedra.iter())
            .map(|t| {
                let [a, b, c, d] = [t[0], t[1], t[2], t[3]].map(|n| self.nodes[n]);
                let e = |p: [f64; 3]| [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
                let (u, v, w) = (e(b), e(c), e(d));
                let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                    + u[2] * (v[0] * w[1] - v[1] * w[0]);
                (det.abs() / 6.0).cbrt()
            })
            .fold(f64::INFINITY, f64::min)
    }
    fn submesh(&self, elements: &[usize]) -> Result<(Self, Vec<Option<usize>>), String> {
        TetrahedralMesh::submesh(self, elements).map_err(|e| e.to_string())
    }
    fn traction(
        &self,
        asm: &Assembly<6>,
        faces: &[BoundaryFace],
        t: [f64; 3],
    ) -> Result<Forces, String> {
        asm.traction(self, faces, t).map_err(|e| e.to_string())
    }
    fn pressure(
        &self,
        asm: &Assembly<6>,
        faces: &[BoundaryFace],
        p: f64,
    ) -> Result<Forces, String> {
        asm.pressure(self, faces, p).map_err(|e| e.to_string())
    }
    fn pressure_with(
        &self,
        asm: &Assembly<6>,
        faces: &[BoundaryFace],
        p: impl Fn([f64; 3]) -> f64,
    ) -> Result<Forces, String> {
        asm.pressure_with(self, faces, p).map_err(|e| e.to_string())
    }
}

/// The mesh of `[mesh.box]` or `[mesh.gmsh]`.
fn build_mesh(scene: &Scene3) -> Result<TetrahedralMesh, SceneError> {
    crate::scene::dimension::check(scene, &scene.source, &scene.spec)?;
    match &scene.spec.mesh {
        MeshSpec::Box {
            x,
            y,
            z,
            cells,
            order,
            focus,
            ratio,
        } => {
            // Before any coordinate is allocated, as `[mesh.rectangle]`.
            if cells.contains(&0) {
                return Err(scene.error(
                    "mesh.box.cells",
                    format!("{cells:?}: the number of cells must be ≥ 1 in x, y and z"),
                ));
            }
            let per_axis = |c: usize| match order {
                Order::P1 => c as f64 + 1.0,
                Order::P2 => 2.0 * c as f64 + 1.0,
            };
            let nodes = per_axis(cells[0]) * per_axis(cells[1]) * per_axis(cells[2]);
            refuse_too_large(scene, "mesh.box.cells", nodes)?;
            let focus = focus.unwrap_or([x[0], y[0], z[0]]);
            let mut axes = Vec::with_capacity(3);
            for (k, (name, range)) in [("x", x), ("y", y), ("z", z)].into_iter().enumerate() {
                let coords =
                    talus_fem::graded_coordinates(range[0], range[1], cells[k], focus[k], ratio[k])
                        .map_err(|e| scene.error(&format!("mesh.box.{name}"), e.to_string()))?;
                axes.push(coords);
            }
            let order = match order {
                Order::P1 => ElementOrder::P1,
                Order::P2 => ElementOrder::P2,
            };
            TetrahedralMesh::block(&axes[0], &axes[1], &axes[2], order)
                .map_err(|e| scene.error("mesh.box", e.to_string()))
        }
        MeshSpec::Gmsh {
            path,
            order,
            extrude: Some(z),
            layers,
        } => extruded_mesh(scene, path, *order, *z, *layers),
        MeshSpec::Gmsh {
            layers: Some(_), ..
        } => Err(scene.error(
            "mesh.gmsh.layers",
            "divides an extrusion: give `extrude = [z0, z1]` with it, or leave it out",
        )),
        MeshSpec::Gmsh { path, order, .. } => {
            let file = scene.resolve(path);
            let mesh = TetrahedralMesh::from_msh(&file)
                .map_err(|e| scene.error("mesh.gmsh.path", format!("{}: {e}", file.display())))?;
            refuse_too_large(scene, "mesh.gmsh.path", mesh.nodes.len() as f64)?;
            match (order, mesh.order) {
                (Some(Order::P2), ElementOrder::P1) | (Some(Order::P1), ElementOrder::P2) => {
                    Err(scene.error(
                        "mesh.gmsh.order",
                        format!(
                            "{:?}: {} holds {:?} tetrahedra; in 3D a mesh is used at the order \
                             it was meshed with (leave `order` out)",
                            order.unwrap_or(Order::P1),
                            file.display(),
                            mesh.order
                        ),
                    ))
                }
                _ => Ok(mesh),
            }
        }
        MeshSpec::Rectangle { .. } => Err(scene.error(
            "mesh.rectangle",
            "is 2D: a 3D scene is meshed by [mesh.box] or [mesh.gmsh] (tetrahedra)",
        )),
    }
}

/// Refuses a mesh of `nodes` nodes whose Newton factorization would not fit this
/// machine's memory (`super::memory`), naming `field` and the estimate.
fn refuse_too_large(scene: &Scene3, field: &str, nodes: f64) -> Result<(), SceneError> {
    let machine = super::memory::machine_mib().unwrap_or(super::memory::UNKNOWN_MACHINE_MIB);
    // Every node's 3 components: the free ones are fewer, by the boundary's.
    let unknowns = 3.0 * nodes;
    let associative = super::memory::associative(scene.spec.material.all());
    let need = super::memory::peak_mib(unknowns, associative);
    if need <= machine {
        return Ok(());
    }
    Err(scene.error(
        field,
        format!(
            "{nodes:.0} nodes, up to {unknowns:.3e} unknowns: a Newton step would need about \
             {:.1} GiB ({} flow; estimated from the peaks measured in docs/3d.md, 'Memory \
             and speed in 3D'), more than this machine's {:.1} GiB; coarsen the mesh",
            need / 1024.0,
            if associative {
                "associative"
            } else {
                "non-associative"
            },
            machine / 1024.0
        ),
    ))
}

/// Layers of an extrusion at most: a cap before anything is allocated.
const MAX_LAYERS: usize = 10_000;

/// `[mesh.gmsh]` with `extrude = [z0, z1]`: the file's 2D triangle mesh (raised to P2 by
/// `order = "P2"`, as in 2D) extruded along z in `layers` equal layers (default 1).
fn extruded_mesh(
    scene: &Scene3,
    path: &str,
    order: Option<Order>,
    [z0, z1]: [f64; 2],
    layers: Option<usize>,
) -> Result<TetrahedralMesh, SceneError> {
    if !(z0.is_finite() && z1.is_finite() && z1 > z0) {
        return Err(scene.error(
            "mesh.gmsh.extrude",
            format!("[{z0}, {z1}] m must be finite with z0 < z1"),
        ));
    }
    let layers = layers.unwrap_or(1);
    if !(1..=MAX_LAYERS).contains(&layers) {
        return Err(scene.error(
            "mesh.gmsh.layers",
            format!("{layers} must be between 1 and {MAX_LAYERS}"),
        ));
    }
    let file = scene.resolve(path);
    let mesh = talus_fem::Mesh::from_msh(&file).map_err(|e| {
        scene.error(
            "mesh.gmsh.path",
            format!(
                "{}: {e} (`extrude` reads a 2D triangle mesh)",
                file.display()
            ),
        )
    })?;
    let mesh = match (order, mesh.order) {
        (Some(Order::P2), ElementOrder::P1) => mesh
            .to_p2()
            .map_err(|e| scene.error("mesh.gmsh.order", e.to_string()))?,
        (Some(Order::P1), ElementOrder::P2) => {
            return Err(scene.error(
                "mesh.gmsh.order",
                format!(
                    "\"P1\": {} holds P2 (6-node) triangles; a P2 mesh is not lowered \
                     (mesh it with order 1, or leave `order` out)",
                    file.display()
                ),
            ))
        }
        _ => mesh,
    };
    // Nodes per layer boundary: the vertices (P1), or every node and the mid-layer ones
    // (P2), before the extrusion allocates them.
    let planes = match mesh.order {
        ElementOrder::P1 => layers as f64 + 1.0,
        ElementOrder::P2 => 2.0 * layers as f64 + 1.0,
    };
    refuse_too_large(scene, "mesh.gmsh.layers", mesh.nodes.len() as f64 * planes)?;
    let zs: Vec<f64> = (0..=layers)
        .map(|k| match k {
            0 => z0,
            k if k == layers => z1,
            k => z0 + (z1 - z0) * k as f64 / layers as f64,
        })
        .collect();
    TetrahedralMesh::extrude(&mesh, &zs).map_err(|e| {
        scene.error(
            "mesh.gmsh.extrude",
            format!("{} extruded over [{z0}, {z1}] m: {e}", file.display()),
        )
    })
}
