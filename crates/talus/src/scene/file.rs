//! A scene file of either kind: finite elements (`[mesh]`) or material points (`[grid]`).
use std::path::{Path, PathBuf};

use super::mpm_load::parse_mpm;
use super::source::{error_at, read, SceneDocument};
use super::{MpmScene, MpmScene3, Scene, Scene3, SceneError, SceneSpec};

/// A 3D FEM scene: read and checked key by key (its own errors first, then a 2D key in
/// it, `scene::dimension`).
fn three_d_scene(source: &str, path: Option<PathBuf>) -> Result<Scene3, SceneError> {
    let scene = SceneDocument::<SceneSpec<[f64; 3]>>::parse(source, path)?;
    super::dimension::check(&scene, source, &scene.spec)?;
    Ok(scene)
}

/// What [`SceneFile::parse`] found.
#[derive(Debug, Clone)]
pub enum SceneFile {
    Fem(Scene),
    /// A 3D FEM scene (`[analysis] geometry = "3d"`, tetrahedra).
    Fem3(Scene3),
    Mpm(MpmScene),
    /// A 3D MPM scene (`[analysis] geometry = "3d"` with a `[grid]`, `docs/3d-mpm.md`).
    Mpm3(MpmScene3),
}

impl SceneFile {
    pub fn from_path(path: &Path) -> Result<Self, SceneError> {
        let source = read(path)?;
        Self::parse(&source, Some(path.to_path_buf()))
    }

    /// A scene with `[mesh]` is FEM, one with `[grid]` MPM; neither or both is an error
    /// naming both.
    pub fn parse(source: &str, path: Option<PathBuf>) -> Result<Self, SceneError> {
        let Ok(table) = toml::from_str::<toml::Table>(source) else {
            // Not TOML: the FEM parser reports the syntax error with its line.
            return Scene::parse(source, path).map(SceneFile::Fem);
        };
        let three_d = table
            .get("analysis")
            .and_then(|a| a.get("geometry"))
            .and_then(|g| g.as_str())
            == Some("3d");
        if table.contains_key("mesh") && !table.contains_key("grid") {
            let at = |field: &str, message: String| error_at(source, path.as_ref(), field, message);
            super::dimension::stress_components(&table, three_d, "FEM", &at)?;
        }
        match (table.contains_key("mesh"), table.contains_key("grid")) {
            (true, false) if three_d => three_d_scene(source, path).map(SceneFile::Fem3),
            (true, false) => Scene::parse(source, path).map(SceneFile::Fem),
            (false, true) if three_d => parse_mpm(source, path).map(SceneFile::Mpm3),
            (false, true) => parse_mpm(source, path).map(SceneFile::Mpm),
            (true, true) => {
                let mesh_line = error_at(source, path.as_ref(), "mesh", String::new()).line;
                let mesh_at = mesh_line.map(|l| format!(", line {l}")).unwrap_or_default();
                Err(error_at(
                    source,
                    path.as_ref(),
                    "grid",
                    format!(
                        "both [mesh] (finite elements{mesh_at}) and [grid] (material points) \
                         are given: a scene has exactly one of them"
                    ),
                ))
            }
            (false, false) => Err(SceneError {
                file: path,
                field: "mesh or grid".into(),
                line: None,
                message: "neither [mesh] (finite elements) nor [grid] (material points) is given: \
                          a scene has exactly one of them"
                    .into(),
            }),
        }
    }
}
