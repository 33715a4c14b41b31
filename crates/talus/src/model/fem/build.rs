//! A finite-element [`Model`] from a scene: the mesh, its boundary conditions and loads,
//! the material, checked field by field against the scene's own scales.
use talus_fem::{
    Assembly, Constraint, Dimension, DofMap, ElementMesh, ElementOrder, FemError, Geometry, Mandel,
    Model, State,
};

use super::scene_mesh::{nearest_node, select_nodes, select_pieces, SceneMesh};
use crate::scene::dimension::three_d_key;
use crate::scene::{
    check, scales, scales::ramp_max, AnalysisKind, Fix, MeshSpec, Ramp, Scene, Scene3,
    SceneDocument, SceneError, SceneOf, SceneSpec, SceneVector, TimeSpec, WaterSpec, WaterTable,
};

/// The mesh of a model of Mandel size `D`: triangles (4) or tetrahedra (6).
pub type MeshOf<const D: usize> = <Mandel<D> as Dimension>::Mesh;

/// A model of 3D stress points: Mandel size 6.
pub type Model3 = Model<6>;
/// Its state.
pub type State3 = State<6>;

/// A [`Model`] built from a scene, and the state a run of it starts from.
pub trait FromScene: Sized {
    fn from_scene(scene: &Scene) -> Result<Self, SceneError>;
    /// The state at the start of a run: at rest, with the scene's initial stress (K₀
    /// procedure or uniform) or stress free.
    fn initial_state(&self, scene: &Scene) -> Result<State, SceneError>;
}

impl FromScene for Model {
    fn from_scene(scene: &Scene) -> Result<Self, SceneError> {
        unstaged(scene)
    }

    fn initial_state(&self, scene: &Scene) -> Result<State, SceneError> {
        initial_state(scene, self)
    }
}

/// The 3D model of `scene` (`[analysis] geometry = "3d"`, `docs/3d.md`), its stages'
/// loads and conditions all acting (a staged scene runs by `super::stages`).
pub fn model_3d(scene: &Scene3) -> Result<Model3, SceneError> {
    unstaged(scene)
}

/// The model of `scene` (2D or 3D) on its whole mesh.
pub(super) fn unstaged<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
) -> Result<Model<D>, SceneError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
    MeshOf<D>: SceneMesh<D>,
{
    let mesh = MeshOf::<D>::from_scene(scene)?;
    let ground = super::materials::ground(scene, &mesh)?;
    crate::scene::stage::check(scene, &scene.spec)?;
    check_scene(scene)?;
    build(scene, mesh, &ground.element_material, &ground, None)
}

/// The state at the start of a run of `model` (2D or 3D): at rest, with the scene's
/// initial stress (K₀ procedure or uniform) or stress free.
pub fn initial_state<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
    model: &Model<D>,
) -> Result<State<D>, SceneError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    let dofs = model.assembly.dofs();
    let mut state = State::at_rest(
        model.n_points(),
        dofs.n_free(),
        dofs.n_prescribed(),
        model.mesh.node_positions().len(),
    );
    if let Some(initial) = &scene.spec.initial_stress {
        state.sigma = crate::model::initial_stress(scene, model, initial)?;
    }
    Ok(state)
}

/// What a stage changes in the model it is built on (`super::stages`).
pub struct StageView<'a> {
    pub name: &'a str,
    /// The water table in force, and its field (`water` or a stage's `stage[k].water`).
    pub water: Option<(&'a WaterSpec, String)>,
}

/// The checks of the scene as a whole, once per run (not per stage's model): time, solver,
/// and the caps on steps (the stages' in all) and halvings.
pub(super) fn check_scene<V: SceneVector>(
    scene: &SceneDocument<SceneSpec<V>>,
) -> Result<(), SceneError> {
    let spec = &scene.spec;
    let time = TimeSpec {
        steps: spec.total_steps(),
        ..spec.time
    };
    check::time(scene, &time)?;
    // Loads finite before the scales read them (`check::loads`).
    check::loads(scene, &scene.spec)?;
    check::solver(scene, &spec.solver)?;
    // Before `caps`, whose field would be `time.steps`, which a staged scene leaves at 0.
    scales::stage_steps_cap(scene, &spec.stage)?;
    scales::caps(scene, &time, spec.solver.max_step_halvings)
}

/// The scene's model on `mesh` (the whole mesh, or a stage's part of it) whose elements'
/// materials are `element_material` (indices into `ground.materials`), with the loads and
/// conditions that act in `stage` (`None`: an unstaged scene, all of them). The scene's
/// own checks ([`check_scene`], `scene::stage::check`) were made by the caller.
pub(super) fn build<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
    mesh: MeshOf<D>,
    element_material: &[usize],
    ground: &super::materials::Ground,
    stage: Option<&StageView>,
) -> Result<Model<D>, SceneError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
    MeshOf<D>: SceneMesh<D>,
{
    let spec = &scene.spec;
    check_scales(scene, &mesh)?;
    let stage_name = stage.map(|s| s.name);
    let acts = |stages: &Option<Vec<String>>| SceneSpec::acts_in(stages, stage_name);
    // "in stage `name`": where a selection that held nodes on the whole mesh may not.
    let in_stage = stage.map_or(String::new(), |s| format!(" in stage \"{}\"", s.name));

    // Axisymmetric: the axis nodes' radial velocity is 0, first, so that a
    // `[[boundary]]` naming them later owns them (and their reaction).
    let geometry = spec.analysis.geometry.fem();
    (mesh.check_geometry(geometry)).map_err(|e| scene.error("analysis.geometry", e))?;
    let axis = mesh.axis_nodes(geometry);
    let mut constraints = Vec::new();
    if !axis.is_empty() {
        constraints.push((axis.clone(), Constraint::FixX));
    }
    let axis_constraints = constraints.len();
    let mut boundary_ramps = Vec::new();
    for (k, b) in spec.boundary.iter().enumerate() {
        if !acts(&b.stages) {
            boundary_ramps.push(None);
            constraints.push((Vec::new(), Constraint::Fixed));
            continue;
        }
        let field = format!("boundary[{k}].nodes");
        let nodes = select_nodes(scene, &mesh, &b.nodes, &field, &in_stage)?;
        let Some(c) = MeshOf::<D>::constraint(b.fix) else {
            let what = format!("{:?} names z, which", b.fix);
            return Err(three_d_key(scene, &format!("boundary[{k}].fix"), &what));
        };
        if !b.velocity.iter().all(|v| v.is_finite()) {
            return Err(scene.error(&format!("boundary[{k}].velocity"), "must be finite"));
        }
        // The axis r = 0 cannot move radially (docs/axisymmetry.md): a radial velocity
        // there would tear the body open along its axis.
        let radial = matches!(b.fix, Fix::X | Fix::Xy) && b.velocity[0] != 0.0;
        if let Some(&n) = nodes.iter().find(|n| radial && axis.contains(n)) {
            let v = b.velocity.as_ref();
            return Err(scene.error(
                &format!("boundary[{k}].velocity"),
                format!(
                    "[{:e}, {:e}] m/s moves node {n} on the axis r = 0 radially; the \
                         axis has no radial velocity: use velocity = [0, {:e}] or leave the \
                         axis out of the set",
                    v[0], v[1], v[1]
                ),
            ));
        }
        boundary_ramps.push(check::ramp(scene, &format!("boundary[{k}].ramp"), &b.ramp)?);
        constraints.push((nodes, c));
    }
    let dofs = DofMap::with_components(mesh.node_positions().len(), N, &constraints)
        .map_err(|e| scene.error("boundary", e.to_string()))?;
    if dofs.n_free() == 0 {
        return Err(scene.error("boundary", "every degree of freedom is prescribed"));
    }
    let water = match stage {
        Some(StageView {
            water: Some((w, field)),
            ..
        }) => Some(WaterTable::try_new(scene, field, w)?),
        Some(_) => None,
        None => water_table(scene)?,
    };
    let (assembly, densities) = assembly_with_densities(
        scene,
        &mesh,
        &dofs,
        element_material,
        water.as_ref(),
        geometry,
    )?;
    let point_material: Vec<usize> = assembly
        .gauss_element
        .iter()
        .map(|&e| element_material[e])
        .collect();

    // A stage may switch the reported boundary off: its reaction is 0 there.
    let switched_off = spec.output.reaction.as_ref().is_some_and(|name| {
        spec.boundary
            .iter()
            .any(|b| b.name.as_ref() == Some(name) && !acts(&b.stages))
    });
    let boundary_nodes: Vec<Vec<usize>> = constraints[axis_constraints..]
        .iter()
        .map(|(nodes, _)| nodes.clone())
        .collect();
    let motion = super::motion::prescribed_motion(
        scene,
        &boundary_nodes,
        boundary_ramps,
        &dofs,
        switched_off,
    )?;

    // Added to the model in the order of the scene: a load without a ramp into the
    // constant forces, a ramped one kept apart at multiplier 1 (`Model::add_load`).
    let mut loads = Vec::new();
    let mut add_load = |forces: (Vec<f64>, Vec<f64>), ramp: Option<Ramp>| {
        loads.push((forces, ramp));
    };
    let gravity_ramp = check::ramp(scene, "gravity_ramp", &spec.gravity_ramp)?;
    match spec.gravity {
        Some(g) => add_load(
            point_weight(scene, &assembly, &densities, g)?,
            gravity_ramp.clone(),
        ),
        None if gravity_ramp.is_some() => {
            return Err(scene.error("gravity_ramp", "multiplies `gravity`, which is not given"))
        }
        None => {}
    }
    // The water's push on the free boundary below the table (`water_loads`), following
    // the weight's ramp as the pore pressure does.
    if let Some(w) = &water {
        let pieces = free_below(
            mesh.boundary_pieces(),
            MeshOf::<D>::piece_nodes,
            mesh.node_positions(),
            &dofs,
            w,
        );
        if !pieces.is_empty() {
            add_load(
                mesh.pressure_with(&assembly, &pieces, |x| w.pore_pressure(x))
                    .map_err(|e| scene.error("water", e))?,
                gravity_ramp.clone(),
            );
        }
    }
    for (k, t) in spec.traction.iter().enumerate() {
        if !acts(&t.stages) {
            continue;
        }
        let field = format!("traction[{k}].{}", MeshOf::<D>::PIECES);
        let pieces = select_pieces(scene, &mesh, &t.edges, &field, &in_stage)?;
        (mesh.check_loaded(&pieces, geometry)).map_err(|e| scene.error(&field, e))?;
        let ramp = check::ramp(scene, &format!("traction[{k}].ramp"), &t.ramp)?;
        add_load(
            (mesh.traction(&assembly, &pieces, t.value))
                .map_err(|e| scene.error(&format!("traction[{k}].value"), e))?,
            ramp,
        );
    }
    for (k, p) in spec.pressure.iter().enumerate() {
        if !acts(&p.stages) {
            continue;
        }
        let field = format!("pressure[{k}].{}", MeshOf::<D>::PIECES);
        let pieces = select_pieces(scene, &mesh, &p.edges, &field, &in_stage)?;
        (mesh.check_loaded(&pieces, geometry)).map_err(|e| scene.error(&field, e))?;
        let ramp = check::ramp(scene, &format!("pressure[{k}].ramp"), &p.ramp)?;
        // `gradient` varies the pressure along y (water against a wall).
        let forces = match p.gradient {
            None => mesh.pressure(&assembly, &pieces, p.value),
            Some(g) => mesh.pressure_with(&assembly, &pieces, |x| p.value + g * x[1]),
        };
        add_load(forces.map_err(|e| scene.error(&field, e))?, ramp);
    }
    for (k, l) in spec.point_load.iter().enumerate() {
        if !acts(&l.stages) {
            continue;
        }
        let field = format!("point_load[{k}]");
        let ramp = check::ramp(scene, &format!("{field}.ramp"), &l.ramp)?;
        let node = nearest_node(mesh.node_positions(), l.point.as_ref());
        add_load(
            assembly
                .point_force(node, l.force)
                .map_err(|e| scene.error(&format!("{field}.force"), e.to_string()))?,
            ramp,
        );
    }
    let mut model = Model::with_materials(mesh, assembly, ground.materials.clone(), point_material)
        .map_err(|e| scene.error("material", e.to_string()))?;
    if let Some(w) = &water {
        model.pore_pressure = (model.assembly.gauss_points.iter())
            .map(|&x| w.pore_pressure(x))
            .collect();
        model.pore_pressure_ramp = gravity_ramp;
    }
    for (forces, ramp) in loads {
        model.add_load(forces, ramp);
    }
    super::quasi_static::scale_masses(scene, &mut model)?;
    model.prescribed_velocity = motion.velocity;
    model.velocity_ramps = motion.velocity_ramps;
    model.reaction_dofs = motion.reaction_dofs;
    model.reaction_direction = motion.reaction_direction;
    model.dof_owner = motion.owner;
    Ok(model)
}

/// What a run of `model` should be told (`summary.json`'s `warnings`): plastic flow on
/// P1 triangles, which lock (Prandtl's N_c 6.0–6.8% too high on 40×28 cells against 0.6–1.3%
/// with P2, `docs/verification.md`), or on P1 tetrahedra, which lock more.
pub fn warnings<const N: usize, const D: usize>(scene: &SceneOf<N>, model: &Model<D>) -> Vec<String>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    let plastic = model.materials.iter().any(|m| m.drucker_prager().is_some());
    if !plastic || model.mesh.order() != ElementOrder::P1 {
        return Vec::new();
    }
    if N == 3 {
        return vec![
            "plastic flow on P1 (4-node) tetrahedra: they lock, more still than P1 \
              triangles, and overestimate limit loads and factors of safety; mesh with P2 \
              (10-node) tetrahedra"
                .to_string(),
        ];
    }
    let gmsh = matches!(scene.spec.mesh, MeshSpec::Gmsh { .. });
    vec![format!(
        "plastic flow on P1 (3-node) triangles: they lock and overestimate limit loads \
         (Prandtl's N_c by 6.0–6.8% on 40×28 cells, against 0.6–1.3% with P2; \
         docs/verification.md); use {}",
        if gmsh {
            "[mesh.gmsh] order = \"P2\", which adds mid-edge nodes to a linear mesh"
        } else {
            "order = \"P2\""
        }
    )]
}

/// The assembly of `mesh` (2D or 3D) and each Gauss point's density (kg/m³): its
/// material's, saturated below the water table. The points' layout is mapped ahead of the
/// assembly only when the densities vary (layers, a water table); one density everywhere
/// gives the scalar assembly (a layered scene of one material is the one-material model
/// bit for bit).
pub(super) fn assembly_with_densities<const N: usize, const D: usize, M>(
    scene: &SceneOf<N>,
    mesh: &M,
    dofs: &DofMap,
    element_material: &[usize],
    water: Option<&WaterTable>,
    geometry: Geometry,
) -> Result<(Assembly<D>, Vec<f64>), SceneError>
where
    M: ElementMesh<Dim = Mandel<D>>,
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    let dry = required_densities(scene)?;
    let densities = if water.is_none() && dry.iter().all(|d| *d == dry[0]) {
        Vec::new()
    } else {
        let (elements, positions) = Assembly::<D>::gauss_layout(mesh, geometry)
            .map_err(|e| scene.error("mesh", e.to_string()))?;
        let point_material: Vec<usize> = elements.iter().map(|&e| element_material[e]).collect();
        let below: Vec<bool> = positions
            .iter()
            .map(|&x| water.is_some_and(|w| w.pore_pressure(x) > 0.0))
            .collect();
        point_densities(scene, &point_material, &below)?
    };
    let uniform = densities
        .iter()
        .all(|d| *d == densities.first().copied().unwrap_or(dry[0]));
    let assembly = if uniform {
        Assembly::with_geometry(
            mesh,
            dofs,
            densities.first().copied().unwrap_or(dry[0]),
            geometry,
        )
    } else {
        Assembly::with_point_densities(mesh, dofs, &densities, geometry)
    }
    .map_err(|e| {
        let field = match &e {
            FemError::InvalidInput {
                field: "density", ..
            } => "material.density",
            _ if geometry == Geometry::Axisymmetric => "analysis.geometry",
            _ => "material.density",
        };
        scene.error(field, e.to_string())
    })?;
    let densities = if densities.is_empty() {
        vec![dry[0]; assembly.n_points()]
    } else {
        densities
    };
    Ok((assembly, densities))
}

/// The weight of gravity `g` (m/s²) on the body (N/m in 2D, N in 3D) with each Gauss
/// point's density: the scalar integration when they are all one (the weight of a
/// one-material scene, bit for bit).
pub(super) fn point_weight<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
    assembly: &Assembly<D>,
    densities: &[f64],
    g: [f64; N],
) -> Result<(Vec<f64>, Vec<f64>), SceneError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    if densities.iter().all(|d| *d == densities[0]) {
        assembly.body_force(densities[0], g)
    } else {
        assembly.body_force_at_points(densities, g)
    }
    .map_err(|e| scene.error("gravity", e.to_string()))
}

/// The weight of gravity `g` (m/s²) on `model` built from `scene`, each point with its
/// density, saturated where the model has pore pressure (free and prescribed dofs): what
/// `[stability] method = "gravity_increase"` multiplies.
pub fn weight<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
    model: &Model<D>,
    g: [f64; N],
) -> Result<(Vec<f64>, Vec<f64>), SceneError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    let below: Vec<bool> = (0..model.n_points())
        .map(|p| model.pore_pressure.get(p).is_some_and(|&pw| pw > 0.0))
        .collect();
    let densities = point_densities(scene, &model.point_material, &below)?;
    point_weight(scene, &model.assembly, &densities, g)
}

/// The boundary pieces the water pushes on (`pieces`: edges in 2D, faces in 3D, with their
/// nodes `nodes_of`): those with a node below the table that are free, i.e. not every node
/// of theirs has a prescribed component (a slope face, the floor of a flooded cut; not a
/// fixed base or a side on rollers, whose supports would carry the push into their
/// reaction alone).
pub(super) fn free_below<B, const N: usize>(
    pieces: Vec<B>,
    nodes_of: impl Fn(&B) -> &[usize],
    positions: &[[f64; N]],
    dofs: &DofMap,
    water: &WaterTable,
) -> Vec<B> {
    let held = |n: usize| (0..N).any(|c| dofs.prescribed(n, c).is_some());
    pieces
        .into_iter()
        .filter(|e| {
            let nodes = nodes_of(e);
            nodes
                .iter()
                .any(|&n| water.pore_pressure(positions[n]) > 0.0)
                && !nodes.iter().all(|&n| held(n))
        })
        .collect()
}

/// The scene's water table, checked (`None`: dry).
pub fn water_table<V: SceneVector>(
    scene: &SceneDocument<SceneSpec<V>>,
) -> Result<Option<WaterTable>, SceneError> {
    scene
        .spec
        .water
        .as_ref()
        .map(|w| WaterTable::try_new(scene, "water", w))
        .transpose()
}

/// Each Gauss point's density (kg/m³): its material's, saturated where `below` (the
/// water table).
fn point_densities<V: SceneVector>(
    scene: &SceneDocument<SceneSpec<V>>,
    point_material: &[usize],
    below: &[bool],
) -> Result<Vec<f64>, SceneError> {
    let dry = required_densities(scene)?;
    let all = scene.spec.material.all();
    Ok(point_material
        .iter()
        .zip(below)
        .map(|(&m, &below)| match below {
            true => all[m].saturated_density.unwrap_or(dry[m]),
            false => dry[m],
        })
        .collect())
}

/// The density (kg/m³) of each material: required by a dynamic analysis (the mass) and by
/// gravity (the weight); a weightless quasi-static scene may leave it out (its masses are
/// scaled from the stiffness, `super::quasi_static`).
pub(super) fn required_densities<V: SceneVector>(
    scene: &SceneDocument<SceneSpec<V>>,
) -> Result<Vec<f64>, SceneError> {
    let spec = &scene.spec;
    let materials = &spec.material;
    let field = |k: usize| format!("{}.density", materials.field(k));
    materials
        .all()
        .iter()
        .enumerate()
        .map(|(k, m)| match m.density {
            Some(d) => Ok(d),
            None if spec.gravity.is_some() => Err(scene.error(
                &field(k),
                "is required with `gravity` (the weight of the ground)",
            )),
            None if spec.analysis.kind == AnalysisKind::Dynamic => Err(scene.error(
                &field(k),
                "is required by a dynamic analysis (the mass); a quasi-static one \
                 ([analysis] kind = \"quasi_static\") without gravity does not need it",
            )),
            None => Ok(1.0),
        })
        .collect()
}

/// The scene against its own scales (`scene::scales`): `h` against the wave time of the
/// smallest element and the boundaries' motion, the stresses against E (the caps:
/// [`check_scene`]), in 2D and 3D.
fn check_scales<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
    mesh: &MeshOf<D>,
) -> Result<(), SceneError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
    MeshOf<D>: SceneMesh<D>,
{
    use scales::norm;
    let spec = &scene.spec;
    let (mut lo, mut hi) = ([f64::INFINITY; N], [f64::NEG_INFINITY; N]);
    for p in mesh.node_positions() {
        for k in 0..N {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let cell = mesh.smallest_cell();
    let tractions = spec.traction.iter().enumerate().map(|(k, t)| {
        (
            format!("traction[{k}].value"),
            norm(&t.value) * ramp_max(&t.ramp),
        )
    });
    let pressures = spec.pressure.iter().enumerate().map(|(k, p)| {
        // Linear in y: largest at the body's top or bottom.
        let at = |y: f64| (p.value + p.gradient.unwrap_or(0.0) * y).abs();
        let v = at(lo[1]).max(at(hi[1])) * ramp_max(&p.ramp);
        (format!("pressure[{k}].value"), v)
    });
    // A point force spread over the smallest cell (3D: its face), as a stress.
    let points = spec.point_load.iter().enumerate().map(|(k, l)| {
        let v = norm(&l.force) * ramp_max(&l.ramp) / cell.powi(N as i32 - 1);
        (format!("point_load[{k}].force"), v)
    });
    let speeds = spec.boundary.iter().enumerate().map(|(k, b)| {
        (
            format!("boundary[{k}].velocity"),
            norm(&b.velocity) * ramp_max(&b.ramp),
        )
    });
    let imposed = scales::Imposed {
        materials: (spec.material.all().iter().enumerate())
            .map(|(k, m)| (spec.material.field(k), m))
            .collect(),
        time: &spec.time,
        // The scales read |g| only.
        gravity: spec.gravity.map(|g| norm(&g)),
        heights: [lo[1], hi[1]],
        initial_stress: spec.initial_stress.as_ref(),
        loads: tractions.chain(pressures).chain(points).collect(),
        speeds: speeds.collect(),
    };
    let body = scales::Scales {
        cell,
        max_step_motion: (0..N).map(|k| hi[k] - lo[k]).fold(f64::INFINITY, f64::min),
        motion_limit: "the body's smallest side",
        dynamic: spec.analysis.kind == AnalysisKind::Dynamic,
    };
    scales::check_scales(scene, &imposed, &body)
}
