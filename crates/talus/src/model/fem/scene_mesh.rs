//! What a scene reads of a mesh of either dimension, so that one `build` makes the model
//! of a plane-strain, axisymmetric or 3D scene: the mesh from `[mesh]`, its node sets and
//! boundary pieces (edges in 2D, faces in 3D) by name or box, the loads on pieces, the
//! supports a `fix` names, the smallest cell, and its part for a stage (`submesh`).
use std::collections::BTreeMap;

use talus_fem::{Assembly, Constraint, Dimension, Geometry, Mandel};

use super::materials::GroundMesh;
use crate::scene::{Fix, SceneDocument, SceneError, SceneSpec, SceneVector, Selection};

/// Forces on the free and prescribed dofs.
pub type Forces = (Vec<f64>, Vec<f64>);

/// A mesh a scene builds its model on: triangles (`D = 4`) or tetrahedra (`D = 6`).
pub trait SceneMesh<const D: usize>: GroundMesh<Point: SceneVector> + Sized
where
    Mandel<D>: Dimension,
{
    /// A boundary piece: an edge (2D) or a face (3D).
    type Piece: Clone;
    /// The loads' key for pieces, `edges` or `faces`, and a piece in words.
    const PIECES: &'static str;
    const PIECE: &'static str;

    /// The mesh of `[mesh]`, checked against the scene's dimension.
    fn from_scene(scene: &SceneDocument<SceneSpec<Self::Point>>) -> Result<Self, SceneError>;

    fn node_sets(&self) -> &BTreeMap<String, Vec<usize>>;
    fn piece_sets(&self) -> &BTreeMap<String, Vec<Self::Piece>>;
    fn nodes_in_box(&self, corners: &[Self::Point; 2]) -> Result<Vec<usize>, String>;
    /// The boundary pieces in a box (2D: refused when the box cuts an edge).
    fn pieces_in_box(&self, corners: &[Self::Point; 2]) -> Result<Vec<Self::Piece>, String>;
    /// Every boundary piece.
    fn boundary_pieces(&self) -> Vec<Self::Piece>;
    fn piece_nodes(piece: &Self::Piece) -> &[usize];
    /// A mesh `geometry` cannot use (axisymmetric: a node at r < 0), named.
    fn check_geometry(&self, _geometry: Geometry) -> Result<(), String> {
        Ok(())
    }
    /// Pieces a load may not take in `geometry` (axisymmetric: on the axis), named.
    fn check_loaded(&self, _pieces: &[Self::Piece], _geometry: Geometry) -> Result<(), String> {
        Ok(())
    }

    /// The constraint of `fix`; `None` when it names an axis the mesh does not have.
    fn constraint(fix: Fix) -> Option<Constraint>;
    /// The side of the smallest element (m): `√(2A)` of a triangle, `∛V` of a
    /// tetrahedron, for the scales' checks.
    fn smallest_cell(&self) -> f64;

    /// The mesh of `elements` and each old node's new index (`None`: gone).
    fn submesh(&self, elements: &[usize]) -> Result<(Self, Vec<Option<usize>>), String>;

    fn traction(
        &self,
        asm: &Assembly<D>,
        pieces: &[Self::Piece],
        t: Self::Point,
    ) -> Result<Forces, String>;
    fn pressure(&self, asm: &Assembly<D>, pieces: &[Self::Piece], p: f64)
        -> Result<Forces, String>;
    fn pressure_with(
        &self,
        asm: &Assembly<D>,
        pieces: &[Self::Piece],
        p: impl Fn(Self::Point) -> f64,
    ) -> Result<Forces, String>;
}

/// The nodes `sel` names on `mesh`, refused when none (`in_stage`: " in stage \"…\"").
pub fn select_nodes<const D: usize, M: SceneMesh<D>>(
    scene: &SceneDocument<SceneSpec<M::Point>>,
    mesh: &M,
    sel: &Selection<M::Point>,
    field: &str,
    in_stage: &str,
) -> Result<Vec<usize>, SceneError>
where
    Mandel<D>: Dimension,
{
    let nodes = match sel {
        Selection::Named(name) => mesh.node_sets().get(name).cloned().ok_or_else(|| {
            scene.error(
                field,
                format!(
                    "no node set named `{name}` (the mesh has: {})",
                    names(mesh.node_sets())
                ),
            )
        })?,
        Selection::Box { corners } => mesh
            .nodes_in_box(corners)
            .map_err(|e| scene.error(field, e))?,
    };
    if nodes.is_empty() {
        return Err(scene.error(field, format!("selects no node{in_stage}")));
    }
    Ok(nodes)
}

/// The boundary pieces `sel` names on `mesh`, refused when none.
pub fn select_pieces<const D: usize, M: SceneMesh<D>>(
    scene: &SceneDocument<SceneSpec<M::Point>>,
    mesh: &M,
    sel: &Selection<M::Point>,
    field: &str,
    in_stage: &str,
) -> Result<Vec<M::Piece>, SceneError>
where
    Mandel<D>: Dimension,
{
    let pieces = match sel {
        Selection::Named(name) => mesh.piece_sets().get(name).cloned().ok_or_else(|| {
            let what = &M::PIECES[..M::PIECES.len() - 1];
            scene.error(
                field,
                format!(
                    "no {what} set named `{name}` (the mesh has: {})",
                    names(mesh.piece_sets())
                ),
            )
        })?,
        Selection::Box { corners } => mesh
            .pieces_in_box(corners)
            .map_err(|e| scene.error(field, e))?,
    };
    if pieces.is_empty() {
        return Err(scene.error(field, format!("selects no {}{in_stage}", M::PIECE)));
    }
    Ok(pieces)
}

/// The node nearest `point` (the first of equally near ones).
pub fn nearest_node<P: AsRef<[f64]>>(nodes: &[P], point: &[f64]) -> usize {
    let d = |n: &P| {
        (n.as_ref().iter().zip(point))
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
    };
    (0..nodes.len())
        .min_by(|&a, &b| d(&nodes[a]).total_cmp(&d(&nodes[b])))
        .unwrap_or(0)
}

fn names<T>(sets: &BTreeMap<String, T>) -> String {
    sets.keys()
        .map(String::as_str)
        .collect::<Vec<_>>()
        .join(", ")
}
