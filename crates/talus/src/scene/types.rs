use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::{Materials, RegionSpec, SolverSpec, WaterSpec};

/// A point or vector of a scene (m, m/s, m/s², Pa, N): `[x, y]` in plane strain and
/// axisymmetry, `[x, y, z]` in 3D (`[analysis] geometry = "3d"`, `docs/3d.md`); y is
/// vertical in both.
pub trait SceneVector:
    Copy
    + Default
    + std::fmt::Debug
    + PartialEq
    + Serialize
    + DeserializeOwned
    + AsRef<[f64]>
    + AsMut<[f64]>
    + Send
    + Sync
    + 'static
{
    /// 2 or 3.
    const DIM: usize;
    /// Cells per axis of a grid of this dimension (`[grid] cells`).
    type Cells: Copy
        + std::fmt::Debug
        + PartialEq
        + Serialize
        + DeserializeOwned
        + AsRef<[usize]>
        + Send
        + Sync
        + 'static;
    /// A uniform stress's plain components (`[initial_stress] stress`): 2D's
    /// `[σxx, σyy, σxy, σzz]`, 3D's `[σxx, σyy, σzz, σyz, σxz, σxy]`
    /// ([`crate::model::mandel_from_components`]).
    type Stress: Copy
        + std::fmt::Debug
        + PartialEq
        + Serialize
        + DeserializeOwned
        + AsRef<[f64]>
        + Send
        + Sync
        + 'static;
    /// How a scene writes [`Self::Stress`].
    const STRESS_FORM: &'static str;
}
impl SceneVector for [f64; 2] {
    const DIM: usize = 2;
    type Cells = [usize; 2];
    type Stress = [f64; 4];
    const STRESS_FORM: &'static str = "[sxx, syy, sxy, szz]";
}
impl SceneVector for [f64; 3] {
    const DIM: usize = 3;
    type Cells = [usize; 3];
    type Stress = [f64; 6];
    const STRESS_FORM: &'static str = "[sxx, syy, szz, syz, sxz, sxy]";
}

/// The whole scene, its points and vectors `V` (2D by default, [`SceneVector`]).
/// Optional sections cost nothing when left out: no gravity, no tractions, default solver
/// settings and outputs.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct SceneSpec<V: SceneVector = [f64; 2]> {
    #[serde(default)]
    pub title: Option<String>,
    pub mesh: MeshSpec,
    /// `[material]` or `[[material]]`.
    pub material: Materials,
    /// Named regions of the mesh by box (Gmsh physical surfaces are regions already).
    #[serde(default)]
    pub region: Vec<RegionSpec<V>>,
    /// A drained water table (default: dry).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub water: Option<WaterSpec>,
    /// Body acceleration (m/s²), e.g. `[0.0, -9.81]` (3D: `[0.0, -9.81, 0.0]`); absent
    /// means weightless.
    #[serde(default)]
    pub gravity: Option<V>,
    /// Multiplier of `gravity` in time (see [`Ramp`](super::Ramp)); default constant 1.
    #[serde(default)]
    pub gravity_ramp: Option<Vec<[f64; 2]>>,
    #[serde(default)]
    pub boundary: Vec<BoundarySpec<V>>,
    #[serde(default)]
    pub traction: Vec<TractionSpec<V>>,
    #[serde(default)]
    pub pressure: Vec<PressureSpec<V>>,
    /// Forces at the nodes nearest given points.
    #[serde(default)]
    pub point_load: Vec<PointLoadSpec<V>>,
    pub time: TimeSpec,
    /// Initial stress (default: stress free); a uniform `stress` has four components in
    /// 2D, six in 3D ([`InitialStressSpec`]).
    #[serde(default)]
    pub initial_stress: Option<InitialStressSpec<V>>,
    /// Dynamic (default) or quasi-static.
    #[serde(default)]
    pub analysis: AnalysisSpec,
    #[serde(default)]
    pub solver: SolverSpec,
    #[serde(default)]
    pub output: OutputSpec,
    /// Points whose displacement and velocity are recorded (`docs/scenes.md`, 'Results').
    #[serde(default)]
    pub monitor: Vec<super::MonitorSpec<V>>,
    /// A factor of safety instead of a run to the end (`docs/stability.md`).
    #[serde(default)]
    pub stability: Option<super::StabilitySpec>,
    /// Construction in stages (`docs/scenes.md`, 'Stages'); none: one stage.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stage: Vec<super::StageSpec>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
pub enum Order {
    P1,
    P2,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum MeshSpec {
    /// A structured rectangle, graded geometrically away from `focus` by `ratio` per cell.
    Rectangle {
        x: [f64; 2],
        y: [f64; 2],
        cells: [usize; 2],
        order: Order,
        #[serde(default)]
        focus: Option<[f64; 2]>,
        #[serde(default = "uniform")]
        ratio: [f64; 2],
    },
    /// A structured box of tetrahedra (3D: each hexahedral cell cut into 6), graded
    /// geometrically away from `focus` by `ratio` per cell along each axis; sets `left`,
    /// `right` (x), `bottom`, `top` (y), `back`, `front` (z).
    Box {
        x: [f64; 2],
        y: [f64; 2],
        z: [f64; 2],
        cells: [usize; 3],
        order: Order,
        #[serde(default)]
        focus: Option<[f64; 3]>,
        #[serde(default = "uniform3")]
        ratio: [f64; 3],
    },
    /// A Gmsh `.msh` 4.1 file, relative to the scene file; `order = "P2"` turns a linear
    /// (P1) mesh into P2, with mid-edge nodes on straight edges.
    Gmsh {
        path: String,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        order: Option<Order>,
        /// 3D only: `[z0, z1]` (m), the file's 2D triangle mesh extruded along z from z0
        /// to z1 into tetrahedra (`TetrahedralMesh::extrude`), its sets extruded with it
        /// plus `back` (z0) and `front` (z1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        extrude: Option<[f64; 2]>,
        /// 3D only, with `extrude`: equal layers of prisms over `[z0, z1]` (default 1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        layers: Option<usize>,
    },
}

fn uniform() -> [f64; 2] {
    [1.0, 1.0]
}

fn uniform3() -> [f64; 3] {
    [1.0, 1.0, 1.0]
}

/// Nodes by the name of a mesh set or by an axis-aligned box `[[xmin, ymin], [xmax, ymax]]`
/// (3D: `[[x0, y0, z0], [x1, y1, z1]]`).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(untagged, bound = "")]
pub enum Selection<V: SceneVector = [f64; 2]> {
    Named(String),
    Box {
        #[serde(rename = "box")]
        corners: [V; 2],
    },
}

/// The fixed velocity components: `"x"`, `"y"`, `"xy"` in 2D; also `"z"`, `"xz"`,
/// `"yz"`, `"xyz"` in 3D.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Fix {
    X,
    Y,
    Xy,
    Z,
    Xz,
    Yz,
    Xyz,
}

impl Fix {
    /// Whether velocity component `comp` (0: x, 1: y, 2: z) is fixed.
    pub fn fixes(self, comp: usize) -> bool {
        let axes: &[usize] = match self {
            Fix::X => &[0],
            Fix::Y => &[1],
            Fix::Z => &[2],
            Fix::Xy => &[0, 1],
            Fix::Xz => &[0, 2],
            Fix::Yz => &[1, 2],
            Fix::Xyz => &[0, 1, 2],
        };
        axes.contains(&comp)
    }

    /// Whether it names z, which a 2D scene has not.
    pub fn names_z(self) -> bool {
        self.fixes(2)
    }
}

/// Dirichlet condition: the fixed components move at `velocity` (default 0, m/s).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct BoundarySpec<V: SceneVector = [f64; 2]> {
    #[serde(default)]
    pub name: Option<String>,
    pub nodes: Selection<V>,
    pub fix: Fix,
    #[serde(default)]
    pub velocity: V,
    /// Multiplier of `velocity` in time; default constant 1.
    #[serde(default)]
    pub ramp: Option<Vec<[f64; 2]>>,
    /// The stages this acts in (`[[stage]]` names); default every stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stages: Option<Vec<String>>,
}

/// Surface traction (Pa) on the boundary edges (3D: faces) selected.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct TractionSpec<V: SceneVector = [f64; 2]> {
    /// `edges` in 2D, `faces` in 3D (`scene::dimension` refuses the other key).
    #[serde(alias = "faces")]
    pub edges: Selection<V>,
    pub value: V,
    /// Multiplier of `value` in time; default constant 1.
    #[serde(default)]
    pub ramp: Option<Vec<[f64; 2]>>,
    /// The stages this acts in (`[[stage]]` names); default every stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stages: Option<Vec<String>>,
}

/// Normal pressure (Pa, positive pushing into the body) on the boundary edges selected,
/// straight or curved; each edge's outward normal comes from its triangle.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct PressureSpec<V: SceneVector = [f64; 2]> {
    /// `edges` in 2D, `faces` in 3D (`scene::dimension` refuses the other key).
    #[serde(alias = "faces")]
    pub edges: Selection<V>,
    /// Pa; with `gradient`, the pressure at y = 0.
    pub value: f64,
    /// dp/dy (Pa/m): the pressure is `value + gradient · y`, e.g. water on a wall,
    /// `value = γ_w y_w, gradient = −γ_w` below a water level `y_w`. Default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gradient: Option<f64>,
    /// Multiplier of `value` in time; default constant 1.
    #[serde(default)]
    pub ramp: Option<Vec<[f64; 2]>>,
    /// The stages this acts in (`[[stage]]` names); default every stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stages: Option<Vec<String>>,
}

/// A force (N per metre of thickness; axisymmetric: N per radian) on the node nearest
/// `point` (m).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct PointLoadSpec<V: SceneVector = [f64; 2]> {
    pub point: V,
    pub force: V,
    /// Multiplier of `force` in time; default constant 1.
    #[serde(default)]
    pub ramp: Option<Vec<[f64; 2]>>,
    /// The stages this acts in (`[[stage]]` names); default every stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stages: Option<Vec<String>>,
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSpec {
    /// h, s.
    pub step: f64,
    /// Required without `[[stage]]`; with stages, each gives its own.
    #[serde(default)]
    pub steps: usize,
}

/// The initial stress, either of two forms (exclusive):
///
/// - the K₀ procedure of geotechnical practice for a horizontal ground surface (`k0`,
///   `surface`, `surcharge`): `σ_yy = −(surcharge + ρ g (surface − y))`,
///   `σ_xx = σ_zz = K₀ σ_yy`, `σ_xy = 0`. It is in equilibrium with gravity and a uniform
///   surcharge; it must lie inside the yield cone, which without cohesion admits
///   `(a − t)/(a + 2t) ≤ K₀ ≤ (a + t)/(a − 2t)`, `a = √(2/3)/k_d`, `t = tan φ / 3` (Jaky's
///   `1 − sin φ` is inside up to φ ≈ 36° with the plane-strain fit);
/// - a uniform `stress = [σxx, σyy, σxy, σzz]` (Pa, tension positive), inside the cone; in
///   a 3D scene (`V = [f64; 3]`, finite elements or material points)
///   `[σxx, σyy, σzz, σyz, σxz, σxy]`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct InitialStressSpec<V: SceneVector = [f64; 2]> {
    #[serde(default)]
    pub k0: Option<f64>,
    /// Height of the ground surface (m).
    #[serde(default)]
    pub surface: Option<f64>,
    /// Vertical pressure on the surface (Pa); default 0.
    #[serde(default)]
    pub surcharge: Option<f64>,
    /// `[σxx, σyy, σxy, σzz]` (3D: `[σxx, σyy, σzz, σyz, σxz, σxy]`; Pa, tension
    /// positive), the same at every point.
    #[serde(default)]
    pub stress: Option<V::Stress>,
}

/// `[analysis]`: what eq. 15's inertia term means (`docs/scenes.md`, 'Analysis').
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct AnalysisSpec {
    pub kind: AnalysisKind,
    /// Plane strain (default) or axisymmetric about the y axis (`docs/axisymmetry.md`).
    pub geometry: GeometryKind,
    /// Quasi-static only: the lumped mass is `inertia_ratio · h² · diag K` (K the elastic
    /// stiffness), so that inertia is this fraction of each node's elastic stiffness
    /// (`docs/derivations.md`, 'The quasi-static limit').
    pub inertia_ratio: Option<f64>,
}

impl Default for AnalysisSpec {
    fn default() -> Self {
        Self {
            kind: AnalysisKind::Dynamic,
            geometry: GeometryKind::PlaneStrain,
            inertia_ratio: None,
        }
    }
}

/// `[analysis] geometry`: what the mesh's plane stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GeometryKind {
    /// A slice of unit thickness; forces per metre.
    PlaneStrain,
    /// A meridian section, `x = r ≥ 0`, `y` the axis; integrals per radian, reported
    /// forces for the whole circumference.
    Axisymmetric,
    /// A 3D body on tetrahedra (`docs/3d.md`); forces in N.
    ThreeD,
}

/// By name, with an error that names the field and the value (serde's own names neither
/// the field nor, for a typo, what it should be).
impl<'de> Deserialize<'de> for GeometryKind {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        match name.as_str() {
            "plane_strain" => Ok(GeometryKind::PlaneStrain),
            "axisymmetric" => Ok(GeometryKind::Axisymmetric),
            "3d" => Ok(GeometryKind::ThreeD),
            _ => Err(serde::de::Error::custom(format!(
                "analysis.geometry = \"{name}\": expected \"plane_strain\", \"axisymmetric\" \
                 or \"3d\""
            ))),
        }
    }
}

impl Serialize for GeometryKind {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(match self {
            GeometryKind::PlaneStrain => "plane_strain",
            GeometryKind::Axisymmetric => "axisymmetric",
            GeometryKind::ThreeD => "3d",
        })
    }
}

impl GeometryKind {
    /// The unit of a `[[point_load]]` force (`docs/scenes.md`): per metre of thickness, per
    /// radian (axisymmetric; the reactions, [`force_unit`](Self::force_unit), are the whole
    /// circumference's), or whole.
    pub fn load_unit(self) -> &'static str {
        match self {
            GeometryKind::PlaneStrain => "N/m",
            GeometryKind::Axisymmetric => "N per radian",
            GeometryKind::ThreeD => "N",
        }
    }

    /// The unit of the reported forces: per metre of thickness, or for the whole
    /// circumference (axisymmetric), or whole (3D).
    pub fn force_unit(self) -> &'static str {
        match self {
            GeometryKind::PlaneStrain => "N/m",
            GeometryKind::Axisymmetric | GeometryKind::ThreeD => "N",
        }
    }

    pub fn fem(self) -> talus_fem::Geometry {
        match self {
            GeometryKind::PlaneStrain => talus_fem::Geometry::PlaneStrain,
            GeometryKind::Axisymmetric => talus_fem::Geometry::Axisymmetric,
            GeometryKind::ThreeD => talus_fem::Geometry::ThreeDimensional,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AnalysisKind {
    /// Eq. 15 with the material's density: today's behaviour.
    Dynamic,
    /// The inertia-free limit of eq. 15; time is a load parameter.
    QuasiStatic,
}

#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSpec {
    /// The boundary (by `name`) whose reaction force and displacement go to history.csv.
    pub reaction: Option<String>,
    /// Write a VTU file every this many steps (0: only the last).
    pub vtu_every: usize,
    pub plots: bool,
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            reaction: None,
            vtu_every: 10,
            plots: true,
        }
    }
}
