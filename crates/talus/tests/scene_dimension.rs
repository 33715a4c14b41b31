//! The scene keys of each dimension (`docs/3d.md`, issue 25's scene contract): a 3D scene
//! (`[analysis] geometry = "3d"`) reads `[mesh.box]`, `fix` strings with z, 3-component
//! vectors and boxes, and loads on `faces`; a 2D scene refuses each of them, naming the
//! field, and a 3D scene refuses loads on `edges`.
use crate::common;
use common::{fem, fem_error, replaced, FOOTING};
use talus::scene::{dimension, Fix, MeshSpec, SceneDocument, SceneSpec, Selection};

/// A 3D block under its weight and a square footing, in the contract's syntax.
const BLOCK: &str = r#"
gravity = [0.0, -9.81, 0.0]

[mesh.box]
x = [0.0, 2.0]
y = [-1.0, 0.0]
z = [0.0, 2.0]
cells = [4, 2, 4]
order = "P2"
focus = [0.0, 0.0, 0.0]
ratio = [1.0, 1.1, 1.0]

[analysis]
geometry = "3d"

[material]
young_modulus = 1.0e8
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 5.0e3
cone_fit = "outer_cone"
density = 2.0e3

[[boundary]]
nodes = "bottom"
fix = "xyz"

[[boundary]]
nodes = "left"
fix = "x"

[[boundary]]
nodes = "back"
fix = "z"

[[boundary]]
name = "footing"
nodes = { box = [[0.0, -1e-9, 0.0], [0.5, 1e-9, 0.5]] }
fix = "xyz"
velocity = [0.0, -1.0e-3, 0.0]

[[traction]]
faces = { box = [[0.5, -1e-9, 0.0], [2.0, 1e-9, 2.0]] }
value = [0.0, -10.0e3, 0.0]

[[pressure]]
faces = "right"
value = 5.0e3

[time]
step = 1.0e-2
steps = 10
"#;

type Scene3 = SceneDocument<SceneSpec<[f64; 3]>>;

#[test]
fn a_3d_scene_reads_boxes_fix_strings_vectors_and_faces() {
    let scene = Scene3::parse(BLOCK, None).unwrap_or_else(|e| panic!("{e}"));
    let spec = &scene.spec;
    assert_eq!(spec.gravity, Some([0.0, -9.81, 0.0]));
    match &spec.mesh {
        MeshSpec::Box {
            z, cells, ratio, ..
        } => {
            assert_eq!(*z, [0.0, 2.0]);
            assert_eq!(*cells, [4, 2, 4]);
            assert_eq!(*ratio, [1.0, 1.1, 1.0]);
        }
        other => panic!("{other:?}"),
    }
    let fixes: Vec<Fix> = spec.boundary.iter().map(|b| b.fix).collect();
    assert_eq!(fixes, [Fix::Xyz, Fix::X, Fix::Z, Fix::Xyz]);
    assert!((0..3).all(|c| Fix::Xyz.fixes(c)));
    assert!(Fix::Z.fixes(2) && !Fix::Z.fixes(0) && !Fix::Z.fixes(1));
    assert!(Fix::Yz.fixes(1) && Fix::Yz.fixes(2) && !Fix::Yz.fixes(0));
    assert_eq!(spec.boundary[3].velocity, [0.0, -1.0e-3, 0.0]);
    assert_eq!(
        spec.traction[0].edges,
        Selection::Box {
            corners: [[0.5, -1e-9, 0.0], [2.0, 1e-9, 2.0]]
        }
    );
    assert_eq!(spec.pressure[0].edges, Selection::Named("right".into()));
    dimension::check(&scene, &scene.source, &scene.spec).unwrap();
}

#[test]
fn a_3d_scene_refuses_loads_on_edges() {
    let text = replaced(BLOCK, "faces = \"right\"", "edges = \"right\"");
    let scene = Scene3::parse(&text, None).unwrap();
    let err = dimension::check(&scene, &scene.source, &scene.spec).unwrap_err();
    assert_eq!(err.field, "pressure[0].edges");
    assert!(err.message.contains("`faces`"), "{err}");
}

#[test]
fn a_2d_scene_refuses_3d_keys_naming_the_field() {
    let cases = [
        (
            replaced(FOOTING, "nodes = \"left\"\nfix = \"x\"", "nodes = \"left\"\nfix = \"xz\""),
            "boundary[1].fix",
        ),
        (
            replaced(
                FOOTING,
                "[mesh.rectangle]\nx = [-1.0, 1.0]          # L = 2 m\ny = [-1.0, 0.0]          # ground surface at y = 0\ncells = [32, 14]         # 896 P2 triangles (the paper: 853 elements)",
                "[mesh.box]\nx = [-1.0, 1.0]\ny = [-1.0, 0.0]\nz = [0.0, 1.0]\ncells = [4, 2, 2]",
            )
            .replace("focus = [0.0, 0.0]       # refined toward the surface\n", "")
            .replace("ratio = [1.0, 1.1]       # uniform in x: the footing edges x = ±0.25 are nodes\n", ""),
            "mesh.box",
        ),
        (
            replaced(
                FOOTING,
                "[[traction]]\nedges =",
                "[[traction]]\nfaces =",
            ),
            "traction[0].faces",
        ),
        (
            replaced(FOOTING, "[time]", "[analysis]\ngeometry = \"3d\"\n\n[time]"),
            "analysis.geometry",
        ),
    ];
    for (text, field) in cases {
        let err = fem_error(&text);
        assert_eq!(err.field, field, "{err}");
        assert!(err.line.is_some(), "{err}: no line");
    }
}

#[test]
fn a_3_component_vector_in_a_2d_scene_is_refused_at_its_line() {
    let text = replaced(
        FOOTING,
        "velocity = [0.0, -1.0e-3]",
        "velocity = [0.0, -1.0e-3, 0.0]",
    );
    let err = talus::scene::Scene::parse(&text, None).unwrap_err();
    assert!(err.field.contains("velocity"), "{err}");
    assert!(err.line.is_some(), "{err}");
    // and the 2D footing itself is untouched by the 3D keys
    let _ = fem(FOOTING);
}

/// A 3D scene file is read key by key (a bad key is named) and, valid, read as a 3D
/// scene (`SceneFile::Fem3`, which `talus run` runs: tests/block_3d.rs).
#[test]
fn a_3d_scene_file_is_checked_key_by_key_and_read_as_3d() {
    use talus::scene::SceneFile;
    assert!(matches!(
        SceneFile::parse(BLOCK, None),
        Ok(SceneFile::Fem3(_))
    ));
    let bad = replaced(BLOCK, "fix = \"z\"", "fix = \"w\"");
    let err = SceneFile::parse(&bad, None).unwrap_err();
    assert!(err.line.is_some() && err.message.contains("`xyz`"), "{err}");
    let edges = replaced(BLOCK, "faces = \"right\"", "edges = \"right\"");
    assert_eq!(
        SceneFile::parse(&edges, None).unwrap_err().field,
        "pressure[0].edges"
    );
}
