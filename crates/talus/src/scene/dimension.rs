//! Which keys belong to which dimension (`docs/3d.md`): a 2D scene (plane strain,
//! axisymmetry) takes `[mesh.rectangle]`, `fix` without z and loads on `edges`; a 3D one
//! (`[analysis] geometry = "3d"`) `[mesh.box]`, `fix` with z and loads on `faces`. Vectors
//! and boxes have 2 or 3 components, which their types check ([`SceneVector`]).
//!
//! [`SceneVector`]: super::SceneVector
use super::{GeometryKind, Locate, SceneError, SceneSpec, SceneVector};

/// Why a 2D scene type refuses the 3D geometry: a 3D scene is read as one
/// (`SceneFile::parse`, which `talus run` uses), with 3-component vectors.
pub(crate) const NO_3D_RUN: &str = "\"3d\": a 3D scene is read as one (SceneFile::parse, \
    `talus run`, docs/3d.md), not as a 2D scene";

/// The sections whose loads act on boundary facets: edges in 2D, faces in 3D.
const FACET_SECTIONS: [&str; 2] = ["traction", "pressure"];

/// Refuses a key of the other dimension in `spec` (read from `source`): `faces` in 2D,
/// `edges` in 3D (the spec keeps either under `edges`), and in a 2D scene the 3D geometry,
/// `[mesh.box]` and a `fix` naming z.
pub fn check<V: SceneVector>(
    scene: &impl Locate,
    source: &str,
    spec: &SceneSpec<V>,
) -> Result<(), SceneError> {
    let three_d = V::DIM == 3;
    let (wrong, right) = if three_d {
        ("edges", "faces")
    } else {
        ("faces", "edges")
    };
    if let Ok(table) = toml::from_str::<toml::Table>(source) {
        for section in FACET_SECTIONS {
            let Some(items) = table.get(section).and_then(|v| v.as_array()) else {
                continue;
            };
            if let Some(k) = items
                .iter()
                .position(|item| item.as_table().is_some_and(|t| t.contains_key(wrong)))
            {
                return Err(scene.error(
                    &format!("{section}[{k}].{wrong}"),
                    format!(
                        "a {} scene's loads act on `{right}`",
                        if three_d { "3D" } else { "2D" }
                    ),
                ));
            }
        }
    }
    if three_d {
        return Ok(());
    }
    if spec.analysis.geometry == GeometryKind::ThreeD {
        return Err(scene.error("analysis.geometry", NO_3D_RUN));
    }
    if let super::MeshSpec::Box { .. } = spec.mesh {
        return Err(three_d_key(scene, "mesh.box", "a box of tetrahedra"));
    }
    if let super::MeshSpec::Gmsh {
        extrude, layers, ..
    } = &spec.mesh
    {
        if extrude.is_some() || layers.is_some() {
            let key = if extrude.is_some() {
                "extrude"
            } else {
                "layers"
            };
            return Err(three_d_key(
                scene,
                &format!("mesh.gmsh.{key}"),
                "an extrusion of the 2D mesh along z into tetrahedra",
            ));
        }
    }
    if let Some((k, b)) = spec
        .boundary
        .iter()
        .enumerate()
        .find(|(_, b)| b.fix.names_z())
    {
        let what = format!("{:?} names z, which", b.fix);
        return Err(three_d_key(scene, &format!("boundary[{k}].fix"), &what));
    }
    Ok(())
}

/// A 3D key in a 2D scene: `what` is 3D.
pub(crate) fn three_d_key(scene: &impl Locate, field: &str, what: &str) -> SceneError {
    scene.error(
        field,
        format!("{what} is 3D: it needs [analysis] geometry = \"3d\" (this scene is 2D)"),
    )
}

/// A uniform `[initial_stress] stress` of the other dimension's length (4 components in 3D,
/// 6 in 2D) in a `kind` (FEM or MPM) scene, refused naming the field and the form.
pub(super) fn stress_components(
    table: &toml::Table,
    three_d: bool,
    kind: &str,
    at: &dyn Fn(&str, String) -> SceneError,
) -> Result<(), SceneError> {
    let stress =
        (table.get("initial_stress").and_then(|t| t.get("stress"))).and_then(|v| v.as_array());
    let Some(stress) = stress else {
        return Ok(());
    };
    let n = stress.len();
    let (other, this, form) = if three_d {
        (4, "3D", <[f64; 3]>::STRESS_FORM.to_string())
    } else {
        (
            6,
            "2D",
            format!(
                "{}; [analysis] geometry = \"3d\" makes a scene 3D",
                <[f64; 2]>::STRESS_FORM
            ),
        )
    };
    if n != other {
        return Ok(());
    }
    Err(at(
        "initial_stress.stress",
        format!(
            "{} has {n} components: the uniform stress of a {this} {kind} scene has {} ({form})",
            toml::Value::Array(stress.clone()),
            if three_d { 6 } else { 4 }
        ),
    ))
}
