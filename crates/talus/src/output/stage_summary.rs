//! `summary.json`'s entry for one stage of a staged run (`docs/scenes.md`, 'Stages').
use serde::{Deserialize, Serialize};

use super::summary::FactorOfSafety;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StageSummary {
    pub name: String,
    /// The run's steps this stage took: `first_step ..= last_step`.
    pub first_step: usize,
    pub last_step: usize,
    /// The time at the stage's end (s).
    pub time: f64,
    /// Elements present in the stage.
    pub elements: usize,
    /// The regions it dug out and built.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub deactivated: Vec<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub activated: Vec<String>,
    /// The reported boundary's reaction at the stage's end, when the scene reports one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reaction: Option<f64>,
    /// Where the stage asked for it (`factor_of_safety = true`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub factor_of_safety: Option<FactorOfSafety>,
}
