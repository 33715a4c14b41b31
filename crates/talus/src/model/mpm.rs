//! A material-point model from a scene (`[grid]`): the solver and its particles, every input checked first so
//! that a bad scene is an error naming the field and the value, never a panic.
use talus_mpm::{
    Grid, GridBoundary, Mpm, MpmSettings, Particles, PrescribedVelocity, ShapeFunction, Side, Wall,
    WallCondition,
};

use talus_bipotential::Material;

use crate::scene::{
    check, scales, scales::ramp_max, AnalysisKind, GeometryKind, InitialStressSpec, Materials,
    MpmScene, PredictorSpec, Ramp, SceneError, ShapeSpec, SideSpec, WallConditionSpec,
};
use talus_engine::{PredictorRule, StepSettings};
use talus_mpm::{MpmLoadProgramme, ProgrammedMpm, RampedSurfaceLoad, RunoutReference};

use crate::model::initial_stress_at;

/// Everything a run needs: the solver, the particles at t = 0, and what to report.
pub struct MpmModel {
    /// The solver with the scene's load programme (it reads as an [`Mpm`]).
    pub mpm: ProgrammedMpm,
    /// How the engine steps it (`[solver]`, `[mpm] predictor`).
    pub step_settings: StepSettings,
    pub particles: Particles,
    /// The `output.reaction` box, if any.
    pub reaction: Option<Reaction>,
    pub runout: RunoutReference,
    /// y of the bottom wall, if there is one (m).
    pub floor: Option<f64>,
    /// The grid extent `[[x0, y0], [x1, y1]]` (m), the frame of every PNG.
    pub bounds: [[f64; 2]; 2],
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
    pub fn from_scene(scene: &MpmScene) -> Result<Self, SceneError> {
        let spec = &scene.spec;
        let grid = grid(scene)?;
        let materials = materials(scene)?;
        if spec.analysis.kind == AnalysisKind::QuasiStatic {
            return Err(scene.error(
                "analysis.kind",
                "\"quasi_static\" is for finite-element scenes ([mesh]); a material point \
                 scene ([grid]) runs \"dynamic\" only",
            ));
        }
        if spec.analysis.geometry != GeometryKind::PlaneStrain {
            return Err(scene.error(
                "analysis.geometry",
                "\"axisymmetric\" is for finite-element scenes ([mesh]); a material point \
                 scene ([grid]) is plane strain only",
            ));
        }
        if let Some(r) = spec.analysis.inertia_ratio {
            return Err(scene.error(
                "analysis.inertia_ratio",
                format!("{r} applies to quasi-static finite-element scenes only"),
            ));
        }
        let densities = densities(scene)?;
        let gravity = spec.gravity.unwrap_or([0.0; 2]);
        if !gravity.iter().all(|g| g.is_finite()) {
            return Err(scene.error("gravity", format!("{gravity:?} m/s² must be finite")));
        }
        let gravity_ramp = check::ramp(scene, "gravity_ramp", &spec.gravity_ramp)?;
        if gravity_ramp.is_some() && spec.gravity.is_none() {
            return Err(scene.error("gravity_ramp", "multiplies `gravity`, which is not given"));
        }
        check::time(scene, &spec.time)?;
        scales::caps(scene, &spec.time, spec.solver.max_step_halvings)?;
        let mut particles = bodies(scene, &grid, &materials, &densities)?;
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
        check_scales(scene)?;
        let settings = settings(scene)?;
        let floor = walls
            .iter()
            .any(|w| w.side == Side::Bottom)
            .then_some(grid.origin()[1]);
        let has_left_wall = walls.iter().any(|w| w.side == Side::Left);
        let runout = RunoutReference::of_bodies(
            spec.body.iter().map(|b| b.rectangle),
            has_left_wall.then_some(grid.origin()[0]),
        );
        let bounds = [grid.origin(), grid.end()];
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

/// The scene's materials, checked, and the material of each body.
struct BodyMaterials {
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
fn materials(scene: &MpmScene) -> Result<BodyMaterials, SceneError> {
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
fn densities(scene: &MpmScene) -> Result<Vec<f64>, SceneError> {
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
fn initial_stress(
    scene: &MpmScene,
    initial: &InitialStressSpec,
    materials: &BodyMaterials,
    gammas: &[f64],
    densities: &[f64],
    particles: &Particles,
) -> Result<Vec<[f64; 4]>, SceneError> {
    let spec = &scene.spec;
    // The form and the numbers first (no point, no cone): the errors below are a
    // material's, at its particles.
    initial_stress_at(scene, None, gammas[0], initial, &[], None)?;
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
    let mut stress = vec![[0.0; 4]; particles.len()];
    for (k, material) in materials.materials.iter().enumerate() {
        let members: Vec<usize> = (0..particles.len())
            .filter(|&p| particles.material_of(p) == k)
            .collect();
        if members.is_empty() {
            continue;
        }
        let points: Vec<[f64; 2]> = members.iter().map(|&p| particles.position[p]).collect();
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
fn check_scales(scene: &MpmScene) -> Result<(), SceneError> {
    let spec = &scene.spec;
    let dx = spec.grid.spacing;
    let (bottom, top) = spec
        .body
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(b, t), r| {
            (b.min(r.rectangle[0][1]), t.max(r.rectangle[1][1]))
        });
    let loads = spec.surface_load.iter().enumerate().map(|(k, l)| {
        let v = l.pressure * ramp_max(&l.ramp);
        (format!("surface_load[{k}].pressure"), v)
    });
    let speeds = spec.prescribed.iter().enumerate().map(|(k, p)| {
        let [vx, vy] = match p.velocity {
            Some(v) => v,
            None => [p.velocity_x.unwrap_or(0.0), p.velocity_y.unwrap_or(0.0)],
        };
        let v = vx.hypot(vy) * ramp_max(&p.ramp);
        (format!("prescribed[{k}].velocity"), v)
    });
    let imposed = scales::Imposed {
        materials: (spec.material.all().iter().enumerate())
            .map(|(k, m)| (spec.material.field(k), m))
            .collect(),
        time: &spec.time,
        gravity: spec.gravity,
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

fn grid(scene: &MpmScene) -> Result<Grid, SceneError> {
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
    if g.cells.iter().any(|&c| c == 0 || c > 1 << 20) {
        return Err(scene.error(
            "grid.cells",
            format!("{:?} must be between 1 and 2^20 per axis", g.cells),
        ));
    }
    let shape = match g.shape {
        ShapeSpec::Linear => ShapeFunction::Linear,
        ShapeSpec::Quadratic => ShapeFunction::QuadraticBSpline,
    };
    Grid::try_new(g.origin, g.spacing, g.cells, shape)
        .map_err(|e| scene.error("grid", e.to_string()))
}

/// `[[xmin, ymin], [xmax, ymax]]` finite with max > min (or ≥ when `allow_flat`).
fn check_rectangle(
    scene: &MpmScene,
    field: &str,
    r: [[f64; 2]; 2],
    allow_flat: bool,
) -> Result<(), SceneError> {
    let ordered = |lo: f64, hi: f64| if allow_flat { hi >= lo } else { hi > lo };
    let finite = r.iter().flatten().all(|v| v.is_finite());
    if !(finite && ordered(r[0][0], r[1][0]) && ordered(r[0][1], r[1][1])) {
        let rel = if allow_flat { "≥" } else { ">" };
        return Err(scene.error(
            field,
            format!("{r:?} must be [[xmin, ymin], [xmax, ymax]], finite, with max {rel} min"),
        ));
    }
    Ok(())
}

/// The bodies' particles, each body of its material's density; with a `[[material]]` list
/// they carry their material's index.
fn bodies(
    scene: &MpmScene,
    grid: &Grid,
    materials: &BodyMaterials,
    densities: &[f64],
) -> Result<Particles, SceneError> {
    let spec = &scene.spec;
    if spec.body.is_empty() {
        return Err(scene.error("body", "no [[body]]: an MPM scene needs at least one"));
    }
    let dx = grid.spacing();
    let (lo, hi) = (grid.origin(), grid.end());
    let mut particles = Particles::default();
    for (k, b) in spec.body.iter().enumerate() {
        let field = format!("body[{k}].rectangle");
        let r = b.rectangle;
        check_rectangle(scene, &field, r, false)?;
        let eps = EPS * dx;
        let inside = (0..2).all(|a| r[0][a] >= lo[a] - eps && r[1][a] <= hi[a] + eps);
        if !inside {
            return Err(scene.error(
                &field,
                format!("{r:?} reaches outside the grid [{lo:?}, {hi:?}]"),
            ));
        }
        for (j, other) in spec.body[..k].iter().enumerate() {
            let o = other.rectangle;
            let overlap = (0..2).all(|a| r[0][a].max(o[0][a]) < r[1][a].min(o[1][a]) - eps);
            if overlap {
                return Err(scene.error(&field, format!("{r:?} overlaps body[{j}] {o:?}")));
            }
        }
        let per_cell = b.particles_per_cell;
        if !(1..=16).contains(&per_cell) {
            return Err(scene.error(
                &format!("body[{k}].particles_per_cell"),
                format!("{per_cell} must be between 1 and 16 per axis"),
            ));
        }
        // A body must hold at least one particle per axis.
        let particle = dx / per_cell as f64;
        let side = (r[1][0] - r[0][0]).min(r[1][1] - r[0][1]);
        if side < particle * (1.0 - EPS) {
            return Err(scene.error(
                &field,
                format!(
                    "{r:?} is {side:.3e} m across, less than one particle spacing \
                     (grid.spacing / particles_per_cell = {dx:e} / {per_cell} = {particle:e} m): \
                     it would hold no particle; use grid.spacing ≤ {:.3e} m",
                    side * per_cell as f64
                ),
            ));
        }
        let material = materials.body[k];
        let mut body = Particles::fill_rectangle(r, dx, per_cell, densities[material])
            .map_err(|e| scene.error(&field, e.to_string()))?;
        if materials.list {
            body = body.with_material(material);
        }
        particles.extend(&body);
    }
    Ok(particles)
}

fn walls(scene: &MpmScene) -> Result<Vec<Wall>, SceneError> {
    let mut walls: Vec<Wall> = Vec::new();
    for (k, w) in scene.spec.wall.iter().enumerate() {
        let side = match w.side {
            SideSpec::Left => Side::Left,
            SideSpec::Right => Side::Right,
            SideSpec::Bottom => Side::Bottom,
            SideSpec::Top => Side::Top,
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
type Boxes = (Vec<PrescribedVelocity>, Vec<Option<Ramp>>);

fn prescribed(scene: &MpmScene, grid: &Grid) -> Result<Boxes, SceneError> {
    let mut boxes = Vec::new();
    let mut ramps = Vec::new();
    for (k, p) in scene.spec.prescribed.iter().enumerate() {
        let field = format!("prescribed[{k}].region");
        check_rectangle(scene, &field, p.region, true)?;
        let velocity = match (p.velocity, p.velocity_x, p.velocity_y) {
            (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                return Err(scene.error(
                    &format!("prescribed[{k}].velocity"),
                    "give either `velocity = [vx, vy]` or `velocity_x` / `velocity_y`, not both",
                ));
            }
            (Some([vx, vy]), None, None) => [Some(vx), Some(vy)],
            (None, None, None) => {
                return Err(scene.error(
                    &format!("prescribed[{k}]"),
                    "no velocity: give `velocity = [vx, vy]`, `velocity_x` or `velocity_y` (m/s)",
                ));
            }
            (None, vx, vy) => [vx, vy],
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
            velocity,
        });
    }
    Ok((boxes, ramps))
}

/// Whether a node of the grid (ghosts aside) lies in `region`, edges included.
fn holds_a_node(grid: &Grid, region: [[f64; 2]; 2]) -> bool {
    let (o, dx, cells) = (grid.origin(), grid.spacing(), grid.cells());
    (0..2).all(|a| {
        let first = ((region[0][a] - o[a]) / dx - EPS).ceil().max(0.0);
        let last = ((region[1][a] - o[a]) / dx + EPS)
            .floor()
            .min(cells[a] as f64);
        first <= last
    })
}

fn reaction(
    scene: &MpmScene,
    n_walls: usize,
    boxes: &[PrescribedVelocity],
) -> Result<Option<Reaction>, SceneError> {
    let Some(name) = &scene.spec.output.reaction else {
        return Ok(None);
    };
    let specs = &scene.spec.prescribed;
    match specs.iter().position(|p| p.name.as_ref() == Some(name)) {
        Some(k) => Ok(Some(Reaction {
            group: n_walls + k,
            velocity_y: boxes[k].velocity[1],
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

/// Each load puts `pressure × √V_p` (N/m) downward on the particles whose centres lie in
/// its region: the pressure times the particle's width along a horizontal surface. A load
/// without a ramp goes into `Particles::external_force`, as it always did; a ramped one is
/// returned at multiplier 1.
fn surface_loads(
    scene: &MpmScene,
    particles: &mut Particles,
) -> Result<Vec<RampedSurfaceLoad>, SceneError> {
    let mut ramped = Vec::new();
    for (k, s) in scene.spec.surface_load.iter().enumerate() {
        let field = format!("surface_load[{k}].region");
        check_rectangle(scene, &field, s.region, true)?;
        if !(s.pressure.is_finite() && s.pressure >= 0.0) {
            return Err(scene.error(
                &format!("surface_load[{k}].pressure"),
                format!("{} Pa must be finite and ≥ 0", s.pressure),
            ));
        }
        let [[x0, y0], [x1, y1]] = s.region;
        let eps = EPS * scene.spec.grid.spacing;
        let mut loaded: Vec<usize> = (0..particles.len())
            .filter(|&p| {
                let [x, y] = particles.position[p];
                x >= x0 - eps && x <= x1 + eps && y >= y0 - eps && y <= y1 + eps
            })
            .collect();
        if loaded.is_empty() {
            return Err(scene.error(&field, format!("{:?} holds no particle centre", s.region)));
        }
        loaded.sort_by(|&a, &b| particles.position[a][0].total_cmp(&particles.position[b][0]));
        for pair in loaded.windows(2) {
            let [a, b] = [pair[0], pair[1]];
            let half = 0.5 * particles.volume[a].sqrt().min(particles.volume[b].sqrt());
            if particles.position[b][0] - particles.position[a][0] < half {
                return Err(scene.error(
                    &field,
                    format!(
                        "{:?} holds more than one particle at x = {:.6} m: the region must hold \
                         only the surface row, or the load counts twice",
                        s.region, particles.position[a][0]
                    ),
                ));
            }
        }
        match check::ramp(scene, &format!("surface_load[{k}].ramp"), &s.ramp)? {
            None => {
                for p in loaded {
                    particles.external_force[p][1] -= s.pressure * particles.volume[p].sqrt();
                }
            }
            Some(ramp) => {
                let force = loaded
                    .iter()
                    .map(|&p| [0.0, -s.pressure * particles.volume[p].sqrt()])
                    .collect();
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

fn settings(scene: &MpmScene) -> Result<MpmSettings, SceneError> {
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
fn step_settings(scene: &MpmScene) -> StepSettings {
    StepSettings {
        predictor: match scene.spec.mpm.predictor {
            PredictorSpec::Previous => PredictorRule::Previous,
            PredictorSpec::Elastic => PredictorRule::Elastic,
        },
        ..scene.spec.solver.step_settings(StepSettings::mpm())
    }
}
