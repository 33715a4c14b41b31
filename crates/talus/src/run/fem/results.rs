//! What a run reports besides the solver: the named boundaries' reactions
//! and the monitors, appended to `history.csv`, then the inertial share of the reported
//! reaction, and `summary.json` at the end (`output::Results`, `docs/scenes.md`,
//! 'Results'); the run loop (`run::steps`) writes it.
use std::ops::{Deref, DerefMut};

use talus_fem::{Dimension, Mandel, Model, State};

use crate::model::fem::{
    prescribed_forces_at_rest, NodeMonitors, ReactionForce, ReactionGroups, StepRecord,
};
use crate::output::Results;
use crate::scene::{AnalysisKind, SceneError, SceneOf, SceneVector};

/// The `history.csv` column after the named boundaries and monitors, in a scene that
/// reports a reaction (`[output] reaction`): the share of that reaction that is inertia.
pub const INERTIAL_SHARE: &str = "inertial_share";

/// A quasi-static run warns (once) when inertia carries more than this share of the
/// reported reaction after its first step (`docs/scenes.md`, 'Analysis').
pub const INERTIAL_SHARE_WARNING: f64 = 1e-2;

pub struct FemResults {
    groups: ReactionGroups,
    monitors: NodeMonitors,
    pub results: FemColumns,
    quasi_static: bool,
    /// The inertia ratio of a quasi-static scene, for the warning.
    inertia_ratio: f64,
    warned: bool,
}

/// The results' columns (`output::Results`), then [`INERTIAL_SHARE`] when the scene
/// reports a reaction: everything else is `Results`'.
pub struct FemColumns {
    results: Results,
    share: bool,
}

impl FemColumns {
    /// `,NAME_fx,...,NAME_vy[,inertial_share]`: what follows the base header.
    pub fn header(&self) -> String {
        let share = if self.share {
            format!(",{INERTIAL_SHARE}")
        } else {
            String::new()
        };
        format!("{}{share}", self.results.header())
    }

    /// `row`, then the share's cell (`NaN` when the reaction is 0: a number for every
    /// reader of history.csv, the Python package's among them).
    fn with_share(&self, row: String, share: Option<f64>) -> String {
        match (self.share, share) {
            (false, _) => row,
            (true, Some(v)) => format!("{row},{v:.6e}"),
            (true, None) => format!("{row},NaN"),
        }
    }
}

impl Deref for FemColumns {
    type Target = Results;
    fn deref(&self) -> &Results {
        &self.results
    }
}

impl DerefMut for FemColumns {
    fn deref_mut(&mut self) -> &mut Results {
        &mut self.results
    }
}

impl FemResults {
    /// The columns of `scene`'s named boundaries and monitors after `base` (history.csv's
    /// other columns), then [`INERTIAL_SHARE`] if the scene reports a reaction. Warns of
    /// the model's doubtful choices and of ramps faster than the step
    /// (`scene::check::fast_ramps`).
    pub fn new<const N: usize, const D: usize>(
        scene: &SceneOf<N>,
        model: &Model<D>,
        base: &str,
    ) -> Result<Self, SceneError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
        [f64; N]: SceneVector,
    {
        let names: Vec<Option<String>> =
            scene.spec.boundary.iter().map(|b| b.name.clone()).collect();
        let groups = ReactionGroups::of_model(model, &names);
        let monitors = NodeMonitors::new(scene, model)?;
        let share = scene.spec.output.reaction.is_some();
        let mut results = Results::with_components(
            &if share {
                format!("{base},{INERTIAL_SHARE}")
            } else {
                base.to_string()
            },
            &groups.names,
            &monitors.names,
            scene.spec.output.reaction.clone(),
            N,
        )
        .map_err(|e| scene.error(&e.field, e.message))?;
        results.set_force_unit(scene.spec.analysis.geometry.force_unit());
        for w in crate::model::fem::warnings(scene, model) {
            results.warn(w);
        }
        let spec = &scene.spec;
        let end = spec.time.step * spec.total_steps() as f64;
        let ramps = crate::scene::check::ramps(spec);
        for w in crate::scene::check::fast_ramps(&ramps, spec.time.step, end) {
            results.warn(w);
        }
        let quasi_static = spec.analysis.kind == AnalysisKind::QuasiStatic;
        Ok(Self {
            groups,
            monitors,
            results: FemColumns { results, share },
            quasi_static,
            inertia_ratio: spec
                .analysis
                .inertia_ratio
                .unwrap_or(crate::model::fem::DEFAULT_INERTIA_RATIO),
            warned: false,
        })
    }

    /// The same results on the model of a staged run's next stage: its named boundaries'
    /// dofs and its monitors' nodes (the mesh may have changed), what was recorded kept.
    pub fn rebind<const N: usize, const D: usize>(
        self,
        scene: &SceneOf<N>,
        model: &Model<D>,
    ) -> Result<Self, SceneError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
        [f64; N]: SceneVector,
    {
        let names: Vec<Option<String>> =
            scene.spec.boundary.iter().map(|b| b.name.clone()).collect();
        Ok(Self {
            groups: ReactionGroups::of_model(model, &names),
            monitors: NodeMonitors::new(scene, model)?,
            ..self
        })
    }

    /// Step 0: the initial state at rest (no inertia: `inertial_share` 0, or `NaN`
    /// without a reported reaction).
    pub fn initial<const N: usize, const D: usize>(
        &mut self,
        model: &Model<D>,
        state: &State<D>,
        reaction: f64,
    ) -> String
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
    {
        let forces = (self.groups).sums_of::<N>(&prescribed_forces_at_rest(model, state));
        let monitors = self.monitors.values(model, state);
        let row = self
            .results
            .record(0, state.time, &forces, &monitors, Some((0.0, reaction)));
        let share = (!model.reaction_dofs.is_empty() && reaction != 0.0).then_some(0.0);
        self.results.with_share(row, share)
    }

    /// After `step`, with the footing displacement of the reported boundary.
    pub fn step<const N: usize, const D: usize>(
        &mut self,
        model: &Model<D>,
        state: &State<D>,
        step: usize,
        record: &StepRecord,
        displacement: f64,
    ) -> String
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
    {
        let forces = record
            .stats
            .as_ref()
            .map(|s| self.groups.sums_of::<N>(&s.prescribed_forces))
            .unwrap_or_default();
        let monitors = self.monitors.values(model, state);
        let row = self.results.record(
            step,
            state.time,
            &forces,
            &monitors,
            Some((displacement, record.reaction_force())),
        );
        let share = inertial_share(model, state, record);
        if let (Some(s), true, false, true) = (share, self.quasi_static, self.warned, step > 1) {
            if s > INERTIAL_SHARE_WARNING {
                self.warned = true;
                self.results.warn(format!(
                    "inertia carries {:.1}% of the reported reaction at step {step} (t = \
                     {:.6e} s; history.csv's `{INERTIAL_SHARE}`): a quasi-static run's answer \
                     should not depend on it; lower analysis.inertia_ratio (now {:e})",
                    100.0 * s,
                    state.time,
                    self.inertia_ratio
                ));
            }
        }
        self.results.with_share(row, share)
    }
}

/// The share of the reported reaction `R` (`reaction_force`) that is inertia after a
/// step, `|R_M| / |R|`; `None` without a reported reaction (or when it is 0).
///
/// Eq. 15 on every dof, summed with weights `w` that are 1 on the reported boundary's
/// dofs along its reported axis (`Model::reaction_direction`: vertical for a footing) and
/// 0 on every other prescribed dof, splits `R` exactly (the free dofs
/// are in balance, so `Σ_j w_j (M a + Bᵀσ − f)_j` is the reported boundary's force):
/// `R = −(w·M a + (B w)·σ − w·f)`, and its inertial part is `R_M = −w·M a`. The weights:
/// - the reported boundary drives the body (it moves along its axis at one speed `v_D`,
///   every other prescribed dof is at rest, as a footing): `w = v / v_D`, the mechanism it
///   drives, so that `R_M v_D` is the rate of change of the kinetic energy;
/// - else, when the reported boundary holds every prescribed dof along its axis (a base,
///   a line of symmetry): `w` a rigid translation along the axis, so that `R_M` is the
///   body's whole `Σ M a` along it;
/// - else the reported dofs' own `M a` (`w` 1 there, 0 elsewhere): a lower bound.
///
/// `M a` is `f − Bᵀσ` on the free dofs (eq. 15 at the step's end) and the step's boundary
/// force minus the one at rest on the prescribed dofs.
pub fn inertial_share<const D: usize>(
    model: &Model<D>,
    state: &State<D>,
    record: &StepRecord,
) -> Option<f64>
where
    Mandel<D>: Dimension,
{
    let stats = record.stats.as_ref()?;
    let reaction = stats.reaction_force;
    let axis = model.reaction_direction.0;
    let reported: Vec<usize> = model
        .reaction_dofs
        .iter()
        .filter(|(_, comp)| *comp == axis)
        .map(|&(j, _)| j)
        .collect();
    if reported.is_empty() || reaction == 0.0 || !reaction.is_finite() {
        return None;
    }
    let asm = &model.assembly;
    let dofs = asm.dofs();
    // Bᵀσ and f(t) once, on the free and the prescribed dofs.
    let (internal_free, internal_prescribed) = asm.internal_force(&state.sigma).ok()?;
    let loads = model.loads_at(state.time);
    // The boundary force at rest, `Bᵀσ − f` (`prescribed_forces_at_rest`).
    let ma_prescribed: Vec<f64> = (stats.prescribed_forces.iter())
        .zip(internal_prescribed.iter().zip(&loads.force_prescribed))
        .map(|(p, (i, f))| p - (i - f))
        .collect();
    let ma_free = || {
        (loads.force_free.iter())
            .zip(&internal_free)
            .map(|(f, i)| f - i)
            .collect::<Vec<f64>>()
    };
    let v = &state.velocity_prescribed;
    let v_d = v[reported[0]];
    let one_speed = v_d != 0.0
        && reported
            .iter()
            .all(|&j| (v[j] - v_d).abs() <= 1e-12 * v_d.abs());
    let others_still = (0..v.len()).all(|j| v[j] == 0.0 || reported.contains(&j));
    let axis_held_by_reported = (dofs.prescribed_dofs().iter().enumerate())
        .all(|(j, &(_, comp))| comp != axis || reported.contains(&j));
    let inertia = if one_speed && others_still {
        let free: f64 = (ma_free().iter().zip(&state.velocity_free))
            .map(|(m, v)| m * v)
            .sum();
        let prescribed: f64 = ma_prescribed.iter().zip(v).map(|(m, v)| m * v).sum();
        (free + prescribed) / v_d
    } else if axis_held_by_reported {
        let ma = ma_free();
        let free: f64 = (0..dofs.n_nodes())
            .filter_map(|n| dofs.free(n, axis))
            .map(|j| ma[j])
            .sum();
        free + reported.iter().map(|&j| ma_prescribed[j]).sum::<f64>()
    } else {
        reported.iter().map(|&j| ma_prescribed[j]).sum()
    };
    let r_m = -inertia * asm.geometry().whole_body_factor();
    Some((r_m / reaction).abs())
}
