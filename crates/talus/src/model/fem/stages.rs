//! Construction in stages (`[[stage]]`, `docs/scenes.md`, 'Stages'): the elements each
//! stage has, its model on that part of the mesh, the state carried over from the stage
//! before, and the out-of-balance force that the stage releases.
//!
//! A stage's model is the scene's on `Mesh::submesh` of its elements, with the loads and
//! conditions that act in it. The state at the end of the stage before carries over
//! element by element and node by node (new elements stress free, new nodes at rest). In
//! the new model that state is out of balance by `r = Bᵀσ − f(t₀)` on the free dofs: the
//! force the removed elements exerted on the rest (their weight minus their internal
//! force, `talus_fem::excavation` derives it), minus the weight of the elements built,
//! plus whatever loads, supports or water changed. The stage adds `r` as a load ramped
//! from 1 at its start to 0 at its end, so that the change is applied over its steps.
use talus_engine::Ramp;
use talus_fem::{transfer_state, Dimension, ElementMesh, Mandel, Model, Part, State};

use super::build::{build, MeshOf, StageView};
use super::materials::{ground, Ground};
use super::scene_mesh::SceneMesh;
use crate::scene::{SceneError, SceneOf, SceneVector, StageSpec, WaterSpec};

/// The stages of a scene, their elements checked against its regions: on triangles
/// (`D = 4`) or tetrahedra (`D = 6`).
pub struct Stages<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    mesh: MeshOf<D>,
    ground: Ground,
    pub plans: Vec<StagePlan>,
}

/// One stage: its elements (indices into the whole mesh, increasing) and its steps.
#[derive(Debug, Clone)]
pub struct StagePlan {
    pub elements: Vec<usize>,
    /// The run's steps before the stage.
    pub first_step: usize,
    /// The water table in force and the field it came from.
    pub water: Option<(WaterSpec, String)>,
    pub spec: StageSpec,
}

impl StagePlan {
    pub fn last_step(&self) -> usize {
        self.first_step + self.spec.steps
    }
}

/// A stage's model, and the whole mesh's indices of its elements and nodes.
pub struct StageModel<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub model: Model<D>,
    pub elements: Vec<usize>,
    pub nodes: Vec<usize>,
}

impl<const D: usize> Stages<D>
where
    Mandel<D>: Dimension,
    MeshOf<D>: SceneMesh<D>,
{
    /// The scene's stages, `None` without `[[stage]]`. A region a stage activates is absent
    /// before it; each stage then removes its `deactivate` regions (which must be present)
    /// and adds its `activate` ones (which must be absent).
    pub fn of<const N: usize>(scene: &SceneOf<N>) -> Result<Option<Self>, SceneError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
        [f64; N]: SceneVector,
    {
        let spec = &scene.spec;
        if spec.stage.is_empty() {
            return Ok(None);
        }
        crate::scene::stage::check(scene, spec)?;
        let mesh = MeshOf::<D>::from_scene(scene)?;
        let ground = ground(scene, &mesh)?;
        let region = |field: String, name: &str| {
            super::materials::region(scene, &ground.regions, &field, name)
        };
        // Present at the start: everything but the regions whose first mention, in the
        // order the stages apply them (removals, then additions), is an addition.
        let mut active = vec![true; mesh.elements().len()];
        let mut seen = std::collections::BTreeSet::new();
        for (k, s) in spec.stage.iter().enumerate() {
            seen.extend(s.deactivate.iter().map(String::as_str));
            for (j, name) in s.activate.iter().enumerate() {
                let elements = region(format!("stage[{k}].activate[{j}]"), name)?;
                if seen.insert(name.as_str()) {
                    elements.iter().for_each(|&e| active[e] = false);
                }
            }
        }
        // Where each region was last removed or built: (stage, removed?).
        let mut history: std::collections::BTreeMap<&str, (usize, bool)> = Default::default();
        let mut water = spec.water.clone().map(|w| (w, "water".to_string()));
        let mut plans = Vec::with_capacity(spec.stage.len());
        let mut first_step = 0;
        for (k, s) in spec.stage.iter().enumerate() {
            for (j, name) in s.deactivate.iter().enumerate() {
                let field = format!("stage[{k}].deactivate[{j}]");
                let elements = region(field.clone(), name)?;
                if let Some(&(m, true)) = history.get(name.as_str()) {
                    return Err(scene.error(
                        &field,
                        format!(
                            "region \"{name}\" was removed already, by stage[{m}] (\"{}\")",
                            spec.stage[m].name
                        ),
                    ));
                }
                if elements.iter().all(|&e| !active[e]) {
                    return Err(scene.error(
                        &field,
                        format!(
                            "region \"{name}\" is not there to remove: a later stage builds it"
                        ),
                    ));
                }
                for &e in elements {
                    active[e] = false;
                }
                history.insert(name, (k, true));
            }
            for (j, name) in s.activate.iter().enumerate() {
                let field = format!("stage[{k}].activate[{j}]");
                let elements = region(field.clone(), name)?;
                if elements.iter().all(|&e| active[e]) {
                    return Err(scene.error(
                        &field,
                        format!(
                            "region \"{name}\" is there already: only an absent region is built"
                        ),
                    ));
                }
                for &e in elements {
                    active[e] = true;
                }
                history.insert(name, (k, false));
            }
            let elements: Vec<usize> = (0..active.len()).filter(|&e| active[e]).collect();
            if elements.is_empty() {
                return Err(scene.error(
                    &format!("stage[{k}].deactivate"),
                    format!(
                        "{:?} leaves stage \"{}\" without any element",
                        s.deactivate, s.name
                    ),
                ));
            }
            if let Some(w) = &s.water {
                water = Some((w.clone(), format!("stage[{k}].water")));
            }
            plans.push(StagePlan {
                elements,
                first_step,
                water: water.clone(),
                spec: s.clone(),
            });
            // Saturating: a sum past the cap is refused below, not overflowed.
            first_step = first_step.saturating_add(s.steps);
        }
        // Once here, not per stage's model (`Stages::model`).
        super::build::check_scene(scene)?;
        Ok(Some(Self {
            mesh,
            ground,
            plans,
        }))
    }

    /// The model of stage `k`.
    pub fn model<const N: usize>(
        &self,
        scene: &SceneOf<N>,
        k: usize,
    ) -> Result<StageModel<D>, SceneError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
        [f64; N]: SceneVector,
    {
        let plan = &self.plans[k];
        let (mesh, node_map) = (self.mesh.submesh(&plan.elements))
            .map_err(|e| scene.error(&format!("stage[{k}]"), e))?;
        let element_material: Vec<usize> = plan
            .elements
            .iter()
            .map(|&e| self.ground.element_material[e])
            .collect();
        let view = StageView {
            name: &plan.spec.name,
            water: plan.water.as_ref().map(|(w, f)| (w, f.clone())),
        };
        let model = build(scene, mesh, &element_material, &self.ground, Some(&view))?;
        let mut nodes = vec![0; model.mesh.node_positions().len()];
        for (old, new) in node_map.iter().enumerate() {
            if let Some(new) = *new {
                nodes[new] = old;
            }
        }
        Ok(StageModel {
            model,
            elements: plan.elements.clone(),
            nodes,
        })
    }
}

impl<const D: usize> StageModel<D>
where
    Mandel<D>: Dimension,
{
    fn part(&self) -> Part<'_, D> {
        Part {
            model: &self.model,
            elements: &self.elements,
            nodes: &self.nodes,
        }
    }
}

/// The state of `next` from `state` of `previous` (`talus_fem::transfer_state`): the
/// stresses of the elements both have (new ones stress free), the displacements and
/// velocities of the nodes both have (new ones at rest; displacements zero everywhere
/// when `reset`).
pub fn carry<const D: usize>(
    previous: &StageModel<D>,
    state: &State<D>,
    next: &StageModel<D>,
    reset: bool,
) -> Result<State<D>, String>
where
    Mandel<D>: Dimension,
{
    transfer_state(previous.part(), state, next.part(), reset).map_err(|e| e.to_string())
}

/// The out-of-balance force of `state` in `model` at its time, `Bᵀσ − f(t)` on the free
/// dofs (N/m; 3D: N), which a stage releases: the module's documentation.
pub fn out_of_balance<const D: usize>(
    model: &Model<D>,
    state: &State<D>,
) -> Result<Vec<f64>, String>
where
    Mandel<D>: Dimension,
{
    let (internal, _) = model
        .assembly
        .internal_force(&state.sigma)
        .map_err(|e| e.to_string())?;
    let loads = model.loads_at(state.time);
    Ok(internal
        .iter()
        .zip(&loads.force_free)
        .map(|(b, f)| b - f)
        .collect())
}

/// Adds `release` (from [`out_of_balance`]) to `model` as a load ramped from 1 at `t0`
/// to 0 at `t1`.
pub fn add_release<const D: usize>(
    model: &mut Model<D>,
    release: Vec<f64>,
    t0: f64,
    t1: f64,
) -> Result<(), String>
where
    Mandel<D>: Dimension,
{
    let ramp = Ramp::try_new(&[[t0, 1.0], [t1, 0.0]]).map_err(|e| e.to_string())?;
    let prescribed = vec![0.0; model.assembly.dofs().n_prescribed()];
    model.add_load((release, prescribed), Some(ramp));
    Ok(())
}

/// The checks a run of `scene` makes before its first step: its model and initial state,
/// or, staged, every stage's model and the first one's initial state (`talus.Scene`
/// validates with it), in 2D (`D = 4`) or 3D (6).
pub fn check_before_run<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
) -> Result<(), SceneError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
    MeshOf<D>: SceneMesh<D>,
{
    match Stages::<D>::of(scene)? {
        Some(stages) => {
            for k in 0..stages.plans.len() {
                let stage = stages.model(scene, k)?;
                if k == 0 {
                    super::initial_state(scene, &stage.model)?;
                }
            }
        }
        None => {
            super::initial_state(scene, &super::build::unstaged::<N, D>(scene)?)?;
        }
    }
    Ok(())
}

/// The model a run of `scene` ends on: its last stage's (on that stage's part of the
/// mesh), or the whole scene's; the mesh its final state lives on.
pub fn final_model<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
) -> Result<Model<D>, SceneError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
    MeshOf<D>: SceneMesh<D>,
{
    match Stages::<D>::of(scene)? {
        Some(stages) => Ok(stages.model(scene, stages.plans.len() - 1)?.model),
        None => super::build::unstaged::<N, D>(scene),
    }
}
