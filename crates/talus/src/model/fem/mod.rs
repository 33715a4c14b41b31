//! The finite-element model of a scene (`[mesh]`): talus-fem's [`Model`] built from the
//! scene, its initial state, the quasi-static masses, and the named boundaries and
//! monitors a run reports.
mod build;
mod materials;
pub mod memory;
mod mesh2;
mod mesh3;
mod monitors;
mod motion;
mod quasi_static;
mod reaction_groups;
mod scene_mesh;
pub use scene_mesh::SceneMesh;
pub mod stages;

pub use build::{
    initial_state, model_3d, warnings, water_table, weight, FromScene, MeshOf, Model3, State3,
};
pub use monitors::NodeMonitors;
pub use quasi_static::DEFAULT_INERTIA_RATIO;
pub use reaction_groups::ReactionGroups;
pub use talus_fem::{
    prescribed_forces, prescribed_forces_at_rest, FemStats, Loads, Model, RampedForce,
    ReactionForce, State,
};

/// What one FEM step did.
pub type StepRecord = talus_engine::StepReport<FemStats>;
/// Why a FEM step failed.
pub type FemStepError = talus_engine::StepError<std::convert::Infallible>;

/// Each element's mean of its Gauss points' values, `W` numbers per point in `values`
/// (point `p` at `W p ..`): summed in point order, then divided by the element's count
/// of points (an element without one: 0). A `values` too short leaves the rest unsummed.
pub(crate) fn element_means<const W: usize, const D: usize>(
    model: &Model<D>,
    values: &[f64],
) -> Vec<[f64; W]>
where
    talus_fem::Mandel<D>: talus_fem::Dimension,
{
    use talus_fem::ElementMesh;
    let n_el = model.mesh.elements().len();
    let mut sums = vec![[0.0; W]; n_el];
    let mut count = vec![0usize; n_el];
    for (v, &e) in values.chunks_exact(W).zip(&model.assembly.gauss_element) {
        for (s, v) in sums[e].iter_mut().zip(v) {
            *s += v;
        }
        count[e] += 1;
    }
    for (s, c) in sums.iter_mut().zip(count) {
        s.iter_mut().for_each(|v| *v /= c.max(1) as f64);
    }
    sums
}
