//! The results a user reads besides the solver's: one reaction per named boundary
//! (`NAME_fx, NAME_fy`, N/m; 3D `NAME_fz` too, N) and one displacement and velocity per
//! monitor (`NAME_ux, NAME_uy, NAME_vx, NAME_vy`; 3D `NAME_ux, NAME_uy, NAME_uz, NAME_vx,
//! NAME_vy, NAME_vz`) appended to each `history.csv` row, tracked over the run for
//! `summary.json` (FEM and MPM alike).
use std::collections::BTreeMap;

use super::plateau::{plateau, PlateauCriterion};
use super::stage_summary::StageSummary;
use super::summary::{
    BoundaryReaction, Limit, MonitorValues, ReportedReaction, RunStatus, Summary,
};

/// Columns, and what the run reached so far.
#[derive(Debug, Clone)]
pub struct Results {
    boundaries: Vec<String>,
    monitors: Vec<String>,
    reported: Option<String>,
    /// Force components per boundary: 2 (`fx, fy`) in 2D and MPM, 3 (`fx, fy, fz`) in 3D;
    /// a monitor's displacement and velocity have as many.
    components: usize,
    last: Vec<Vec<f64>>,
    peak: Vec<(Vec<f64>, usize)>,
    monitor_values: Vec<Option<Vec<f64>>>,
    /// `(settlement, force)` of the reported boundary at every recorded step.
    curve: Vec<(f64, f64)>,
    steps: usize,
    time: f64,
    force_unit: &'static str,
    /// What the run should say besides its numbers (`Summary::warnings`).
    warnings: Vec<String>,
    /// The stages finished so far (`Summary::stages`).
    stages: Vec<StageSummary>,
}

/// What [`Results`] recorded so far (its columns come from the scene): saved in a
/// checkpoint (`crate::run::checkpoint`).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ResultsProgress {
    last: Vec<Vec<f64>>,
    peak: Vec<(Vec<f64>, usize)>,
    monitor_values: Vec<Option<Vec<f64>>>,
    curve: Vec<(f64, f64)>,
    steps: usize,
    time: f64,
    #[serde(default)]
    stages: Vec<StageSummary>,
}

/// A name that cannot head columns: the scene field that gave it and why.
#[derive(Debug, Clone, PartialEq)]
pub struct BadColumn {
    pub field: String,
    pub message: String,
}

impl Results {
    /// `boundaries` and `monitors`: `(scene field, name)` in file order; `base`: the
    /// history.csv columns before them. Every generated column must be new.
    pub fn new(
        base: &str,
        boundaries: &[(String, String)],
        monitors: &[(String, String)],
        reported: Option<String>,
    ) -> Result<Self, BadColumn> {
        Self::with_components(base, boundaries, monitors, reported, 2)
    }

    /// [`Results::new`] with `components` force components per boundary and displacement
    /// and velocity components per monitor (3 in 3D: `NAME_fx, NAME_fy, NAME_fz`,
    /// `NAME_ux, NAME_uy, NAME_uz, NAME_vx, NAME_vy, NAME_vz`).
    pub fn with_components(
        base: &str,
        boundaries: &[(String, String)],
        monitors: &[(String, String)],
        reported: Option<String>,
        components: usize,
    ) -> Result<Self, BadColumn> {
        let components = components.clamp(1, crate::scene::REACTION_COLUMNS.len());
        let mut columns: Vec<(usize, String)> = Vec::new();
        let named = boundaries
            .iter()
            .map(|b| (b, &crate::scene::REACTION_COLUMNS[..components]))
            .chain(
                monitors
                    .iter()
                    .map(|m| (m, crate::scene::monitor_columns(components))),
            );
        let fields: Vec<&String> = boundaries.iter().chain(monitors).map(|(f, _)| f).collect();
        for (k, ((field, name), suffixes)) in named.enumerate() {
            if let Some(why) = crate::scene::bad_name(name) {
                return Err(BadColumn {
                    field: field.clone(),
                    message: format!("`{name}` {why}"),
                });
            }
            columns.extend(suffixes.iter().map(|s| (k, format!("{name}_{s}"))));
        }
        let base: Vec<&str> = base.split(',').collect();
        if let Some((k, column)) = crate::scene::first_duplicate(&base, &columns) {
            return Err(BadColumn {
                field: fields[*k].clone(),
                message: format!(
                    "its history.csv column `{column}` repeats another column (names must be unique)"
                ),
            });
        }
        Ok(Self {
            boundaries: boundaries.iter().map(|b| b.1.clone()).collect(),
            monitors: monitors.iter().map(|m| m.1.clone()).collect(),
            reported,
            components,
            last: vec![vec![0.0; components]; boundaries.len()],
            peak: vec![(vec![0.0; components], 0); boundaries.len()],
            monitor_values: vec![None; monitors.len()],
            curve: Vec::new(),
            steps: 0,
            time: 0.0,
            force_unit: "N/m",
            warnings: Vec::new(),
            stages: Vec::new(),
        })
    }

    /// The unit the summary gives the forces in (`N/m` unless set: axisymmetric runs
    /// report whole-circumference forces in `N`).
    /// Adds a warning, logged now and kept for `summary.json`.
    pub fn warn(&mut self, warning: String) {
        tracing::warn!("{warning}");
        self.warnings.push(warning);
    }

    pub fn set_force_unit(&mut self, unit: &'static str) {
        self.force_unit = unit;
    }

    /// `,NAME_fx,NAME_fy,...,NAME_ux,...`: what follows the base header.
    pub fn header(&self) -> String {
        let b = self.boundaries.iter().flat_map(|n| {
            crate::scene::REACTION_COLUMNS[..self.components]
                .iter()
                .map(move |s| format!(",{n}_{s}"))
        });
        let m = self.monitors.iter().flat_map(|n| {
            (crate::scene::monitor_columns(self.components).iter())
                .map(move |s| format!(",{n}_{s}"))
        });
        b.chain(m).collect()
    }

    /// Records step `step` (0: the initial state) at `time`: each named boundary's force,
    /// each monitor's `[ux, uy, vx, vy]` (3D `[ux, uy, uz, vx, vy, vz]`; `None`: no
    /// material around an MPM point, written as empty cells), the reported boundary's
    /// `(settlement, force)`. Returns what follows the row's base columns.
    pub fn record(
        &mut self,
        step: usize,
        time: f64,
        forces: &[impl AsRef<[f64]>],
        monitors: &[Option<impl AsRef<[f64]>>],
        reported: Option<(f64, f64)>,
    ) -> String {
        let mut row = String::new();
        for (k, f) in forces.iter().enumerate().take(self.boundaries.len()) {
            let f = f.as_ref();
            for c in 0..self.components {
                row += &format!(",{:.10e}", f.get(c).copied().unwrap_or(0.0));
            }
            self.last[k] = f.to_vec();
            if crate::scene::scales::norm(f) > crate::scene::scales::norm(&self.peak[k].0) {
                self.peak[k] = (f.to_vec(), step);
            }
        }
        for (k, m) in monitors.iter().enumerate().take(self.monitors.len()) {
            match m {
                Some(v) => {
                    for x in v.as_ref() {
                        row += &format!(",{x:.10e}");
                    }
                }
                None => row += &",".repeat(2 * self.components),
            }
            self.monitor_values[k] = m.as_ref().map(|v| v.as_ref().to_vec());
        }
        if let Some(point) = reported {
            self.curve.push(point);
        }
        self.steps = step;
        self.time = time;
        row
    }

    /// What was recorded so far, for a checkpoint.
    pub fn progress(&self) -> ResultsProgress {
        ResultsProgress {
            last: self.last.clone(),
            peak: self.peak.clone(),
            monitor_values: self.monitor_values.clone(),
            curve: self.curve.clone(),
            steps: self.steps,
            time: self.time,
            stages: self.stages.clone(),
        }
    }

    /// Continues from `progress`, saved from results with the same columns; an other
    /// number of boundaries or monitors is refused (the checkpoint is not this scene's).
    pub fn restore(&mut self, progress: ResultsProgress) -> Result<(), String> {
        let (b, m) = (self.boundaries.len(), self.monitors.len());
        if progress.last.len() != b || progress.peak.len() != b {
            return Err(format!(
                "{} named boundaries saved, {b} in the scene",
                progress.last.len()
            ));
        }
        if progress.monitor_values.len() != m {
            return Err(format!(
                "{} monitors saved, {m} in the scene",
                progress.monitor_values.len()
            ));
        }
        self.last = progress.last;
        self.peak = progress.peak;
        self.monitor_values = progress.monitor_values;
        self.curve = progress.curve;
        self.steps = progress.steps;
        self.time = progress.time;
        self.stages = progress.stages;
        Ok(())
    }

    /// Records a finished stage (`summary.json`'s `stages`).
    pub fn push_stage(&mut self, stage: StageSummary) {
        self.stages.push(stage);
    }

    /// `(settlement, force)` of the reported boundary at every recorded step.
    pub fn curve(&self) -> &[(f64, f64)] {
        &self.curve
    }

    pub fn summary(
        &self,
        status: RunStatus,
        error: Option<String>,
        steps_requested: usize,
    ) -> Summary {
        let criterion = PlateauCriterion::default();
        let boundaries = self
            .boundaries
            .iter()
            .enumerate()
            .map(|(k, name)| {
                (
                    name.clone(),
                    BoundaryReaction {
                        last: self.last[k].clone(),
                        peak: self.peak[k].0.clone(),
                        peak_step: self.peak[k].1,
                    },
                )
            })
            .collect();
        let monitors = self
            .monitors
            .iter()
            .zip(&self.monitor_values)
            .map(|(name, v)| (name.clone(), v.as_deref().and_then(MonitorValues::from_row)))
            .collect::<BTreeMap<_, _>>();
        let reaction = self.reported.as_ref().and_then(|name| {
            self.curve
                .last()
                .map(|&(settlement, force)| ReportedReaction {
                    boundary: name.clone(),
                    force,
                    settlement,
                })
        });
        // The curve holds one point per recorded step from step 0 on.
        let limit = reaction
            .as_ref()
            .and_then(|_| plateau(&self.curve, &criterion))
            .map(|p| Limit::new(p.force, p.settlement, p.start, &criterion));
        Summary {
            status,
            error,
            steps: self.steps,
            steps_requested,
            time: self.time,
            boundaries,
            monitors,
            reaction,
            limit,
            force_unit: self.force_unit.to_string(),
            factor_of_safety: None,
            collapse: None,
            warnings: self.warnings.clone(),
            stages: self.stages.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn named(field: &str, name: &str) -> (String, String) {
        (field.to_string(), name.to_string())
    }

    #[test]
    fn columns_follow_the_names_and_collisions_are_named() {
        let r = Results::new(
            "step,time",
            &[named("boundary[0].name", "base")],
            &[named("monitor[0].name", "crest")],
            None,
        )
        .unwrap();
        assert_eq!(
            r.header(),
            ",base_fx,base_fy,crest_ux,crest_uy,crest_vx,crest_vy"
        );
        let err = Results::new(
            "step,time",
            &[],
            &[named("monitor[0].name", "a"), named("monitor[1].name", "a")],
            None,
        )
        .unwrap_err();
        assert_eq!(err.field, "monitor[1].name");
        let err = Results::new(
            "step,reaction_force_x",
            &[named("wall[0].name", "reaction_force")],
            &[],
            None,
        );
        assert!(err.is_ok(), "reaction_force_fx is a new column");
        let err =
            Results::new("step,a_ux", &[], &[named("monitor[0].name", "a")], None).unwrap_err();
        assert!(err.message.contains("a_ux"), "{err:?}");
        let err = Results::new("step", &[named("boundary[2].name", "a b")], &[], None).unwrap_err();
        assert_eq!(err.field, "boundary[2].name");
    }

    #[test]
    fn a_3d_monitor_has_six_columns_and_its_summary_z_components() {
        let mut r = Results::with_components(
            "step",
            &[named("boundary[0].name", "base")],
            &[named("monitor[0].name", "crest")],
            None,
            3,
        )
        .unwrap();
        assert_eq!(
            r.header(),
            ",base_fx,base_fy,base_fz,crest_ux,crest_uy,crest_uz,crest_vx,crest_vy,crest_vz"
        );
        let row = r.record(0, 0.0, &[[1.0, 2.0, 3.0]], &[None::<[f64; 6]>], None);
        assert_eq!(row.matches(',').count(), 9, "{row}");
        r.record(
            1,
            0.1,
            &[[1.0, 2.0, 3.0]],
            &[Some([1., 2., 3., 4., 5., 6.])],
            None,
        );
        let m = r.summary(RunStatus::Finished, None, 1).monitors["crest"].unwrap();
        assert_eq!(
            (m.ux, m.uy, m.uz, m.vx, m.vy, m.vz),
            (1., 2., Some(3.), 4., 5., Some(6.))
        );
        let err =
            Results::with_components("step,a_uz", &[], &[named("monitor[0].name", "a")], None, 3)
                .unwrap_err();
        assert!(err.message.contains("a_uz"), "{err:?}");
    }

    #[test]
    fn final_and_peak_by_magnitude() {
        let mut r = Results::new(
            "step",
            &[named("boundary[0].name", "b")],
            &[],
            Some("b".into()),
        )
        .unwrap();
        let none: &[Option<[f64; 4]>] = &[];
        r.record(0, 0.0, &[[0.0, 1.0]], none, Some((0.0, 1.0)));
        r.record(1, 0.1, &[[3.0, -4.0]], none, Some((0.1, 4.0)));
        let row = r.record(2, 0.2, &[[1.0, 2.0]], none, Some((0.2, 2.0)));
        assert_eq!(row, format!(",{:.10e},{:.10e}", 1.0, 2.0));
        let s = r.summary(RunStatus::Finished, None, 2);
        assert_eq!(s.boundaries["b"].last, [1.0, 2.0]);
        assert_eq!(s.boundaries["b"].peak, [3.0, -4.0]);
        assert_eq!(s.boundaries["b"].peak_step, 1);
        assert_eq!(s.reaction.unwrap().force, 2.0);
        assert_eq!((s.steps, s.time), (2, 0.2));
    }
}
