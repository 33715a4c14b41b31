//! What the search needs of a scene in its dimension: the plane-strain or axisymmetric
//! [`Scene`] (Mandel size 4, triangles) or the 3D [`Scene3`] (6, tetrahedra). The search,
//! criterion, bracket and outputs are one implementation over both; only building the
//! model, its weight, a monitored node and the picture of the mechanism differ.
use std::path::Path;

use talus_fem::{Dimension, Mandel};

use crate::model::fem::{FromScene, Model, NodeMonitors, State};
use crate::output;
use crate::run::RunError;
use crate::scene::{Locate, Scene, Scene3, SceneError, SceneSpec, SceneVector};

/// A scene whose factor of safety the search finds, its model of Mandel size `D`.
pub trait StabilityScene<const D: usize>: Locate
where
    Mandel<D>: Dimension,
{
    /// `[x, y]` or `[x, y, z]`.
    type Vector: SceneVector;

    fn spec(&self) -> &SceneSpec<Self::Vector>;

    /// The model of the scene, checked as a plain run checks it.
    fn build_model(&self) -> Result<Model<D>, RunError>;

    /// The state the loading starts from (at rest, with the scene's initial stress).
    fn initial_state(&self, model: &Model<D>) -> Result<State<D>, SceneError>;

    /// The weight of gravity `g` (the scene's, unramped) on `model`: free and prescribed
    /// dofs (N/m in 2D, N in 3D).
    fn weight(&self, model: &Model<D>, g: Self::Vector)
        -> Result<(Vec<f64>, Vec<f64>), SceneError>;

    /// The node of the `[[monitor]]` named `name`.
    fn monitor_node(&self, model: &Model<D>, name: &str) -> Result<usize, SceneError>;

    /// What a run of `model` should be told (`summary.json`'s `warnings`).
    fn model_warnings(&self, model: &Model<D>) -> Vec<String>;

    /// `mechanism.png`: the per-element `magnitude` on the mesh (2D only: a map of a 3D
    /// body is a ParaView job, `mechanism.vtu`).
    fn plot_mechanism(
        &self,
        model: &Model<D>,
        path: &Path,
        magnitude: &[f64],
        labels: [&str; 3],
    ) -> Result<(), RunError>;
}

impl StabilityScene<4> for Scene {
    type Vector = [f64; 2];

    fn spec(&self) -> &SceneSpec {
        &self.spec
    }

    fn build_model(&self) -> Result<Model, RunError> {
        Ok(Model::from_scene(self)?)
    }

    fn initial_state(&self, model: &Model) -> Result<State, SceneError> {
        FromScene::initial_state(model, self)
    }

    fn weight(&self, model: &Model, g: [f64; 2]) -> Result<(Vec<f64>, Vec<f64>), SceneError> {
        crate::model::fem::weight(self, model, g)
    }

    fn monitor_node(&self, model: &Model, name: &str) -> Result<usize, SceneError> {
        NodeMonitors::node_named(self, model, name)
    }

    fn model_warnings(&self, model: &Model) -> Vec<String> {
        crate::model::fem::warnings(self, model)
    }

    fn plot_mechanism(
        &self,
        model: &Model,
        path: &Path,
        magnitude: &[f64],
        [title, subtitle, label]: [&str; 3],
    ) -> Result<(), RunError> {
        let mesh = output::MeshView {
            nodes: &model.mesh.nodes,
            elements: &model.mesh.triangles,
        };
        output::plot_field_map(
            path,
            &mesh,
            None,
            magnitude,
            &output::FieldMap {
                title,
                subtitle: Some(subtitle),
                label,
                clip_percentile: None,
                resolution: 0.0,
            },
        )
        .map_err(RunError::Output)
    }
}

impl StabilityScene<6> for Scene3 {
    type Vector = [f64; 3];

    fn spec(&self) -> &SceneSpec<[f64; 3]> {
        &self.spec
    }

    fn build_model(&self) -> Result<Model<6>, RunError> {
        Ok(crate::model::fem::model_3d(self)?)
    }

    fn initial_state(&self, model: &Model<6>) -> Result<State<6>, SceneError> {
        crate::model::fem::initial_state(self, model)
    }

    fn weight(&self, model: &Model<6>, g: [f64; 3]) -> Result<(Vec<f64>, Vec<f64>), SceneError> {
        crate::model::fem::weight(self, model, g)
    }

    fn monitor_node(&self, model: &Model<6>, name: &str) -> Result<usize, SceneError> {
        NodeMonitors::node_named(self, model, name)
    }

    fn model_warnings(&self, model: &Model<6>) -> Vec<String> {
        crate::model::fem::warnings(self, model)
    }

    fn plot_mechanism(
        &self,
        _: &Model<6>,
        _: &Path,
        _: &[f64],
        _: [&str; 3],
    ) -> Result<(), RunError> {
        Ok(())
    }
}
