//! A material-point model from a scene (`[grid]`), 2D or 3D (`docs/3d-mpm.md`): the solver
//! and its particles, every input checked first so that a bad scene is an error naming the
//! field and the value, never a panic. One build for both dimensions; what differs (the
//! grid, the bodies' fills) is [`MpmSpace`].
use talus_mpm::{
    front, radial_front, Dimension, Grid, GridBoundary, Mandel, Mpm, MpmError, MpmSettings,
    Particles, PrescribedVelocity, ShapeFunction, Side, Wall, WallCondition,
};

use talus_bipotential::Material;

use crate::scene::{
    check, check_mpm_dimension, scales,
    scales::{norm, ramp_max},
    AnalysisKind, BodySpec, CylinderSpec, GeometryKind, InitialStressSpec, Materials, MpmScene,
    MpmScene3, MpmSceneSpec, PredictorSpec, Ramp, SceneDocument, SceneError, SceneVector,
    ShapeSpec, SideSpec, WallConditionSpec,
};
use talus_engine::{PredictorRule, StepSettings};
use talus_mpm::{MpmLoadProgramme, ProgrammedMpm, RampedSurfaceLoad, RunoutReference};

use crate::model::initial_stress_at;

/// An MPM scene of `N` dimensions.
pub type MpmDocument<const N: usize> = SceneDocument<MpmSceneSpec<[f64; N]>>;

/// Everything a run needs: the solver, the particles at t = 0, and what to report; `D` the
/// Mandel size (4 in 2D, 6 in 3D).
pub struct MpmModel<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    /// The solver with the scene's load programme (it reads as an [`Mpm`]).
    pub mpm: ProgrammedMpm<D>,
    /// How the engine steps it (`[solver]`, `[mpm] predictor`).
    pub step_settings: StepSettings,
    pub particles: Particles<D>,
    /// The `output.reaction` box, if any.
    pub reaction: Option<Reaction>,
    pub runout: Runout,
    /// y of the bottom wall, if there is one (m).
    pub floor: Option<f64>,
    /// The grid's extent in x and y `[[x0, y0], [x1, y1]]` (m), the frame of every PNG
    /// (in 3D the particles seen along z).
    pub bounds: [[f64; 2]; 2],
}

/// How a run measures the runout of its bodies (history.csv's `front` and
/// `runout_normalized`, `docs/scenes.md`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Runout {
    /// The largest particle x, against the bodies' extent from the left wall
    /// ([`RunoutReference`]): 2D, and 3D bodies that are not all one cylinder.
    Front(RunoutReference),
    /// 3D bodies that are one vertical cylinder (or its quarter): the largest distance `R`
    /// of a particle from its axis `[x_c, z_c]`, against its radius `R₀`:
    /// `(R − R₀)/R₀`, Lube et al. (2004)'s runout.
    Radial { axis: [f64; 2], radius: f64 },
}

impl Runout {
    /// The front of `particles` (m): x, or the distance from the axis.
    pub fn front<const D: usize>(&self, particles: &Particles<D>) -> f64
    where
        Mandel<D>: Dimension,
    {
        match self {
            Runout::Front(_) => front(particles),
            Runout::Radial { axis, .. } => radial_front(particles, *axis),
        }
    }

    /// What [`normalized`](Self::normalized) measures, for a run's last line.
    pub fn measure(&self) -> &'static str {
        match self {
            Runout::Front(_) => "(L − L0)/L0",
            Runout::Radial { .. } => "(R − R0)/R0",
        }
    }

    /// `(L − L₀)/L₀` or `(R − R₀)/R₀` of a `front` (m).
    pub fn normalized(&self, front: f64) -> f64 {
        match self {
            Runout::Front(r) => r.normalized(front),
            Runout::Radial { radius, .. } => (front - radius) / radius,
        }
    }
}

/// What an MPM scene of Mandel size `D` builds its own way; the rest of the build is one
/// for both.
pub trait MpmSpace<const D: usize>: Dimension<Point: SceneVector>
where
    Mandel<D>: Dimension,
{
    /// The grid of the scene's `origin`, `spacing`, `cells` (checked) and shape.
    fn grid(
        origin: Self::Point,
        spacing: f64,
        cells: <Self::Point as SceneVector>::Cells,
        shape: ShapeFunction,
    ) -> Result<Grid<D>, MpmError>;

    /// The particles of a body (its shape checked by [`body_shape`]), or why not.
    fn fill(
        shape: &BodyShape<Self::Point>,
        spacing: f64,
        per_cell: usize,
        density: f64,
    ) -> Result<Particles<D>, String>;

    /// The prescribed components of a box from `[vx, vy(, vz)]`.
    fn components(v: &[Option<f64>]) -> Self::Components;
}

impl MpmSpace<4> for Mandel<4> {
    fn grid(
        origin: [f64; 2],
        spacing: f64,
        cells: [usize; 2],
        shape: ShapeFunction,
    ) -> Result<Grid, MpmError> {
        Grid::try_new(origin, spacing, cells, shape)
    }

    fn fill(
        shape: &BodyShape<[f64; 2]>,
        spacing: f64,
        per_cell: usize,
        density: f64,
    ) -> Result<Particles, String> {
        match shape {
            BodyShape::Cuboid(r) => {
                Particles::fill_rectangle(*r, spacing, per_cell, density).map_err(|e| e.to_string())
            }
            // `check_mpm_dimension` refuses a cylinder in 2D.
            BodyShape::Cylinder(_) => Err("a cylinder is 3D".into()),
        }
    }

    fn components(v: &[Option<f64>]) -> [Option<f64>; 2] {
        [v[0], v[1]]
    }
}

impl MpmSpace<6> for Mandel<6> {
    fn grid(
        origin: [f64; 3],
        spacing: f64,
        cells: [usize; 3],
        shape: ShapeFunction,
    ) -> Result<Grid<6>, MpmError> {
        Grid::try_new_3d(origin, spacing, cells, shape)
    }

    fn fill(
        shape: &BodyShape<[f64; 3]>,
        spacing: f64,
        per_cell: usize,
        density: f64,
    ) -> Result<Particles<6>, String> {
        let filled = match shape {
            BodyShape::Cuboid(b) => Particles::fill_box(*b, spacing, per_cell, density),
            BodyShape::Cylinder(c) => {
                let base = [c.centre[0], c.base, c.centre[1]];
                let fill = if c.quarter {
                    Particles::fill_quarter_cylinder
                } else {
                    Particles::fill_cylinder
                };
                fill(base, c.radius, c.height, spacing, per_cell, density)
            }
        };
        filled.map_err(|e| e.to_string())
    }

    fn components(v: &[Option<f64>]) -> [Option<f64>; 3] {
        [v[0], v[1], v[2]]
    }
}

/// A body's checked shape: a rectangle (3D: box) by its corners, or a cylinder.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BodyShape<V> {
    Cuboid([V; 2]),
    Cylinder(CylinderSpec),
}

impl<V: SceneVector> BodyShape<V> {
    /// The `[[body]]` key that gives this shape: `rectangle` (2D), `box` (3D), `cylinder`.
    pub fn key(&self) -> &'static str {
        match self {
            BodyShape::Cuboid(_) if V::DIM == 3 => "box",
            BodyShape::Cuboid(_) => "rectangle",
            BodyShape::Cylinder(_) => "cylinder",
        }
    }
}

/// The prescribed box whose force goes into history.csv.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reaction {
    /// Its index in `StepReport::group_forces` (after the walls).
    pub group: usize,
    /// Its prescribed vertical velocity (m/s), if any.
    pub velocity_y: Option<f64>,
}

/// Tolerance on geometric comparisons, relative to the cell size.
const EPS: f64 = 1e-9;

impl MpmModel {
    /// The model of a 2D scene.
    pub fn from_scene(scene: &MpmScene) -> Result<Self, SceneError> {
        Self::build(scene)
    }
}

impl MpmModel<6> {
    /// The model of a 3D scene (`[analysis] geometry = "3d"`).
    pub fn from_scene_3d(scene: &MpmScene3) -> Result<Self, SceneError> {
        Self::build(scene)
    }
}

impl<const D: usize> MpmModel<D>
where
    Mandel<D>: Dimension,
{
    /// The model of a scene of either dimension.
    pub fn build<const N: usize>(scene: &MpmDocument<N>) -> Result<Self, SceneError>
    where
        Mandel<D>: MpmSpace<D> + Dimension<Point = [f64; N]>,
        [f64; N]: SceneVector,
    {
        let spec = &scene.spec;
        check_mpm_dimension(&scene.source, scene.path.as_ref(), N)?;
        let three_d = N == 3;
        let geometry = spec.analysis.geometry;
        if three_d != (geometry == GeometryKind::ThreeD) {
            let message = if three_d {
                format!(
                    "{:?}: a 3D material point scene has geometry = \"3d\"",
                    geometry
                )
            } else {
                crate::scene::dimension::NO_3D_RUN.to_string()
            };
            return Err(scene.error("analysis.geometry", message));
        }
        let grid = grid(scene)?;
        let materials = materials(scene)?;
        if spec.analysis.kind == AnalysisKind::QuasiStatic {
            return Err(scene.error(
                "analysis.kind",
                "\"quasi_static\" is for finite-element scenes ([mesh]); a material point \
                 scene ([grid]) runs \"dynamic\" only",
            ));
        }
        if spec.analysis.geometry == GeometryKind::Axisymmetric {
            return Err(scene.error(
                "analysis.geometry",
                "\"axisymmetric\" is for finite-element scenes ([mesh]); a material point \
                 scene ([grid]) is plane strain or 3D",
            ));
        }
        if let Some(r) = spec.analysis.inertia_ratio {
            return Err(scene.error(
                "analysis.inertia_ratio",
                format!("{r} applies to quasi-static finite-element scenes only"),
            ));
        }
        let densities = densities(scene)?;
        let gravity = spec.gravity.unwrap_or([0.0; N]);
        if !gravity.iter().all(|g| g.is_finite()) {
            return Err(scene.error("gravity", format!("{gravity:?} m/s² must be finite")));
        }
        let gravity_ramp = check::ramp(scene, "gravity_ramp", &spec.gravity_ramp)?;
        if gravity_ramp.is_some() && spec.gravity.is_none() {
            return Err(scene.error("gravity_ramp", "multiplies `gravity`, which is not given"));
        }
        check::time(scene, &spec.time)?;
        scales::caps(scene, &spec.time, spec.solver.max_step_halvings)?;
        let shapes = body_shapes(scene, &grid)?;
        let mut particles = bodies(scene, &grid, &shapes, &materials, &densities)?;
        let walls = walls(scene)?;
        let (prescribed, prescribed_ramps) = prescribed(scene, &grid)?;
        let reaction = reaction(scene, walls.len(), &prescribed)?;
        let ramped_surface_loads = surface_loads(scene, &mut particles)?;
        if let Some(initial) = &spec.initial_stress {
            // In equilibrium with the gravity of the start, t = 0 (`gravity_ramp` scales it).
            let gammas: Vec<f64> = densities
                .iter()
                .map(|density| match &gravity_ramp {
                    Some(r) => -density * gravity[1] * r.at(0.0),
                    None => -density * gravity[1],
                })
                .collect();
            particles.stress =
                initial_stress(scene, initial, &materials, &gammas, &densities, &particles)?;
        }
        check::time(scene, &spec.time)?;
        check::solver(scene, &spec.solver)?;
        check_scales(scene, &shapes)?;
        let settings = settings(scene)?;
        let floor = walls
            .iter()
            .any(|w| w.side == Side::Bottom)
            .then_some(grid.origin()[1]);
        let has_left_wall = walls.iter().any(|w| w.side == Side::Left);
        let runout = runout(&shapes, has_left_wall.then_some(grid.origin()[0]));
        let (o, e) = (grid.origin(), grid.end());
        let bounds = [[o[0], o[1]], [e[0], e[1]]];
        let boundary = GridBoundary { walls, prescribed };
        let mpm = Mpm::with_materials(grid, boundary, &materials.materials, gravity, settings)
            .map_err(|e| scene.error("grid", e.to_string()))?;
        let programme = MpmLoadProgramme {
            gravity: gravity_ramp,
            prescribed: prescribed_ramps,
            surface_loads: ramped_surface_loads,
        };
        Ok(Self {
            mpm: ProgrammedMpm::new(mpm, programme),
            step_settings: step_settings(scene),
            particles,
            reaction,
            runout,
            floor,
            bounds,
        })
    }
}

/// The runout of bodies of `shapes`: radial when they are one cylinder (the column of
/// Lube et al. 2004), else the x front from the bodies' extent (`left_wall`: the x of the
/// left wall, if any).
fn runout<V: SceneVector>(shapes: &[BodyShape<V>], left_wall: Option<f64>) -> Runout {
    if let [BodyShape::Cylinder(c)] = shapes {
        return Runout::Radial {
            axis: c.centre,
            radius: c.radius,
        };
    }
    Runout::Front(RunoutReference::of_bodies(
        shapes.iter().map(|s| {
            let [lo, hi] = extent(s);
            [[lo[0], lo[1]], [hi[0], hi[1]]]
        }),
        left_wall,
    ))
}

/// The scene's materials, checked, and the material of each body.
pub struct BodyMaterials {
    /// In file order: the particles' material indices point into it.
    materials: Vec<Material>,
    /// Each `[[body]]`'s index into `materials`.
    body: Vec<usize>,
    /// A `[[material]]` list: the particles carry their indices (a single `[material]`
    /// leaves them empty, all of material 0, as before there were several).
    list: bool,
}

/// `[material]` (every body of it) or a `[[material]]` list whose every material has a
/// `name`, is used by a body, and names no `regions` (the bodies place the materials);
/// each `[[body]]` names its `material` (optional with a single one).
fn materials<V: SceneVector>(
    scene: &SceneDocument<MpmSceneSpec<V>>,
) -> Result<BodyMaterials, SceneError> {
    let spec = &scene.spec;
    let all = spec.material.all();
    let list = matches!(spec.material, Materials::Many(_));
    let mut materials = Vec::with_capacity(all.len());
    // The materials' names, in order (a single `[material]` may have none).
    let mut names: Vec<&str> = Vec::with_capacity(all.len());
    for (k, m) in all.iter().enumerate() {
        let field = spec.material.field(k);
        if !m.regions.is_empty() {
            return Err(scene.error(
                &format!("{field}.regions"),
                format!(
                    "{:?}: regions place materials in finite-element scenes ([mesh]); in a \
                     material point scene ([grid]) each [[body]] names its material \
                     (material = \"name\")",
                    m.regions
                ),
            ));
        }
        materials.push(check::material(scene, &field, m)?);
        match &m.name {
            Some(name) => {
                if let Some(j) = names.iter().position(|n| n == name) {
                    return Err(scene.error(
                        &format!("{field}.name"),
                        format!("\"{name}\" is also the name of material[{j}]"),
                    ));
                }
                names.push(name);
            }
            None if list => {
                return Err(scene.error(
                    &format!("{field}.name"),
                    "is required in a [[material]] list (each [[body]] names its material)",
                ));
            }
            None => {}
        }
    }
    let known = || {
        if names.is_empty() {
            "the one [material] has no name".to_string()
        } else {
            let quoted: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
            format!("materials: {}", quoted.join(", "))
        }
    };
    let mut body = Vec::with_capacity(spec.body.len());
    for (k, b) in spec.body.iter().enumerate() {
        let field = format!("body[{k}].material");
        let index = match &b.material {
            None if list => {
                return Err(scene.error(
                    &field,
                    format!(
                        "missing: with a [[material]] list every [[body]] names its material \
                         (material = \"name\"; {})",
                        known()
                    ),
                ));
            }
            None => 0,
            Some(name) => names.iter().position(|n| n == name).ok_or_else(|| {
                scene.error(
                    &field,
                    format!("\"{name}\" is no material of the scene ({})", known()),
                )
            })?,
        };
        body.push(index);
    }
    // Without bodies, `bodies` says so.
    if list && !body.is_empty() {
        if let Some(k) = (0..all.len()).find(|k| !body.contains(k)) {
            return Err(scene.error(
                &format!("{}.name", spec.material.field(k)),
                format!(
                    "\"{}\" is the material of no [[body]]: give a body material = \"{0}\", \
                     or remove it",
                    names[k]
                ),
            ));
        }
    }
    Ok(BodyMaterials {
        materials,
        body,
        list,
    })
}

/// Each material's density (kg/m³): required, the particles' mass.
fn densities<V: SceneVector>(
    scene: &SceneDocument<MpmSceneSpec<V>>,
) -> Result<Vec<f64>, SceneError> {
    let materials = &scene.spec.material;
    let mut densities = Vec::with_capacity(materials.all().len());
    for (k, m) in materials.all().iter().enumerate() {
        let field = format!("{}.density", materials.field(k));
        let density = m.density.ok_or_else(|| {
            scene.error(&field, "is required by a material point scene (the mass)")
        })?;
        if !(density.is_finite() && density > 0.0) {
            return Err(scene.error(&field, format!("{density} kg/m³ must be finite and > 0")));
        }
        densities.push(density);
    }
    Ok(densities)
}

/// `[initial_stress]` at every particle, each checked against its own material's cone (an
/// elastic material has none). `gammas`: each material's unit weight at t = 0 (N/m³). The
/// K₀ procedure takes one unit weight: bodies of different densities under gravity are
/// refused (the weight of the layers above a particle is not known to MPM yet).
fn initial_stress<const D: usize, const N: usize>(
    scene: &MpmDocument<N>,
    initial: &InitialStressSpec<[f64; N]>,
    materials: &BodyMaterials,
    gammas: &[f64],
    densities: &[f64],
    particles: &Particles<D>,
) -> Result<Vec<[f64; D]>, SceneError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    let spec = &scene.spec;
    // The form and the numbers first (no point, no cone): the errors below are a
    // material's, at its particles.
    initial_stress_at::<D, _>(scene, None, gammas[0], initial, &[] as &[[f64; N]], None)?;
    if initial.k0.is_some() && gammas.iter().any(|g| *g != gammas[0]) {
        let all = spec.material.all();
        let listed: Vec<String> = (densities.iter().enumerate())
            .map(|(k, d)| match &all[k].name {
                Some(name) => format!("{} (\"{name}\") {d} kg/m³", spec.material.field(k)),
                None => format!("{} {d} kg/m³", spec.material.field(k)),
            })
            .collect();
        return Err(scene.error(
            "initial_stress.k0",
            format!(
                "the K₀ procedure of a material point scene takes one density, but the \
                 bodies' materials have {}: give them equal densities, or a uniform `stress` \
                 (layers of different densities are for finite-element scenes today)",
                listed.join(", ")
            ),
        ));
    }
    let mut stress = vec![[0.0; D]; particles.len()];
    for (k, material) in materials.materials.iter().enumerate() {
        let members: Vec<usize> = (0..particles.len())
            .filter(|&p| particles.material_of(p) == k)
            .collect();
        if members.is_empty() {
            continue;
        }
        let points: Vec<[f64; N]> = members.iter().map(|&p| particles.position[p]).collect();
        let at = initial_stress_at(
            scene,
            material.drucker_prager(),
            gammas[k],
            initial,
            &points,
            None,
        )
        .map_err(|mut e| {
            if materials.list {
                let name = spec.material.all()[k].name.as_deref().unwrap_or_default();
                e.message.push_str(&format!(
                    " (at the particles of {} \"{name}\")",
                    spec.material.field(k)
                ));
            }
            e
        })?;
        for (&p, s) in members.iter().zip(at) {
            stress[p] = s;
        }
    }
    Ok(stress)
}

/// The scene against its own scales (`scene::scales`): `h` against the wave time of a cell
/// and the boxes' motion (at most a cell per step), the stresses against E.
fn check_scales<V: SceneVector>(
    scene: &SceneDocument<MpmSceneSpec<V>>,
    shapes: &[BodyShape<V>],
) -> Result<(), SceneError> {
    let spec = &scene.spec;
    let dx = spec.grid.spacing;
    let (bottom, top) = shapes
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(b, t), s| {
            let [lo, hi] = extent(s);
            (b.min(lo[1]), t.max(hi[1]))
        });
    let loads = spec.surface_load.iter().enumerate().map(|(k, l)| {
        let (key, v) = match (l.pressure, l.traction) {
            (Some(p), _) => ("pressure", p),
            (None, t) => ("traction", t.map_or(0.0, |t| norm(t.as_ref()))),
        };
        (format!("surface_load[{k}].{key}"), v * ramp_max(&l.ramp))
    });
    let speeds = spec.prescribed.iter().enumerate().map(|(k, p)| {
        let given = [p.velocity_x, p.velocity_y, p.velocity_z];
        let v = match p.velocity {
            Some(v) => norm(v.as_ref()),
            None => norm(&given.map(|c| c.unwrap_or(0.0))[..V::DIM]),
        };
        (format!("prescribed[{k}].velocity"), v * ramp_max(&p.ramp))
    });
    let imposed = scales::Imposed {
        materials: (spec.material.all().iter().enumerate())
            .map(|(k, m)| (spec.material.field(k), m))
            .collect(),
        time: &spec.time,
        gravity: spec.gravity.map(|g| norm(g.as_ref())),
        heights: [bottom, top],
        initial_stress: spec.initial_stress.as_ref(),
        loads: loads.collect(),
        speeds: speeds.collect(),
    };
    let grid = scales::Scales {
        cell: dx,
        max_step_motion: dx,
        motion_limit: "one grid cell",
        dynamic: true,
    };
    scales::check_scales(scene, &imposed, &grid)
}

fn grid<const D: usize, const N: usize>(scene: &MpmDocument<N>) -> Result<Grid<D>, SceneError>
where
    Mandel<D>: MpmSpace<D> + Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    let g = &scene.spec.grid;
    if !g.origin.iter().all(|v| v.is_finite()) {
        return Err(scene.error("grid.origin", format!("{:?} m must be finite", g.origin)));
    }
    if !(g.spacing.is_finite() && g.spacing > 0.0) {
        return Err(scene.error(
            "grid.spacing",
            format!("{} m must be finite and > 0", g.spacing),
        ));
    }
    if g.cells.as_ref().iter().any(|&c| c == 0 || c > 1 << 20) {
        return Err(scene.error(
            "grid.cells",
            format!("{:?} must be between 1 and 2^20 per axis", g.cells),
        ));
    }
    let shape = match g.shape {
        ShapeSpec::Linear => ShapeFunction::Linear,
        ShapeSpec::Quadratic => ShapeFunction::QuadraticBSpline,
    };
    Mandel::<D>::grid(g.origin, g.spacing, g.cells, shape)
        .map_err(|e| scene.error("grid", e.to_string()))
}

/// `[[xmin, ymin(, zmin)], [xmax, ymax(, zmax)]]` finite with max > min (or ≥ when
/// `allow_flat`) on every axis.
fn check_rectangle<V: SceneVector>(
    scene: &impl crate::scene::Locate,
    field: &str,
    r: [V; 2],
    allow_flat: bool,
) -> Result<(), SceneError> {
    let ordered = |lo: f64, hi: f64| if allow_flat { hi >= lo } else { hi > lo };
    let [lo, hi] = [r[0].as_ref(), r[1].as_ref()];
    let finite = lo.iter().chain(hi).all(|v| v.is_finite());
    if !(finite && (0..V::DIM).all(|a| ordered(lo[a], hi[a]))) {
        let rel = if allow_flat { "≥" } else { ">" };
        let corners = if V::DIM == 3 {
            "[[xmin, ymin, zmin], [xmax, ymax, zmax]]"
        } else {
            "[[xmin, ymin], [xmax, ymax]]"
        };
        return Err(scene.error(
            field,
            format!("{r:?} must be {corners}, finite, with max {rel} min"),
        ));
    }
    Ok(())
}

/// The bounding box of a body, `[lo, hi]` in x, y, z (z = 0 in 2D).
fn extent<V: SceneVector>(shape: &BodyShape<V>) -> [[f64; 3]; 2] {
    match shape {
        BodyShape::Cuboid(r) => r.map(|c| {
            let c = c.as_ref();
            [c[0], c[1], c.get(2).copied().unwrap_or(0.0)]
        }),
        BodyShape::Cylinder(c) => {
            let [xc, zc] = c.centre;
            let low = if c.quarter { 0.0 } else { c.radius };
            [
                [xc - low, c.base, zc - low],
                [xc + c.radius, c.base + c.height, zc + c.radius],
            ]
        }
    }
}

/// Each body's shape, checked: one of `rectangle` (2D), `box` or `cylinder` (3D; the
/// other dimension's keys are refused by `check_mpm_dimension`), finite, of positive
/// extent, inside the grid, overlapping no earlier body (by bounding boxes).
fn body_shapes<const D: usize, const N: usize>(
    scene: &MpmDocument<N>,
    grid: &Grid<D>,
) -> Result<Vec<BodyShape<[f64; N]>>, SceneError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    let spec = &scene.spec;
    if spec.body.is_empty() {
        return Err(scene.error("body", "no [[body]]: an MPM scene needs at least one"));
    }
    let dx = grid.spacing();
    let eps = EPS * dx;
    let (lo, hi) = (grid.origin(), grid.end());
    let mut shapes: Vec<BodyShape<[f64; N]>> = Vec::with_capacity(spec.body.len());
    for (k, b) in spec.body.iter().enumerate() {
        let shape = body_shape(scene, k, b)?;
        let field = format!("body[{k}].{}", shape.key());
        let [b0, b1] = extent(&shape);
        let inside = (0..N).all(|a| b0[a] >= lo[a] - eps && b1[a] <= hi[a] + eps);
        if !inside {
            return Err(scene.error(
                &field,
                format!(
                    "{} reaches outside the grid [{lo:?}, {hi:?}]",
                    shown(&shape, &[b0, b1])
                ),
            ));
        }
        for (j, other) in shapes.iter().enumerate() {
            let [o0, o1] = extent(other);
            let overlap = (0..N).all(|a| b0[a].max(o0[a]) < b1[a].min(o1[a]) - eps);
            if overlap {
                return Err(scene.error(
                    &field,
                    format!(
                        "{} overlaps body[{j}] {}",
                        shown(&shape, &[b0, b1]),
                        shown(other, &[o0, o1])
                    ),
                ));
            }
        }
        shapes.push(shape);
    }
    Ok(shapes)
}

/// A body as the user wrote it (a cylinder with its bounding box).
fn shown<V: SceneVector>(shape: &BodyShape<V>, bounds: &[[f64; 3]; 2]) -> String {
    match shape {
        BodyShape::Cuboid(r) => format!("{r:?}"),
        BodyShape::Cylinder(c) => format!("{c:?} (bounding box {bounds:?})"),
    }
}

/// Body `k`'s one shape, of positive extent.
fn body_shape<V: SceneVector>(
    scene: &SceneDocument<MpmSceneSpec<V>>,
    k: usize,
    b: &BodySpec<V>,
) -> Result<BodyShape<V>, SceneError> {
    let given: Vec<&str> = [
        ("rectangle", b.rectangle.is_some()),
        ("box", b.cuboid.is_some()),
        ("cylinder", b.cylinder.is_some()),
    ]
    .iter()
    .filter_map(|(key, on)| on.then_some(*key))
    .collect();
    let expected = if V::DIM == 3 {
        "`box = [[x0, y0, z0], [x1, y1, z1]]` or `cylinder = { centre = [xc, zc], base, \
         radius, height }`"
    } else {
        "`rectangle = [[xmin, ymin], [xmax, ymax]]`"
    };
    match (b.rectangle, b.cuboid, b.cylinder) {
        (Some(r), None, None) => {
            check_rectangle(scene, &format!("body[{k}].rectangle"), r, false)?;
            Ok(BodyShape::Cuboid(r))
        }
        (None, Some(r), None) => {
            check_rectangle(scene, &format!("body[{k}].box"), r, false)?;
            Ok(BodyShape::Cuboid(r))
        }
        (None, None, Some(c)) => {
            let field = format!("body[{k}].cylinder");
            if !(c.centre.iter().all(|v| v.is_finite()) && c.base.is_finite()) {
                return Err(scene.error(
                    &format!("{field}.centre"),
                    format!("{c:?}: centre and base must be finite"),
                ));
            }
            for (key, v) in [("radius", c.radius), ("height", c.height)] {
                if !(v.is_finite() && v > 0.0) {
                    return Err(scene.error(
                        &format!("{field}.{key}"),
                        format!("{v} m must be finite and > 0"),
                    ));
                }
            }
            Ok(BodyShape::Cylinder(c))
        }
        (None, None, None) => Err(scene.error(
            &format!("body[{k}]"),
            format!("has no shape: give it a {expected}"),
        )),
        _ => Err(scene.error(
            &format!("body[{k}].{}", given[1]),
            format!("a body has one shape ({}), not both", given.join(" or ")),
        )),
    }
}

/// The bodies' particles, each body of its material's density; with a `[[material]]` list
/// they carry their material's index.
fn bodies<const D: usize, const N: usize>(
    scene: &MpmDocument<N>,
    grid: &Grid<D>,
    shapes: &[BodyShape<[f64; N]>],
    materials: &BodyMaterials,
    densities: &[f64],
) -> Result<Particles<D>, SceneError>
where
    Mandel<D>: MpmSpace<D> + Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    let spec = &scene.spec;
    let dx = grid.spacing();
    let mut particles = Particles::default();
    for (k, (b, shape)) in spec.body.iter().zip(shapes).enumerate() {
        let field = format!("body[{k}].{}", shape.key());
        let per_cell = b.particles_per_cell;
        if !(1..=16).contains(&per_cell) {
            return Err(scene.error(
                &format!("body[{k}].particles_per_cell"),
                format!("{per_cell} must be between 1 and 16 per axis"),
            ));
        }
        // A body must hold at least one particle per axis.
        let particle = dx / per_cell as f64;
        let side = match shape {
            BodyShape::Cuboid(r) => {
                let [lo, hi] = [r[0].as_ref(), r[1].as_ref()];
                (0..N).map(|a| hi[a] - lo[a]).fold(f64::INFINITY, f64::min)
            }
            BodyShape::Cylinder(c) => c.radius.min(c.height),
        };
        if side < particle * (1.0 - EPS) {
            return Err(scene.error(
                &field,
                format!(
                    "{} is {side:.3e} m across, less than one particle spacing \
                     (grid.spacing / particles_per_cell = {dx:e} / {per_cell} = {particle:e} m): \
                     it would hold no particle; use grid.spacing ≤ {:.3e} m",
                    shown(shape, &extent(shape)),
                    side * per_cell as f64
                ),
            ));
        }
        let material = materials.body[k];
        let mut body = Mandel::<D>::fill(shape, dx, per_cell, densities[material])
            .map_err(|e| scene.error(&field, e))?;
        if body.is_empty() {
            return Err(scene.error(&field, "holds no particle centre"));
        }
        if materials.list {
            body = body.with_material(material);
        }
        particles.extend(&body);
    }
    Ok(particles)
}

fn walls<V: SceneVector>(scene: &SceneDocument<MpmSceneSpec<V>>) -> Result<Vec<Wall>, SceneError> {
    let mut walls: Vec<Wall> = Vec::new();
    for (k, w) in scene.spec.wall.iter().enumerate() {
        let side = match w.side {
            SideSpec::Left => Side::Left,
            SideSpec::Right => Side::Right,
            SideSpec::Bottom => Side::Bottom,
            SideSpec::Top => Side::Top,
            SideSpec::Back => Side::Back,
            SideSpec::Front => Side::Front,
        };
        if let Some(j) = walls.iter().position(|o| o.side == side) {
            return Err(scene.error(
                &format!("wall[{k}].side"),
                format!("{side:?} already has a wall (wall[{j}])").to_lowercase(),
            ));
        }
        let friction_field = format!("wall[{k}].friction");
        let condition = match (w.condition, w.friction) {
            (WallConditionSpec::Friction, None) => {
                return Err(scene.error(
                    &friction_field,
                    "missing: condition = \"friction\" needs `friction = μ` (μ ≥ 0)",
                ));
            }
            (WallConditionSpec::Friction, Some(mu)) => {
                if !(mu.is_finite() && mu >= 0.0) {
                    return Err(
                        scene.error(&friction_field, format!("{mu} must be finite and ≥ 0"))
                    );
                }
                WallCondition::Friction { coefficient: mu }
            }
            (c, Some(mu)) => {
                let c = if c == WallConditionSpec::Fixed {
                    "fixed"
                } else {
                    "slip"
                };
                return Err(scene.error(
                    &friction_field,
                    format!(
                        "friction = {mu} is given to a condition = \"{c}\" wall: \
                         only condition = \"friction\" takes it"
                    ),
                ));
            }
            (WallConditionSpec::Fixed, None) => WallCondition::Fixed,
            (WallConditionSpec::Slip, None) => WallCondition::Slip,
        };
        walls.push(Wall { side, condition });
    }
    Ok(walls)
}

/// The boxes and their velocity ramps.
type Boxes<const D: usize> = (Vec<PrescribedVelocity<D>>, Vec<Option<Ramp>>);

fn prescribed<const D: usize, const N: usize>(
    scene: &MpmDocument<N>,
    grid: &Grid<D>,
) -> Result<Boxes<D>, SceneError>
where
    Mandel<D>: MpmSpace<D> + Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    let mut boxes = Vec::new();
    let mut ramps = Vec::new();
    for (k, p) in scene.spec.prescribed.iter().enumerate() {
        let field = format!("prescribed[{k}].region");
        check_rectangle(scene, &field, p.region, true)?;
        let (whole, each) = if N == 3 {
            (
                "`velocity = [vx, vy, vz]`",
                "`velocity_x`, `velocity_y` or `velocity_z`",
            )
        } else {
            ("`velocity = [vx, vy]`", "`velocity_x` or `velocity_y`")
        };
        let one = [p.velocity_x, p.velocity_y, p.velocity_z];
        let velocity = match (p.velocity, one.iter().any(Option::is_some)) {
            (Some(_), true) => {
                return Err(scene.error(
                    &format!("prescribed[{k}].velocity"),
                    format!("give either {whole} or {each}, not both"),
                ));
            }
            (Some(v), false) => v.map(Some),
            (None, false) => {
                return Err(scene.error(
                    &format!("prescribed[{k}]"),
                    format!("no velocity: give {whole}, {each} (m/s)"),
                ));
            }
            (None, true) => std::array::from_fn(|a| one[a]),
        };
        if !velocity.iter().flatten().all(|v| v.is_finite()) {
            return Err(scene.error(
                &format!("prescribed[{k}].velocity"),
                format!("{velocity:?} m/s must be finite"),
            ));
        }
        if !holds_a_node(grid, p.region) {
            return Err(scene.error(
                &field,
                format!(
                    "{:?} holds no grid node (spacing {} m)",
                    p.region,
                    grid.spacing()
                ),
            ));
        }
        if let Some(name) = &p.name {
            let earlier = &scene.spec.prescribed[..k];
            if earlier.iter().any(|o| o.name.as_ref() == Some(name)) {
                return Err(scene.error(
                    &format!("prescribed[{k}].name"),
                    format!("`{name}` names an earlier box too"),
                ));
            }
        }
        ramps.push(check::ramp(
            scene,
            &format!("prescribed[{k}].ramp"),
            &p.ramp,
        )?);
        boxes.push(PrescribedVelocity {
            region: p.region,
            velocity: Mandel::<D>::components(&velocity),
        });
    }
    Ok((boxes, ramps))
}

/// Whether a node of the grid (ghosts aside) lies in `region`, edges included.
fn holds_a_node<const D: usize>(grid: &Grid<D>, region: [talus_mpm::Vector<D>; 2]) -> bool
where
    Mandel<D>: Dimension,
{
    let (o, dx, cells) = (grid.origin(), grid.spacing(), grid.cells());
    (0..Mandel::<D>::AXES).all(|a| {
        let first = ((region[0][a] - o[a]) / dx - EPS).ceil().max(0.0);
        let last = ((region[1][a] - o[a]) / dx + EPS)
            .floor()
            .min(cells[a] as f64);
        first <= last
    })
}

fn reaction<const D: usize, V: SceneVector>(
    scene: &SceneDocument<MpmSceneSpec<V>>,
    n_walls: usize,
    boxes: &[PrescribedVelocity<D>],
) -> Result<Option<Reaction>, SceneError>
where
    Mandel<D>: Dimension,
{
    let Some(name) = &scene.spec.output.reaction else {
        return Ok(None);
    };
    let specs = &scene.spec.prescribed;
    match specs.iter().position(|p| p.name.as_ref() == Some(name)) {
        Some(k) => Ok(Some(Reaction {
            group: n_walls + k,
            velocity_y: boxes[k].velocity.as_ref()[1],
        })),
        None => {
            let names: Vec<String> = specs
                .iter()
                .filter_map(|p| p.name.as_ref().map(|n| format!("`{n}`")))
                .collect();
            let known = if names.is_empty() {
                "no [[prescribed]] box has a name".to_string()
            } else {
                format!("named boxes: {}", names.join(", "))
            };
            Err(scene.error(
                "output.reaction",
                format!("no [[prescribed]] box named `{name}` ({known})"),
            ))
        }
    }
}

/// The face a particle of volume `V_p` shows on the surface: its width `√V_p` (2D, per
/// metre of thickness) or the area `V_p^(2/3)` of its cube (3D).
fn face<const N: usize>(volume: f64) -> f64 {
    if N == 3 {
        volume.cbrt().powi(2)
    } else {
        volume.sqrt()
    }
}

/// Surface load `k`'s traction (Pa): its `traction`, or its `pressure` downward, finite,
/// one of them.
fn traction<const N: usize>(scene: &MpmDocument<N>, k: usize) -> Result<[f64; N], SceneError>
where
    [f64; N]: SceneVector,
{
    let s = &scene.spec.surface_load[k];
    let form = if N == 3 { "[tx, ty, tz]" } else { "[tx, ty]" };
    match (s.pressure, s.traction) {
        (Some(p), None) => {
            if !(p.is_finite() && p >= 0.0) {
                return Err(scene.error(
                    &format!("surface_load[{k}].pressure"),
                    format!("{p} Pa must be finite and ≥ 0"),
                ));
            }
            // A pressure pushes down: −p along y.
            Ok(std::array::from_fn(|a| if a == 1 { -p } else { 0.0 }))
        }
        (None, Some(t)) => {
            if !t.iter().all(|c| c.is_finite()) {
                return Err(scene.error(
                    &format!("surface_load[{k}].traction"),
                    format!("{t:?} Pa must be finite"),
                ));
            }
            Ok(t)
        }
        (Some(p), Some(t)) => Err(scene.error(
            &format!("surface_load[{k}].traction"),
            format!("{t:?} and pressure = {p}: give either `pressure` or `traction`, not both"),
        )),
        (None, None) => Err(scene.error(
            &format!("surface_load[{k}]"),
            format!("no load: give `pressure = p` (Pa, downward) or `traction = {form}` (Pa)"),
        )),
    }
}

/// Each load puts its traction times the particle's face ([`face`]: `√V_p` per metre in 2D,
/// `V_p^(2/3)` in 3D) on the particles whose centres lie in its region: a downward
/// `pressure` is the traction `(0, −p(, 0))`. A load without a ramp goes into
/// `Particles::external_force`, as it always did; a ramped one is returned at multiplier 1.
/// The region must hold only the surface row (3D: layer): two particles in one column
/// (of the same x, in 3D x and z) would count the load twice.
fn surface_loads<const D: usize, const N: usize>(
    scene: &MpmDocument<N>,
    particles: &mut Particles<D>,
) -> Result<Vec<RampedSurfaceLoad<D>>, SceneError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    let mut ramped = Vec::new();
    for (k, s) in scene.spec.surface_load.iter().enumerate() {
        let field = format!("surface_load[{k}].region");
        check_rectangle(scene, &field, s.region, true)?;
        let traction = traction(scene, k)?;
        let [lo, hi] = s.region;
        let eps = EPS * scene.spec.grid.spacing;
        let position = &particles.position;
        let mut loaded: Vec<usize> = (0..particles.len())
            .filter(|&p| {
                (0..N).all(|a| position[p][a] >= lo[a] - eps && position[p][a] <= hi[a] + eps)
            })
            .collect();
        if loaded.is_empty() {
            return Err(scene.error(&field, format!("{:?} holds no particle centre", s.region)));
        }
        loaded.sort_by(|&a, &b| position[a][0].total_cmp(&position[b][0]));
        // A particle's side: √V_p, ∛V_p.
        let side = |p: usize| {
            let v = particles.volume[p];
            if N == 3 {
                v.cbrt()
            } else {
                v.sqrt()
            }
        };
        let widest = loaded.iter().fold(0.0f64, |w, &p| w.max(side(p)));
        for (i, &a) in loaded.iter().enumerate() {
            // The particles after `a` in x within half the widest side, in its column.
            for &b in &loaded[i + 1..] {
                let gap = position[b][0] - position[a][0];
                if gap >= 0.5 * widest {
                    break;
                }
                let half = 0.5 * side(a).min(side(b));
                let column =
                    gap < half && (2..N).all(|c| (position[b][c] - position[a][c]).abs() < half);
                if !column {
                    continue;
                }
                let (at, surface) = if N == 3 {
                    (
                        format!(
                            "(x, z) = ({:.6}, {:.6}) m",
                            position[a][0],
                            position[a][N - 1]
                        ),
                        "surface layer",
                    )
                } else {
                    (format!("x = {:.6} m", position[a][0]), "surface row")
                };
                return Err(scene.error(
                    &field,
                    format!(
                        "{:?} holds more than one particle at {at}: the region must hold \
                         only the {surface}, or the load counts twice",
                        s.region
                    ),
                ));
            }
        }
        let force = |p: usize| -> [f64; N] {
            let area = face::<N>(particles.volume[p]);
            std::array::from_fn(|a| traction[a] * area)
        };
        match check::ramp(scene, &format!("surface_load[{k}].ramp"), &s.ramp)? {
            None => {
                for p in loaded {
                    let f = force(p);
                    for (sum, fa) in particles.external_force[p].iter_mut().zip(f) {
                        *sum += fa;
                    }
                }
            }
            Some(ramp) => {
                let force = loaded.iter().map(|&p| force(p)).collect();
                ramped.push(RampedSurfaceLoad {
                    ramp,
                    particles: loaded,
                    force,
                });
            }
        }
    }
    Ok(ramped)
}

fn settings<V: SceneVector>(
    scene: &SceneDocument<MpmSceneSpec<V>>,
) -> Result<MpmSettings, SceneError> {
    let m = &scene.spec.mpm;
    if !(m.flip_ratio.is_finite() && (0.0..=1.0).contains(&m.flip_ratio)) {
        return Err(scene.error(
            "mpm.flip_ratio",
            format!("{} must be in [0, 1] (0 = PIC, 1 = FLIP)", m.flip_ratio),
        ));
    }
    Ok(MpmSettings {
        flip_ratio: m.flip_ratio,
        rotate_stress: m.rotate_stress,
        ..MpmSettings::default()
    })
}

/// The engine's settings of an MPM scene: its `[solver]` section with MPM's defaults, and
/// `[mpm] predictor`.
fn step_settings<V: SceneVector>(scene: &SceneDocument<MpmSceneSpec<V>>) -> StepSettings {
    StepSettings {
        predictor: match scene.spec.mpm.predictor {
            PredictorSpec::Previous => PredictorRule::Previous,
            PredictorSpec::Elastic => PredictorRule::Elastic,
        },
        ..scene.spec.solver.step_settings(StepSettings::mpm())
    }
}
