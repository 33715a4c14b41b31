//! The spec of a material-point (MPM) scene: a `[grid]` instead of a `[mesh]`, bodies of
//! particles, walls and prescribed-velocity boxes on the grid, surface loads on particles.
//! `[material]`, `[time]`, `[solver]` and `[initial_stress]` are those of FEM scenes;
//! `[analysis]` is read so that `kind = "quasi_static"` can be refused by name, and
//! `geometry = "3d"` makes it a 3D scene (`docs/3d-mpm.md`): its points and vectors `V`
//! have 3 components, its bodies are boxes and cylinders.
use serde::{Deserialize, Serialize};

use super::{AnalysisSpec, InitialStressSpec, Materials, SceneVector, SolverSpec, TimeSpec};

/// The whole MPM scene (see docs/scenes.md, "MPM scenes"), its points and vectors `V`
/// (2D by default, [`SceneVector`]).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct MpmSceneSpec<V: SceneVector = [f64; 2]> {
    #[serde(default)]
    pub title: Option<String>,
    /// Body acceleration (m/s²); absent means weightless.
    #[serde(default)]
    pub gravity: Option<V>,
    /// Multiplier of `gravity` in time (docs/scenes.md, 'Load programmes').
    #[serde(default)]
    pub gravity_ramp: Option<Vec<[f64; 2]>>,
    pub grid: GridSpec<V>,
    /// Rectangles (3D: boxes, cylinders) filled with particles, each of its own `material`
    /// (of a `[[material]]` list) or all of the single `[material]`.
    #[serde(default)]
    pub body: Vec<BodySpec<V>>,
    /// The keys of a FEM scene's materials (`flow = "davis"` included), checked by the same
    /// `check::material`; no `regions` (bodies name their materials).
    pub material: Materials,
    #[serde(default)]
    pub wall: Vec<WallSpec>,
    #[serde(default)]
    pub prescribed: Vec<PrescribedSpec<V>>,
    #[serde(default)]
    pub surface_load: Vec<SurfaceLoadSpec<V>>,
    /// K₀ or uniform stress at every particle (default: stress free); a uniform `stress`
    /// has 4 components in 2D, 6 in 3D.
    #[serde(default)]
    pub initial_stress: Option<InitialStressSpec<V>>,
    /// Only `kind = "dynamic"` (the default): the material point method follows the flow.
    #[serde(default)]
    pub analysis: AnalysisSpec,
    pub time: TimeSpec,
    #[serde(default)]
    pub mpm: MpmSpec,
    #[serde(default)]
    pub solver: SolverSpec,
    #[serde(default)]
    pub output: MpmOutputSpec,
    /// Points whose grid-interpolated displacement and velocity are recorded.
    #[serde(default)]
    pub monitor: Vec<super::MonitorSpec<V>>,
}

/// Square (3D: cubic) cells of side `spacing` (m) from `origin` (the corner of smallest
/// coordinates, m): `cells = [nx, ny]`, in 3D `[nx, ny, nz]`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct GridSpec<V: SceneVector = [f64; 2]> {
    pub origin: V,
    pub spacing: f64,
    pub cells: V::Cells,
    #[serde(default)]
    pub shape: ShapeSpec,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ShapeSpec {
    Linear,
    /// Quadratic B-splines (C¹: no cell-crossing noise).
    #[default]
    Quadratic,
}

/// A body of particles, `particles_per_cell` per axis and per cell, of the material
/// `material` names: in 2D a `rectangle = [[xmin, ymin], [xmax, ymax]]`; in 3D a
/// `box = [[x0, y0, z0], [x1, y1, z1]]` or a vertical `cylinder` (one of them).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct BodySpec<V: SceneVector = [f64; 2]> {
    /// 2D only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rectangle: Option<[V; 2]>,
    /// 3D only.
    #[serde(default, rename = "box", skip_serializing_if = "Option::is_none")]
    pub cuboid: Option<[V; 2]>,
    /// 3D only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cylinder: Option<CylinderSpec>,
    /// Per axis; default 2.
    #[serde(default = "two")]
    pub particles_per_cell: usize,
    /// The `name` of a `[[material]]` (required with a list); with a single `[material]`
    /// it may be left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

fn two() -> usize {
    2
}

/// A vertical cylinder (axis along y through `(x_c, z_c)`): its base at `y = base`, its
/// `radius` and `height` (m); `quarter = true` keeps the quadrant `x ≥ x_c, z ≥ z_c`, the
/// whole cylinder by symmetry with slip walls on `x = x_c` and `z = z_c`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CylinderSpec {
    /// `[x_c, z_c]` (m).
    pub centre: [f64; 2],
    pub base: f64,
    pub radius: f64,
    pub height: f64,
    #[serde(default)]
    pub quarter: bool,
}

/// The grid's faces: `left`/`right` (x), `bottom`/`top` (y), and in 3D `back` (z = z₀) and
/// `front` (largest z), as talus-mpm and the FEM box name them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SideSpec {
    Left,
    Right,
    Bottom,
    Top,
    Back,
    Front,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WallConditionSpec {
    Fixed,
    Slip,
    Friction,
}

/// A wall on a side of the grid; `friction` (μ ≥ 0) is required iff `condition = "friction"`.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    /// Names the wall's reaction columns in history.csv.
    #[serde(default)]
    pub name: Option<String>,
    pub side: SideSpec,
    pub condition: WallConditionSpec,
    #[serde(default)]
    pub friction: Option<f64>,
}

/// Grid nodes inside `region` move with the given velocity (m/s): `velocity = [vx, vy]`
/// (3D: `[vx, vy, vz]`) prescribes every component, `velocity_x` / `velocity_y` (3D: also
/// `velocity_z`) one each (the others stay free).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct PrescribedSpec<V: SceneVector = [f64; 2]> {
    #[serde(default)]
    pub name: Option<String>,
    pub region: [V; 2],
    #[serde(default)]
    pub velocity: Option<V>,
    #[serde(default)]
    pub velocity_x: Option<f64>,
    #[serde(default)]
    pub velocity_y: Option<f64>,
    /// 3D only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity_z: Option<f64>,
    /// Multiplier of the velocity in time.
    #[serde(default)]
    pub ramp: Option<Vec<[f64; 2]>>,
}

/// A load on the surface of the bodies, carried by the particles whose centres lie in
/// `region` (the surface row, in 3D the surface layer): a downward `pressure` (Pa) or a
/// `traction = [tx, ty]` (3D: `[tx, ty, tz]`, Pa), one of them; each particle takes it
/// times its face, `√V_p` per metre in 2D, `V_p^(2/3)` in 3D.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct SurfaceLoadSpec<V: SceneVector = [f64; 2]> {
    pub region: [V; 2],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pressure: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traction: Option<V>,
    /// Multiplier of the load in time.
    #[serde(default)]
    pub ramp: Option<Vec<[f64; 2]>>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PredictorSpec {
    #[default]
    Previous,
    Elastic,
}

/// The MPM transfer and stress-update options.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct MpmSpec {
    /// FLIP weight α in `v = α v_FLIP + (1 − α) v_PIC`, in [0, 1].
    pub flip_ratio: f64,
    pub rotate_stress: bool,
    pub predictor: PredictorSpec,
}

impl Default for MpmSpec {
    fn default() -> Self {
        Self {
            flip_ratio: 0.95,
            rotate_stress: true,
            predictor: PredictorSpec::Previous,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct MpmOutputSpec {
    /// Particle VTU every this many steps (0: only the first and the last).
    pub vtu_every: usize,
    /// PNG of the particles every this many steps (0: only the first and the last).
    pub snapshot_every: usize,
    /// The `[[prescribed]]` box (by `name`) whose force goes into history.csv.
    pub reaction: Option<String>,
    /// Report the final normalized runout in the summary.
    pub runout: bool,
    /// Summary plots (force–displacement of the `reaction` box).
    pub plots: bool,
}

impl Default for MpmOutputSpec {
    fn default() -> Self {
        Self {
            vtu_every: 10,
            snapshot_every: 0,
            reaction: None,
            runout: false,
            plots: true,
        }
    }
}
