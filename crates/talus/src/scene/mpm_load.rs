use super::source::{error_near, Locate, SceneDocument};
use super::{MpmSceneSpec, SceneError};

/// A parsed MPM scene.
pub type MpmScene = SceneDocument<MpmSceneSpec>;

impl MpmScene {
    /// An error at `field` (`wall[1].friction`), with the line where it stands, or where
    /// it belongs when it is missing.
    pub fn error(&self, field: &str, message: impl Into<String>) -> SceneError {
        error_near(&self.source, self.path.as_ref(), field, message.into())
    }
}

impl Locate for MpmScene {
    fn error(&self, field: &str, message: impl Into<String>) -> SceneError {
        MpmScene::error(self, field, message)
    }
}
