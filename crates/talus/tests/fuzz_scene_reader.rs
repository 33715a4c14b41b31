//! Fuzzing of the scene reader (`talus run SCENE`): the shipped scenes mutated, and footing
//! scenes generated with values across many orders of magnitude. A scene is read and
//! validated as `talus run` does it (`SceneFile`, the size estimate, then the model of the
//! run: `Model::from_scene`, its initial state and result columns, or the stability analysis,
//! or `MpmModel::from_scene`), without stepping. Each stage returns Ok or an error, never
//! panics; a model that builds holds finite numbers.
//! `TALUS_FUZZ_CASES` / `TALUS_FUZZ_SCALE` raise the case count (`cargo xtask fuzz`);
//! `docs/scenes.md`, 'Fuzzing'.
use std::path::{Path, PathBuf};

use proptest::prelude::*;
use proptest::sample::select;
use talus::model::fem::{FromScene, Model};
use talus::model::mpm::{MpmDocument, MpmModel, MpmSpace};
use talus::model::size::SizeEstimate;
use talus::run::fem::FemResults;
use talus::scene::SceneFile;
use talus::scene::SceneVector;
use talus_mpm::{Dimension, Mandel};

#[path = "../../ssn/tests/common/mutations.rs"]
mod mutations;
use mutations::{apply, cases, fuzz, mutated, Outcome};

/// Gauss points or particles above which a valid scene is not built in a fuzz case (a
/// case stays under about 50 ms); the shipped scenes have at most 6720.
const MAX_POINTS: f64 = 20_000.0;
/// Grid nodes above which an MPM scene is not built (the shipped ones have at most 4136).
const MAX_GRID_NODES: f64 = 20_000.0;

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// Every shipped scene, with its path (Gmsh meshes are found next to it).
fn seeds() -> Vec<(PathBuf, Vec<u8>)> {
    let mut seeds: Vec<(PathBuf, Vec<u8>)> = std::fs::read_dir(scenes_dir())
        .expect("scenes/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .map(|p| {
            let text = std::fs::read(&p).expect("scene");
            (p, text)
        })
        .collect();
    seeds.sort();
    assert!(seeds.len() >= 10, "{} scenes found", seeds.len());
    seeds
}

fn finite(v: &[f64], what: &str) -> Result<(), String> {
    match v.iter().find(|x| !x.is_finite()) {
        Some(x) => Err(format!("{what} holds {x}")),
        None => Ok(()),
    }
}

/// Reads, validates and builds the scene as `talus run` does before its first step.
fn read(bytes: &[u8], path: &Path) -> Result<Outcome, String> {
    let text = String::from_utf8_lossy(bytes);
    let file = match SceneFile::parse(&text, Some(path.to_path_buf())) {
        Ok(f) => f,
        Err(e) => return Ok(Outcome::Refused(e.to_string())),
    };
    match file {
        SceneFile::Fem(scene) => {
            let estimate = match SizeEstimate::of_fem(&scene) {
                Ok(e) => e,
                Err(e) => return Ok(Outcome::Refused(e.to_string())),
            };
            if let Err(e) = estimate.check(None) {
                return Ok(Outcome::Refused(e.to_string()));
            }
            if estimate.points > MAX_POINTS {
                return Ok(Outcome::Skipped(format!("{} points", estimate.points)));
            }
            if scene.spec.stability.is_some() {
                return match talus::analysis::stability::Analysis::new(&scene) {
                    Ok(_) => Ok(Outcome::Read),
                    Err(e) => Ok(Outcome::Refused(e.to_string())),
                };
            }
            let model = match Model::from_scene(&scene) {
                Ok(m) => m,
                Err(e) => return Ok(Outcome::Refused(e.to_string())),
            };
            let state = match model.initial_state(&scene) {
                Ok(s) => s,
                Err(e) => return Ok(Outcome::Refused(e.to_string())),
            };
            if let Err(e) = FemResults::new(&scene, &model, "step") {
                return Ok(Outcome::Refused(e.to_string()));
            }
            let nodes: Vec<f64> = model.mesh.nodes.iter().flatten().copied().collect();
            finite(&nodes, "the mesh")?;
            finite(&model.force_free, "the forces")?;
            finite(&model.force_prescribed, "the forces on prescribed dofs")?;
            finite(&model.prescribed_velocity, "the prescribed velocities")?;
            finite(&state.sigma, "the initial stress")?;
            finite(&model.loads_at(0.0).force_free, "the loads at t = 0")?;
            Ok(Outcome::Read)
        }
        SceneFile::Fem3(scene) => match talus::model::fem::model_3d(&scene) {
            Ok(model) => {
                finite(&model.force_free, "the forces on free dofs")?;
                finite(&model.prescribed_velocity, "the prescribed velocities")?;
                Ok(Outcome::Read)
            }
            Err(e) => Ok(Outcome::Refused(e.to_string())),
        },
        SceneFile::Mpm3(scene) => read_mpm::<6, 3>(&scene),
        SceneFile::Mpm(scene) => read_mpm::<4, 2>(&scene),
    }
}
/// A material point scene of either dimension read into its model (or refused), its
/// particles finite.
fn read_mpm<const D: usize, const N: usize>(scene: &MpmDocument<N>) -> Result<Outcome, String>
where
    Mandel<D>: MpmSpace<D> + Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    let estimate = SizeEstimate::of_mpm(scene);
    if let Err(e) = estimate.check(None) {
        return Ok(Outcome::Refused(e.to_string()));
    }
    if !(estimate.points <= MAX_POINTS && estimate.grid_nodes <= MAX_GRID_NODES) {
        return Ok(Outcome::Skipped(format!(
            "{} particles, {} grid nodes",
            estimate.points, estimate.grid_nodes
        )));
    }
    let model = match MpmModel::<D>::build(scene) {
        Ok(m) => m,
        Err(e) => return Ok(Outcome::Refused(e.to_string())),
    };
    let p = &model.particles;
    let xs: Vec<f64> = p
        .position
        .iter()
        .flat_map(|x| x.as_ref().to_vec())
        .collect();
    finite(&xs, "the particle positions")?;
    let stress: Vec<f64> = p.stress.iter().flatten().copied().collect();
    finite(&stress, "the particle stresses")?;
    finite(&p.mass, "the particle masses")?;
    finite(&p.volume, "the particle volumes")?;
    let loads: Vec<f64> = (p.external_force.iter())
        .flat_map(|f| f.as_ref().to_vec())
        .collect();
    finite(&loads, "the particle loads")?;
    Ok(Outcome::Read)
}

#[test]
fn mutated_scenes_are_read_or_refused_never_panic() {
    let seeds = seeds();
    fuzz(
        "scene .toml (mutated files)",
        cases(4_000),
        mutated(seeds.len()),
        |(seed, mutations)| {
            let (path, text) = &seeds[*seed];
            read(&apply(text, mutations), path)
        },
    );
}

// ------------------------------------------------------------------ generated scenes

/// A number across the range a user could type: every order of magnitude from 1e-300 to
/// 1e300 of either sign, zero, and the ordinary values of a soil.
fn magnitude() -> impl Strategy<Value = f64> {
    prop_oneof![
        2 => (-300i32..=300, 1.0f64..10.0, any::<bool>())
            .prop_map(|(e, m, neg)| if neg { -m } else { m } * 10f64.powi(e)),
        1 => Just(0.0),
        2 => -100.0f64..100.0,
    ]
}

/// A strip footing on a rectangle (the shape of `scenes/footing.toml`) with every number
/// drawn from [`magnitude`] or a small count.
#[derive(Debug, Clone)]
struct Footing {
    cells: [u64; 2],
    p2: bool,
    x: [f64; 2],
    y: [f64; 2],
    material: [f64; 6],
    velocity: f64,
    traction: f64,
    gravity: f64,
    time: (f64, u64),
    k0: Option<f64>,
}

/// Mostly an ordinary value (`typical` times a factor in [0.5, 2]), sometimes any
/// [`magnitude`]: most generated scenes then differ from a valid one in a field or two.
fn value(typical: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        12 => (0.5f64..2.0).prop_map(move |f| f * typical),
        1 => magnitude(),
    ]
}

/// Mostly exactly `typical` (the footing's geometry: its boxes need nodes at x = ±0.25 on
/// y = 0), sometimes any [`magnitude`].
fn exact(typical: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        12 => Just(typical),
        1 => magnitude(),
    ]
}

fn count(typical: impl Strategy<Value = u64> + 'static) -> impl Strategy<Value = u64> {
    prop_oneof![
        12 => typical,
        1 => select(&[0u64, 1, 1000, 100_000, u32::MAX as u64, u64::MAX][..]),
    ]
}

fn footing() -> impl Strategy<Value = Footing> {
    (
        // x nodes at -1 + 2k/n: n = 8 or 16 puts nodes at ±0.25.
        (count(select(&[8u64, 16][..])), count(1u64..6)),
        any::<bool>(),
        [exact(-1.0), exact(1.0)],
        [exact(-1.0), exact(0.0)],
        [
            value(1e9),
            value(0.2),
            value(27.0),
            value(2e3),
            value(10.0),
            value(2e3),
        ],
        (value(-1e-3), value(-2e4), value(-9.81)),
        (value(1e-2), count(1u64..5)),
        proptest::option::of(value(0.5)),
    )
        .prop_map(
            |((nx, ny), p2, x, y, material, (velocity, traction, gravity), time, k0)| Footing {
                cells: [nx, ny],
                p2,
                x,
                y,
                material,
                velocity,
                traction,
                gravity,
                time,
                k0,
            },
        )
}

impl Footing {
    fn text(&self) -> String {
        let [e, nu, phi, c, psi, rho] = self.material;
        let k0 = self
            .k0
            .map(|k| format!("[initial_stress]\nk0 = {k:e}\nsurface = 0.0\n"))
            .unwrap_or_default();
        format!(
            "gravity = [0.0, {g:e}]\n\
             [mesh.rectangle]\nx = [{x0:e}, {x1:e}]\ny = [{y0:e}, {y1:e}]\ncells = [{nx}, {ny}]\n\
             order = \"{order}\"\n\
             [material]\nyoung_modulus = {e:e}\npoisson_ratio = {nu:e}\nfriction_angle = {phi:e}\n\
             cohesion = {c:e}\ndilatancy_angle = {psi:e}\ndensity = {rho:e}\ncone_fit = \"plane_strain\"\n\
             [[boundary]]\nnodes = \"bottom\"\nfix = \"xy\"\n\
             [[boundary]]\nname = \"footing\"\nnodes = {{ box = [[-0.25, -1e-9], [0.25, 1e-9]] }}\n\
             fix = \"xy\"\nvelocity = [0.0, {v:e}]\n\
             [[traction]]\nedges = {{ box = [[0.25, -1e-9], [1.0, 1e-9]] }}\nvalue = [0.0, {t:e}]\n\
             {k0}\
             [time]\nstep = {h:e}\nsteps = {steps}\n\
             [output]\nreaction = \"footing\"\n",
            g = self.gravity,
            x0 = self.x[0],
            x1 = self.x[1],
            y0 = self.y[0],
            y1 = self.y[1],
            nx = self.cells[0],
            ny = self.cells[1],
            order = if self.p2 { "P2" } else { "P1" },
            v = self.velocity,
            t = self.traction,
            h = self.time.0,
            steps = self.time.1,
        )
    }
}

/// Generated footings: each one is read, validated and built, or refused with a message;
/// never a panic.
#[test]
fn generated_footings_are_built_or_refused_never_panic() {
    let path = scenes_dir().join("generated.toml");
    fuzz(
        "scene .toml (generated footings)",
        cases(4_000),
        footing(),
        |f| read(f.text().as_bytes(), &path),
    );
}

/// The generated footing with ordinary values is built: the generator can reach the
/// build stage, so the property above exercises it.
#[test]
fn generated_footing_with_ordinary_values_builds() {
    let f = Footing {
        cells: [8, 4],
        p2: true,
        x: [-1.0, 1.0],
        y: [-1.0, 0.0],
        material: [1e9, 0.3, 27.0, 2e3, 14.0, 2e3],
        velocity: -1e-3,
        traction: -2e4,
        gravity: -9.81,
        time: (1e-2, 3),
        k0: Some(0.5),
    };
    let outcome = read(f.text().as_bytes(), &scenes_dir().join("generated.toml")).unwrap();
    match outcome {
        Outcome::Read => {}
        Outcome::Refused(e) | Outcome::Skipped(e) => panic!("refused: {e}\n{}", f.text()),
    }
}
