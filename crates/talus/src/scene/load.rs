use std::path::PathBuf;

use super::source::{error_at, Locate, SceneDocument};
use super::{SceneError, SceneSpec, SceneVector};

/// A parsed FEM scene.
pub type Scene = SceneDocument<SceneSpec>;

/// A parsed 3D FEM scene (`[analysis] geometry = "3d"`).
pub type Scene3 = SceneDocument<SceneSpec<[f64; 3]>>;

/// A FEM scene of `N`-component points: [`Scene`] (2) or [`Scene3`] (3).
pub type SceneOf<const N: usize> = SceneDocument<SceneSpec<[f64; N]>>;

/// The text of `scenes/footing.toml`, shipped in the binary.
pub const BUILTIN_FOOTING: &str = include_str!("../../../../scenes/footing.toml");

/// The paper's footing (Fig. 3), shipped in the binary: `scenes/footing.toml`.
pub fn builtin_footing() -> Scene {
    Scene::parse(BUILTIN_FOOTING, None).expect("the built-in scene is valid")
}

/// The built-in footing on `cells = [nx, ny]` with the paper mesh's vertical grading
/// (1.1 per cell over 14 cells: `ratio = [1, 1.1^(14/ny)]`): the meshes of the scaling
/// benchmarks (`docs/performance.md`).
pub fn builtin_footing_with_cells(cells: [usize; 2]) -> Scene {
    let mut scene = builtin_footing();
    if let super::MeshSpec::Rectangle {
        cells: c, ratio, ..
    } = &mut scene.spec.mesh
    {
        *c = cells;
        ratio[1] = paper_grading(cells[1]);
    }
    scene
}

/// The vertical `ratio` of the paper mesh's grading on `ny` cells: the 14 cells' total
/// `1.1^13`, spread as `1.1^(14/ny)` per cell.
pub fn paper_grading(ny: usize) -> f64 {
    1.1f64.powf(14.0 / ny as f64)
}

/// A FEM scene in 2D or 3D (`V` its vectors): the errors and paths of both.
impl<V: SceneVector> SceneDocument<SceneSpec<V>> {
    /// An error at `field` (a path such as `material.young_modulus` or `boundary[1].nodes`),
    /// with the line where that field stands in the file.
    pub fn error(&self, field: &str, message: impl Into<String>) -> SceneError {
        error_at(&self.source, self.path.as_ref(), field, message.into())
    }

    /// Relative paths in the scene are relative to the scene file.
    pub fn resolve(&self, relative: &str) -> PathBuf {
        match self.path.as_ref().and_then(|p| p.parent()) {
            Some(dir) => dir.join(relative),
            None => PathBuf::from(relative),
        }
    }
}

impl<V: SceneVector> Locate for SceneDocument<SceneSpec<V>> {
    fn error(&self, field: &str, message: impl Into<String>) -> SceneError {
        SceneDocument::<SceneSpec<V>>::error(self, field, message)
    }
}
