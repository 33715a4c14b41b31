//! The 3D cases (`docs/3d.md`): the uniaxial-strain column of `scenes/block_3d.toml`, the
//! square footing on undrained clay between the von Mises cylinders inscribed in and
//! circumscribed about Tresca's hexagon, and the extruded plane-strain slope against its
//! 2D factor of safety, dry and with a water table, and the circular footing on clay
//! against its axisymmetric run on the revolved mesh. The integration tests (`block_3d.rs`,
//! `square_footing_clay_3d.rs`, `slope_extruded_3d.rs`, `circular_footing_3d.rs`) run the
//! same functions and check more of their files.
use std::time::Instant;

use talus_fem::ReactionForce;

use super::stability::scene_path;
use super::{case_dir, CaseResult, Check};
use crate::analysis::stability::{self, StabilityRun};
use crate::run::fem::{run_scene, run_scene_3d};
use crate::run::RunOptions;
use crate::scene::{Scene, Scene3, SceneFile};

/// `scenes/block_3d.toml`.
pub const BLOCK_3D: &str = include_str!("../../../../../scenes/block_3d.toml");
/// `scenes/square_footing_clay_3d.toml`.
pub const SQUARE_FOOTING_CLAY_3D: &str =
    include_str!("../../../../../scenes/square_footing_clay_3d.toml");

/// Tresca's `N_c` of a rough square footing: Salgado, Lyamin, Sloan & Yu (2004), the
/// mean of their bounds, and Gourvenec, Randolph & Kingsnorth (2006).
pub const TRESCA_SQUARE_NC: [f64; 2] = [5.78, 5.90];

fn parse3(text: &str, path: Option<std::path::PathBuf>) -> Result<Scene3, String> {
    match SceneFile::parse(text, path) {
        Ok(SceneFile::Fem3(s)) => Ok(s),
        Ok(_) => Err("not read as a 3D scene".into()),
        Err(e) => Err(e.to_string()),
    }
}

fn replaced(text: &str, from: &str, to: &str) -> Result<String, String> {
    if text.contains(from) {
        Ok(text.replacen(from, to, 1))
    } else {
        Err(format!("the scene no longer holds `{from}`"))
    }
}

/// The elastic block under its own weight (ρ = 2000 kg/m³, ν = 0.25, 2 m high): the
/// largest error of the Gauss points' `σ_yy` against `−ρ g (H − y)`, relative to ρ g H.
pub fn block_column_case() -> Vec<CaseResult> {
    let start = Instant::now();
    let computed = (|| -> Result<f64, String> {
        let scene = parse3(BLOCK_3D, None)?;
        let mut options = RunOptions::new(case_dir("block_3d"));
        options.write_fields = false;
        let run = run_scene_3d(&scene, &options, None).map_err(|e| e.to_string())?;
        let model = crate::model::fem::model_3d(&scene).map_err(|e| e.to_string())?;
        let (rho_g, height) = (2000.0 * 9.81, 2.0);
        let sigma = &run.final_state.sigma;
        Ok((model.assembly.gauss_points.iter().enumerate())
            .map(|(p, x)| (sigma[6 * p + 1] + rho_g * (height - x[1])).abs() / (rho_g * height))
            .fold(0.0, f64::max))
    })()
    .unwrap_or(f64::NAN);
    vec![CaseResult {
        case: "block_3d_uniaxial_strain".into(),
        quantity: "largest error of σ_yy against −ρ g (H − y) over the Gauss points, in ρ g H \
                   (P2 tetrahedra)"
            .into(),
        reference: 0.0,
        computed,
        tolerance: 1e-6,
        check: Check::Absolute,
        seconds: start.elapsed().as_secs_f64(),
        source: "uniaxial strain under self-weight (Timoshenko & Goodier, Theory of Elasticity)"
            .into(),
    }]
}

/// `N_c = F / ((B/2)² c)` of the quarter square footing on `cells` with `cone_fit`, on its
/// plateau, and the last step's relative rise.
pub fn square_footing_nc(cells: [usize; 3], cone_fit: &str) -> Result<(f64, f64), String> {
    let text = replaced(
        SQUARE_FOOTING_CLAY_3D,
        "cells = [9, 7, 9]",
        &format!("cells = {cells:?}"),
    )?;
    let text = replaced(
        &text,
        "cone_fit = \"plane_strain\"",
        &format!("cone_fit = \"{cone_fit}\""),
    )?;
    let scene = parse3(&text, None)?;
    let name = format!("square_footing_clay_3d_{cone_fit}_{}", cells[0]);
    let mut options = RunOptions::new(case_dir(&name));
    options.write_fields = false;
    let run = run_scene_3d(&scene, &options, None).map_err(|e| e.to_string())?;
    let f: Vec<f64> = run.records.iter().map(|r| r.reaction_force()).collect();
    let n = f.len();
    if n < 2 {
        return Err("fewer than two steps".into());
    }
    // The quarter footing's area (B/2)² = 0.25 m², c = 10 kPa.
    Ok((f[n - 1] / (0.25 * 1.0e4), (f[n - 1] - f[n - 2]) / f[n - 1]))
}

/// `N₀` of `N(h) = N₀ + C h^p` through `(h₁, n₁)` and `(h₂, n₂)`.
pub fn extrapolated(p: f64, (h1, n1): (f64, f64), (h2, n2): (f64, f64)) -> f64 {
    let c = (n1 - n2) / (h1.powf(p) - h2.powf(p));
    n2 - c * h2.powf(p)
}

/// The square footing's bracket: the inscribed cylinder's `N_c` on 6×5×6 and 9×7×9 cells
/// extrapolated to h → 0 (p = 1) at most 5.78, the circumscribed one (2/√3 times it: a
/// weightless φ = 0 body's limit load scales with the cylinder's radius, checked on the
/// coarse mesh) at least 5.90.
pub fn square_footing_clay_case() -> Vec<CaseResult> {
    let start = Instant::now();
    let runs = (|| -> Result<[f64; 3], String> {
        let (coarse, _) = square_footing_nc([6, 5, 6], "plane_strain")?;
        let (fine, _) = square_footing_nc([9, 7, 9], "plane_strain")?;
        let (outer, _) = square_footing_nc([6, 5, 6], "outer_cone")?;
        Ok([coarse, fine, outer])
    })();
    let [coarse, fine, outer] = runs.unwrap_or([f64::NAN; 3]);
    let inscribed = extrapolated(1.0, (1.0 / 6.0, coarse), (1.0 / 9.0, fine));
    let ratio = 2.0 / 3f64.sqrt();
    let seconds = start.elapsed().as_secs_f64();
    let source = "Salgado et al. 2004 (5.78), Gourvenec et al. 2006 (5.90); limit theorems";
    vec![
        CaseResult {
            case: "square_footing_clay_3d_inscribed".into(),
            quantity: "N_c of the inscribed von Mises cylinder (k_d = √2), 6×5×6 and 9×7×9 \
                       cells extrapolated to h → 0 (p = 1): a lower bound of Tresca's"
                .into(),
            reference: TRESCA_SQUARE_NC[0],
            computed: inscribed,
            tolerance: 0.0,
            check: Check::AtMost,
            seconds,
            source: source.into(),
        },
        CaseResult {
            case: "square_footing_clay_3d_circumscribed".into(),
            quantity: "N_c of the circumscribed cylinder (k_d = 2√6/3) = 2/√3 × the \
                       inscribed, extrapolated: an upper bound of Tresca's"
                .into(),
            reference: TRESCA_SQUARE_NC[1],
            computed: inscribed * ratio,
            tolerance: 0.0,
            check: Check::AtLeast,
            seconds,
            source: source.into(),
        },
        CaseResult {
            case: "square_footing_clay_3d_cylinder_ratio".into(),
            quantity: "N_c circumscribed / inscribed on 6×5×6 cells (reference 2/√3)".into(),
            reference: ratio,
            computed: outer / coarse,
            tolerance: 1e-3,
            check: Check::Relative,
            seconds,
            source: "von Mises cylinders' radii k_d c: 2√6/3 against √2".into(),
        },
    ]
}

/// `scenes/slope_3d_section.msh`: `slope.geo` at twice its element size.
const SECTION: &str = "path = \"slope_3d_section.msh\"";

/// The 2D scene `name` (`slope.toml` or `slope_water.toml`) on the section mesh, and its
/// twin extruded 1 m along z in one layer of P2 tetrahedra with rollers on both z faces
/// (`scenes/slope_extruded.toml`'s form), the base fixed in x, y and z. With `monitor`,
/// `[stability] monitor` names the scene's `[[monitor]]` "crest".
pub fn extruded_slope_scenes(name: &str, monitor: bool) -> Result<(Scene, Scene3), String> {
    let path = scene_path(name);
    let text = std::fs::read_to_string(&path).map_err(|e| e.to_string())?;
    let mut text2 = replaced(&text, "path = \"slope.msh\"", SECTION)?;
    text2 = text2.replace("plots = true", "plots = false");
    if monitor {
        text2 = replaced(
            &text2,
            "tolerance = 0.005",
            "tolerance = 0.005\nmonitor = \"crest\"",
        )?;
    }
    let mut text3 = replaced(
        &text2,
        "gravity = [0.0, -10.0]",
        "gravity = [0.0, -10.0, 0.0]",
    )?;
    text3 = replaced(
        &text3,
        SECTION,
        &format!("{SECTION}\nextrude = [0.0, 1.0]\nlayers = 1"),
    )?;
    text3 = replaced(&text3, "fix = \"xy\"", "fix = \"xyz\"")?;
    text3 = replaced(
        &text3,
        "[analysis]\n",
        "[[boundary]]\nnodes = \"back\"\nfix = \"z\"\n\n[[boundary]]\nnodes = \"front\"\n\
         fix = \"z\"\n\n[analysis]\ngeometry = \"3d\"\n",
    )?;
    text3 = text3.replace("point = [20.0, 10.0]", "point = [20.0, 10.0, 0.5]");
    let s2 = Scene::parse(&text2, Some(path.clone())).map_err(|e| e.to_string())?;
    Ok((s2, parse3(&text3, Some(path))?))
}

/// Both searches of [`extruded_slope_scenes`], the 3D one writing its fields.
pub fn extruded_slope_runs(
    name: &str,
    monitor: bool,
) -> Result<(StabilityRun<4>, StabilityRun<6>), String> {
    let (s2, s3) = extruded_slope_scenes(name, monitor)?;
    let stem = name.trim_end_matches(".toml");
    let run2 = stability::run(&s2, &RunOptions::new(case_dir(&format!("{stem}_2d"))))
        .map_err(|e| e.to_string())?;
    let options = RunOptions {
        write_fields: true,
        ..RunOptions::new(case_dir(&format!("{stem}_extruded")))
    };
    let run3 = stability::run(&s3, &options).map_err(|e| e.to_string())?;
    Ok((run2, run3))
}

/// The extruded slab's factor of safety against the 2D one on the same section: dry
/// (`slope.toml`) and with the water table of `slope_water.toml` (its `[stability]
/// monitor` on the crest).
pub fn extruded_slope_cases() -> Vec<CaseResult> {
    [("slope.toml", false), ("slope_water.toml", true)]
        .into_iter()
        .map(|(name, monitor)| {
            let start = Instant::now();
            let (reference, computed) = extruded_slope_runs(name, monitor)
                .ok()
                .and_then(|(r2, r3)| Some((r2.factor_of_safety.value?, r3.factor_of_safety.value?)))
                .unwrap_or((f64::NAN, f64::NAN));
            CaseResult {
                case: format!("{}_extruded_3d", name.trim_end_matches(".toml")),
                quantity: "F of the slab extruded along z with rollers on both z faces, P2 \
                           tetrahedra (reference: F of the 2D section, P2 triangles)"
                    .into(),
                reference,
                computed,
                tolerance: 0.01,
                check: Check::Relative,
                seconds: start.elapsed().as_secs_f64(),
                source: "plane strain: the extruded slab's mechanism is the section's".into(),
            }
        })
        .collect()
}

/// `N_c = Q / (π R² c)` of the circular footing (R = 0.5 m, c = 10 kPa) after each step
/// of the 3D quarter cylinder (`scenes/circular_footing_3d.toml`, 4 × the quarter's load)
/// and of its axisymmetric run on the meridian it was revolved from
/// (`scenes/circular_footing_axi.toml`, whose load is the whole footing's):
/// `(three_d, axisymmetric)`.
pub fn circular_footing_nc() -> Result<(Vec<f64>, Vec<f64>), String> {
    let area_c = std::f64::consts::PI * 0.25 * 1.0e4;
    let options = |name: &str| RunOptions {
        write_fields: false,
        ..RunOptions::new(case_dir(name))
    };
    let path3 = scene_path("circular_footing_3d.toml");
    let text3 = std::fs::read_to_string(&path3).map_err(|e| e.to_string())?;
    let run3 = run_scene_3d(&parse3(&text3, Some(path3))?, &options("circular_3d"), None)
        .map_err(|e| e.to_string())?;
    let path = scene_path("circular_footing_axi.toml");
    let text = std::fs::read_to_string(&path).map_err(|e| e.to_string())?;
    let axi = Scene::parse(&text, Some(path)).map_err(|e| e.to_string())?;
    let run = run_scene(&axi, &options("circular_axi")).map_err(|e| e.to_string())?;
    let nc = |q: f64| q / area_c;
    Ok((
        run3.records
            .iter()
            .map(|r| nc(4.0 * r.reaction_force()))
            .collect(),
        run.records.iter().map(|r| nc(r.reaction_force())).collect(),
    ))
}

/// The circular footing's limit load in 3D against its axisymmetric run, within 2 %
/// (issue 25).
pub fn circular_footing_case() -> Vec<CaseResult> {
    let start = Instant::now();
    let (computed, reference) = circular_footing_nc()
        .ok()
        .and_then(|(n3, na)| Some((*n3.last()?, *na.last()?)))
        .unwrap_or((f64::NAN, f64::NAN));
    vec![CaseResult {
        case: "circular_footing_3d_vs_axisymmetric".into(),
        quantity: "N_c of a rough rigid circular footing on clay (outer cone), quarter \
                   cylinder of P2 tetrahedra revolved from the axisymmetric meridian \
                   (reference: the axisymmetric run)"
            .into(),
        reference,
        computed,
        tolerance: 0.02,
        check: Check::Relative,
        seconds: start.elapsed().as_secs_f64(),
        source: "axisymmetry: the 3D mechanism of an axisymmetric footing is axisymmetric".into(),
    }]
}
