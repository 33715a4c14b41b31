//! A scene file of either kind: finite elements (`[mesh]`) or material points (`[grid]`).
use std::path::{Path, PathBuf};

use super::source::{error_at, read, SceneDocument};
use super::{MpmScene, Scene, SceneError, SceneSpec};

/// A 3D FEM scene: read and checked key by key (its own errors first), then refused, since
/// a 3D scene file does not run yet (`docs/3d.md`, 'Next').
fn three_d_scene(source: &str, path: Option<PathBuf>) -> SceneError {
    let scene = match SceneDocument::<SceneSpec<[f64; 3]>>::parse(source, path) {
        Ok(scene) => scene,
        Err(e) => return e,
    };
    if let Err(e) = super::dimension::check(&scene, source, &scene.spec) {
        return e;
    }
    scene.error("analysis.geometry", super::dimension::NO_3D_RUN)
}

/// What [`SceneFile::parse`] found.
#[derive(Debug, Clone)]
pub enum SceneFile {
    Fem(Scene),
    Mpm(MpmScene),
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
        match (table.contains_key("mesh"), table.contains_key("grid")) {
            (true, false) if three_d => Err(three_d_scene(source, path)),
            (true, false) => Scene::parse(source, path).map(SceneFile::Fem),
            (false, true) => MpmScene::parse(source, path).map(SceneFile::Mpm),
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
