//! `summary.json`, written at the end of every run (finished or failed): how it ended, the
//! named boundaries' final and peak reactions, the monitors' final values and the limit
//! load when the reported reaction levelled off (`docs/scenes.md`, 'summary.json'); and
//! the same in one sentence for the run's last line.
use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::plateau::PlateauCriterion;
use super::OutputError;

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    Finished,
    /// A step did not converge even after its halvings.
    NotConverged,
    /// Any other error (solver setup, an inverted particle, a file that cannot be written).
    Failed,
    /// The body accelerated without bound under its loads (`docs/scenes.md`, 'Collapse').
    Collapsed,
    /// SIGINT/SIGTERM stopped the run between two steps.
    Interrupted,
}

/// Where a collapsed run ended: the step after which the criterion held (MPM: the step
/// that left the grid) and the time reached then (s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CollapseTime {
    pub step: usize,
    pub time: f64,
}

/// Reaction of a named boundary (N/m): the force it applies to the body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BoundaryReaction {
    /// `[fx, fy]` (3D: `[fx, fy, fz]`) after the last step.
    #[serde(rename = "final")]
    pub last: Vec<f64>,
    /// The force of the step with the largest `√(fx² + fy² [+ fz²])`, and that step.
    pub peak: Vec<f64>,
    pub peak_step: usize,
}

/// A monitor's displacement (m) and velocity (m/s) after the last step; `None` in MPM when
/// no material is left around the point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MonitorValues {
    pub ux: f64,
    pub uy: f64,
    /// 3D only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uz: Option<f64>,
    pub vx: f64,
    pub vy: f64,
    /// 3D only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vz: Option<f64>,
}

impl MonitorValues {
    /// From a row's `[ux, uy, vx, vy]` (2D, MPM) or `[ux, uy, uz, vx, vy, vz]` (3D).
    pub fn from_row(v: &[f64]) -> Option<Self> {
        match *v {
            [ux, uy, vx, vy] => Some(Self {
                ux,
                uy,
                uz: None,
                vx,
                vy,
                vz: None,
            }),
            [ux, uy, uz, vx, vy, vz] => Some(Self {
                ux,
                uy,
                uz: Some(uz),
                vx,
                vy,
                vz: Some(vz),
            }),
            _ => None,
        }
    }
}

/// The reported boundary (`output.reaction`): its force and settlement as in the
/// `reaction_force` / `footing_displacement` columns (FEM: along the boundary's motion when
/// it moves along one axis, downward otherwise, `docs/scenes.md` 'Outputs'; MPM:
/// `−reaction_force_y` and `−v_y t`, downward positive).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReportedReaction {
    pub boundary: String,
    pub force: f64,
    pub settlement: f64,
}

/// The plateau of the reported reaction (`output::plateau`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Limit {
    /// Mean force over the plateau (N/m, in the reported reaction's direction).
    pub force: f64,
    /// Settlement where the plateau starts (m), and its step.
    pub settlement: f64,
    pub step: usize,
    pub criterion: String,
    pub tolerance: f64,
    pub span: f64,
    pub min_points: usize,
}

impl Limit {
    pub fn new(force: f64, settlement: f64, step: usize, c: &PlateauCriterion) -> Self {
        Self {
            force,
            settlement,
            step,
            criterion: c.describe(),
            tolerance: c.tolerance,
            span: c.span,
            min_points: c.min_points,
        }
    }
}

/// The factor of safety of a `[stability]` run (`docs/stability.md`): `value` is the
/// middle of `bracket = [largest stable F, smallest failing F]` once its relative width is
/// within `tolerance`; `null` otherwise, `status` saying why.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FactorOfSafety {
    pub value: Option<f64>,
    /// How the search ended (`analysis::stability::SearchStatus`): `found` (with a
    /// `value`), `no_mechanism` (every trial came to rest up to the search's upper end,
    /// `bracket[0]`), `no_stable_factor` (every trial failed down to its lower end,
    /// `bracket[1]`), `unbracketed`, `max_trials` or `interrupted`.
    pub status: String,
    pub bracket: [Option<f64>; 2],
    pub within_tolerance: bool,
    pub tolerance: f64,
    /// `strength_reduction` or `gravity_increase`.
    pub method: String,
    /// Strength reduction's dilatancy rule.
    pub dilatancy: Option<String>,
    /// The failure criterion in words.
    pub criterion: String,
    /// Trials run.
    pub trials: usize,
    /// The trials' Newton tolerance (`[stability] newton_tolerance`); absent from the
    /// summaries of versions before it.
    #[serde(default)]
    pub newton_tolerance: Option<f64>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub status: RunStatus,
    /// The error that stopped the run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Steps completed, of `steps_requested`, and the time reached (s).
    pub steps: usize,
    pub steps_requested: usize,
    pub time: f64,
    pub boundaries: BTreeMap<String, BoundaryReaction>,
    pub monitors: BTreeMap<String, Option<MonitorValues>>,
    pub reaction: Option<ReportedReaction>,
    pub limit: Option<Limit>,
    /// The unit of every force above: `N/m` (plane strain, per metre of thickness) or `N`
    /// (axisymmetric, the whole circumference).
    #[serde(default = "per_metre")]
    pub force_unit: String,
    /// Only for a `[stability]` run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub factor_of_safety: Option<FactorOfSafety>,
    /// Only when `status` is `collapsed`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collapse: Option<CollapseTime>,
    /// What the run warned of (e.g. plastic flow on locking P1 triangles).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// One entry per stage a staged run finished (`[[stage]]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stages: Vec<super::StageSummary>,
}

fn per_metre() -> String {
    "N/m".to_string()
}

impl Summary {
    pub fn write(&self, path: &Path) -> Result<(), OutputError> {
        let text = serde_json::to_string_pretty(self).map_err(|e| OutputError::Invalid {
            field: "summary",
            message: e.to_string(),
        })?;
        super::atomic::write(path, text + "\n")
    }

    /// A summary written by [`Summary::write`].
    pub fn read(path: &Path) -> Result<Self, OutputError> {
        let text = std::fs::read_to_string(path).map_err(|e| OutputError::io(path, e))?;
        serde_json::from_str(&text).map_err(|e| OutputError::invalid("summary", e.to_string()))
    }

    /// The summary in words: how the run ended, the reported reaction and its limit.
    pub fn sentence(&self) -> String {
        let status = match self.status {
            RunStatus::Finished => "finished",
            RunStatus::NotConverged => "stopped (a step did not converge)",
            RunStatus::Failed => "stopped (failed)",
            RunStatus::Collapsed => "stopped: the body COLLAPSED",
            RunStatus::Interrupted => "interrupted (SIGINT/SIGTERM)",
        };
        let mut s = format!(
            "run {status} after {} of {} steps, t = {:.6e} s",
            self.steps, self.steps_requested, self.time
        );
        if let Some(c) = &self.collapse {
            s += &format!(
                " (collapse found at step {}, t = {:.6e} s: the loads exceed what the body \
                 can carry)",
                c.step, c.time
            );
        }
        let unit = &self.force_unit;
        if let Some(r) = &self.reaction {
            s += &format!(
                "; `{}` pushes with {:.4e} {unit} at {:.4e} m settlement",
                r.boundary, r.force, r.settlement
            );
            s += &match &self.limit {
                Some(l) => format!(
                    "; limit load {:.4e} {unit}, plateau from {:.4e} m (step {})",
                    l.force, l.settlement, l.step
                ),
                None => "; no plateau of the force (no limit load)".to_string(),
            };
        }
        for (name, b) in &self.boundaries {
            s += &format!(
                "; {name}: final {} {unit}, peak {} {unit}",
                components(&b.last),
                components(&b.peak)
            );
        }
        for (name, m) in &self.monitors {
            s += &match m {
                Some(m) => {
                    let u: Vec<f64> = [m.ux, m.uy].into_iter().chain(m.uz).collect();
                    format!("; {name}: u = {} m", components(&u))
                }
                None => format!("; {name}: no material around the point"),
            };
        }
        if let Some(f) = &self.factor_of_safety {
            s += &f.sentence();
        }
        for stage in &self.stages {
            s += &format!(
                "; stage \"{}\" (steps {}–{}, {} elements)",
                stage.name, stage.first_step, stage.last_step, stage.elements
            );
            if let Some(f) = &stage.factor_of_safety {
                s += &f.sentence().replacen("; ", ": ", 1);
            }
        }
        s
    }
}

/// `(a, b)` or `(a, b, c)`: every component of a 2D or 3D vector.
fn components(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|c| format!("{c:.4e}")).collect();
    format!("({})", parts.join(", "))
}

impl FactorOfSafety {
    /// `; factor of safety 1.3950 in [1.3906, 1.3994] (strength_reduction, 9 trials)`.
    fn sentence(&self) -> String {
        let end = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.4}"));
        let [lo, hi] = self.bracket;
        match (self.value, self.status.as_str()) {
            (Some(v), _) => format!(
                "; factor of safety {v:.4} in [{}, {}] ({}, {} trials)",
                end(lo),
                end(hi),
                self.method,
                self.trials
            ),
            (None, "no_mechanism") => format!(
                "; NO FAILURE up to F = {} (the search's end): every trial came to rest, \
                 no mechanism and no factor of safety ({}, {} trials)",
                end(lo),
                self.method,
                self.trials
            ),
            (None, "no_stable_factor") => format!(
                "; FAILS at every factor down to F = {} (the search's end): no trial came \
                 to rest, no factor of safety ({}, {} trials)",
                end(hi),
                self.method,
                self.trials
            ),
            (None, _) => format!(
                "; no factor of safety within the tolerance: bracket [{}, {}] ({}, {} trials)",
                end(lo),
                end(hi),
                self.method,
                self.trials
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn summary(force: Vec<f64>, monitor: MonitorValues) -> Summary {
        Summary {
            status: RunStatus::Finished,
            error: None,
            steps: 1,
            steps_requested: 1,
            time: 1.0,
            boundaries: BTreeMap::from([(
                "base".to_string(),
                BoundaryReaction {
                    last: force.clone(),
                    peak: force,
                    peak_step: 1,
                },
            )]),
            monitors: BTreeMap::from([("crest".to_string(), Some(monitor))]),
            reaction: None,
            limit: None,
            force_unit: "N".into(),
            factor_of_safety: None,
            collapse: None,
            warnings: Vec::new(),
            stages: Vec::new(),
        }
    }

    /// The last log line names every component a 3D run wrote (it named 2 of 3), and a 2D
    /// line is the one it always was.
    #[test]
    fn the_sentence_names_every_component_in_2d_and_3d() {
        let m3 = MonitorValues {
            ux: 1.0,
            uy: 2.0,
            uz: Some(3.0),
            vx: 0.0,
            vy: 0.0,
            vz: Some(0.0),
        };
        let s = summary(vec![10.0, 20.0, 30.0], m3).sentence();
        assert!(
            s.contains("base: final (1.0000e1, 2.0000e1, 3.0000e1) N, peak (1.0000e1, 2.0000e1, 3.0000e1) N"),
            "{s}"
        );
        assert!(
            s.contains("crest: u = (1.0000e0, 2.0000e0, 3.0000e0) m"),
            "{s}"
        );
        let m2 = MonitorValues {
            uz: None,
            vz: None,
            ..m3
        };
        let s = summary(vec![10.0, 20.0], m2).sentence();
        assert!(
            s.contains("base: final (1.0000e1, 2.0000e1) N, peak (1.0000e1, 2.0000e1) N; crest: u = (1.0000e0, 2.0000e0) m"),
            "{s}"
        );
    }
}
