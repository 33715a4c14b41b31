//! What an MPM run reports besides the solver: the named walls' and boxes' reactions
//! (`StepReport::group_forces`, each component owned by the last condition prescribing
//! it) and the monitors' grid-interpolated displacement and velocity
//! (`talus_mpm::grid_value_at`), appended to `history.csv`; `summary.json` at the end.
use talus_mpm::{grid_value_at, Dimension, Mandel, Particles};

use crate::output::Results;
use crate::scene::{SceneError, SceneVector};

use crate::model::mpm::{MpmDocument, MpmModel};
use talus_mpm::{GroupForces, MpmStepReport};

pub struct MpmResults<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    /// Index in `StepReport::group_forces` of each named wall or box.
    groups: Vec<usize>,
    points: Vec<<Mandel<D> as Dimension>::Point>,
    /// Particle positions at t = 0: the displacement is `x_p − X_p`.
    initial_position: Vec<<Mandel<D> as Dimension>::Point>,
    pub results: Results,
}

impl<const D: usize, const N: usize> MpmResults<D>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    /// The named walls and boxes (`NAME_fx, NAME_fy`, in 3D also `NAME_fz`) and monitors.
    pub fn new(
        scene: &MpmDocument<N>,
        model: &MpmModel<D>,
        base: &str,
    ) -> Result<Self, SceneError> {
        let spec = &scene.spec;
        let mut named = Vec::new();
        let mut groups = Vec::new();
        for (k, w) in spec.wall.iter().enumerate() {
            if let Some(name) = &w.name {
                named.push((format!("wall[{k}].name"), name.clone()));
                groups.push(k);
            }
        }
        for (k, p) in spec.prescribed.iter().enumerate() {
            if let Some(name) = &p.name {
                named.push((format!("prescribed[{k}].name"), name.clone()));
                groups.push(spec.wall.len() + k);
            }
        }
        let mut monitors = Vec::new();
        let mut points = Vec::new();
        let grid = model.mpm.grid();
        let p = &model.particles;
        for (k, m) in spec.monitor.iter().enumerate() {
            let field = format!("monitor[{k}].point");
            match grid_value_at(grid, p, &p.position, m.point) {
                Ok(Some(_)) => {}
                Ok(None) => {
                    return Err(scene.error(
                        &field,
                        format!("{:?} m has no material around it at t = 0", m.point),
                    ))
                }
                Err(e) => return Err(scene.error(&field, e.to_string())),
            }
            monitors.push((format!("monitor[{k}].name"), m.name.clone()));
            points.push(m.point);
        }
        let mut results =
            Results::with_components(base, &named, &monitors, spec.output.reaction.clone(), N)
                .map_err(|e| scene.error(&e.field, e.message))?;
        // N/m in plane strain, N in 3D.
        results.set_force_unit(spec.analysis.geometry.force_unit());
        // Ramps faster than the step are sampled at the step ends only: said, not silent.
        let ramps = crate::scene::check::mpm_ramps(spec);
        let end = spec.time.step * spec.time.steps as f64;
        for w in crate::scene::check::fast_ramps(&ramps, spec.time.step, end) {
            results.warn(w);
        }
        Ok(Self {
            groups,
            points,
            initial_position: p.position.clone(),
            results,
        })
    }

    /// Records step `step` (`report`: none at step 0) at `time`; `reported`: the
    /// reported box's `(settlement, force)`.
    pub fn record(
        &mut self,
        model: &MpmModel<D>,
        particles: &Particles<D>,
        step: usize,
        time: f64,
        report: Option<&MpmStepReport<D>>,
        reported: Option<(f64, f64)>,
    ) -> String {
        let forces: Vec<[f64; N]> = self
            .groups
            .iter()
            .map(|&g| {
                report
                    .and_then(|r| r.group_forces().get(g).copied())
                    .unwrap_or([0.0; N])
            })
            .collect();
        if self.points.is_empty() {
            return self
                .results
                .record(step, time, &forces, &[None::<[f64; N]>; 0], reported);
        }
        let displacement: Vec<[f64; N]> = particles
            .position
            .iter()
            .zip(&self.initial_position)
            .map(|(x, x0)| std::array::from_fn(|a| x[a] - x0[a]))
            .collect();
        let grid = model.mpm.grid();
        // `[ux, uy, vx, vy]`, in 3D `[ux, uy, uz, vx, vy, vz]`.
        let monitors: Vec<Option<Vec<f64>>> = self
            .points
            .iter()
            .map(|&point| {
                let u = grid_value_at(grid, particles, &displacement, point).ok()??;
                let v = grid_value_at(grid, particles, &particles.velocity, point).ok()??;
                Some(u.into_iter().chain(v).collect())
            })
            .collect();
        self.results
            .record(step, time, &forces, &monitors, reported)
    }
}
