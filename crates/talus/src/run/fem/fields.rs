//! The element fields of a FEM state in a VTU file (`docs/scenes.md`, 'Outputs'), and
//! the last two states a run kept for the step's plastic strain increment.
use std::path::Path;

use nalgebra::SVector;
use talus_fem::{Dimension, Dof, ElementMesh, Mandel};

use crate::model::fem::{element_means, Model, State};
use crate::output::{self, FieldExtras, FieldSnapshot, MeshView, OutputError};
use crate::run::RunError;

/// The stress and displacement after the last two steps of a run, from which a VTU's
/// `plastic_strain_increment` is taken (`Δ` over the step that led to the written state).
/// `N` components per node: 2 in 2D, 3 in 3D.
#[derive(Debug)]
pub(super) struct LastSteps<const N: usize = 2> {
    before: Option<Kept<N>>,
    latest: Option<Kept<N>>,
}

impl<const N: usize> Default for LastSteps<N> {
    fn default() -> Self {
        Self {
            before: None,
            latest: None,
        }
    }
}

#[derive(Debug)]
struct Kept<const N: usize> {
    step: usize,
    sigma: Vec<f64>,
    displacement: Vec<[f64; N]>,
}

impl<const N: usize> Default for Kept<N> {
    fn default() -> Self {
        Self {
            step: 0,
            sigma: Vec::new(),
            displacement: Vec::new(),
        }
    }
}

/// The Mandel stress (flat, Pa) and nodal displacement (m) a step started from.
pub(super) type Start<'a, const N: usize = 2> = (&'a [f64], &'a [[f64; N]]);

impl<const N: usize> LastSteps<N> {
    /// Keeps `state`, the state after `step`, and the one kept before it (reusing the
    /// older one's memory).
    pub(super) fn push<const D: usize>(&mut self, step: usize, state: &State<D>)
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
    {
        let mut k = self.before.take().unwrap_or_default();
        k.step = step;
        k.sigma.clone_from(&state.sigma);
        k.displacement.clone_from(&state.displacement);
        self.before = self.latest.replace(k);
    }

    /// Where the step to `state`, the state after `step`, started: `state` itself at step 0
    /// (no step yet: a zero increment), else the kept state of `step − 1` when `state` is
    /// the last one kept. `None` when that state was not kept or has other sizes.
    pub(super) fn start_of<'a, const D: usize>(
        &'a self,
        step: usize,
        state: &'a State<D>,
    ) -> Option<Start<'a, N>>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
    {
        if step == 0 {
            return Some((&state.sigma, &state.displacement));
        }
        let latest = self.latest.as_ref()?;
        let before = self.before.as_ref()?;
        let sizes = |k: &Kept<N>| (k.sigma.len(), k.displacement.len());
        (latest.step == step
            && before.step + 1 == step
            && sizes(before) == (state.sigma.len(), state.displacement.len()))
            .then_some((&before.sigma, &before.displacement))
    }
}

/// Per-element averages of the Gauss-point stress and plastic strain.
pub(super) fn element_fields<const D: usize>(
    model: &Model<D>,
    state: &State<D>,
) -> (Vec<[f64; D]>, Vec<f64>)
where
    Mandel<D>: Dimension,
{
    let stress = element_means::<D, D>(model, &state.sigma);
    let plastic = element_means::<1, D>(model, &state.plastic_strain);
    (stress, plastic.into_iter().map(|[p]| p).collect())
}

/// Each element's mean of its Gauss points' Mandel values.
fn element_tensor_means<const D: usize>(
    model: &Model<D>,
    point_values: &[SVector<f64, D>],
) -> Vec<[f64; D]>
where
    Mandel<D>: Dimension,
{
    let flat: Vec<f64> = point_values
        .iter()
        .flat_map(|v| v.iter().copied())
        .collect();
    element_means::<D, D>(model, &flat)
}

/// The small strain `B u` at each Gauss point (Mandel `(xx, yy, zz, √2 xy)`, zz the hoop
/// strain `u_r / r` in axisymmetry) of the nodal displacement `u` (m), by the assembly's
/// strain operator.
fn point_strains<const N: usize, const D: usize>(
    model: &Model<D>,
    u: &[[f64; N]],
    field: &'static str,
) -> Result<Vec<SVector<f64, D>>, RunError>
where
    Mandel<D>: Dimension,
{
    let invalid = |message: String| RunError::Output(OutputError::Invalid { field, message });
    let dofs = model.assembly.dofs();
    if u.len() != dofs.n_nodes() {
        return Err(invalid(format!(
            "{} nodal displacements for {} nodes",
            u.len(),
            dofs.n_nodes()
        )));
    }
    let mut free = vec![0.0; dofs.n_free()];
    let mut prescribed = vec![0.0; dofs.n_prescribed()];
    for (node, d) in u.iter().enumerate() {
        for (comp, value) in d.iter().enumerate() {
            match dofs.dof(node, comp) {
                Some(Dof::Free(i)) => free[i] = *value,
                Some(Dof::Prescribed(j)) => prescribed[j] = *value,
                None => {}
            }
        }
    }
    model
        .assembly
        .strain(&free, &prescribed)
        .map_err(|e| invalid(e.to_string()))
}

/// Per element, the mean over its Gauss points of the total small strain `B u`.
fn element_strains<const N: usize, const D: usize>(
    model: &Model<D>,
    state: &State<D>,
) -> Result<Vec<[f64; D]>, RunError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
{
    Ok(element_tensor_means(
        model,
        &point_strains(model, &state.displacement, "strain")?,
    ))
}

/// Per element, the mean over its Gauss points of the plastic strain increment of the step
/// from `start` to `state`: `Δεᵖ = B Δu − S Δσ`, `S` the point's elastic compliance. It is
/// what the step's solve gave, `−z_p / V_p` (eq. 15: `S Δσ = B Δu − V Δεᵖ` per point).
fn element_plastic_increments<const N: usize, const D: usize>(
    model: &Model<D>,
    state: &State<D>,
    (sigma0, u0): Start<N>,
) -> Result<Vec<[f64; D]>, RunError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
{
    let field = "plastic_strain_increment";
    let du: Vec<[f64; N]> = state
        .displacement
        .iter()
        .zip(u0)
        .map(|(u, u0)| std::array::from_fn(|k| u[k] - u0[k]))
        .collect();
    let mut increments = point_strains(model, &du, field)?;
    if state.sigma.len() != D * increments.len() || sigma0.len() != state.sigma.len() {
        return Err(RunError::Output(OutputError::invalid(
            field,
            format!(
                "{} and {} stresses for {} Gauss points × {D}",
                sigma0.len(),
                state.sigma.len(),
                increments.len()
            ),
        )));
    }
    for (p, d) in increments.iter_mut().enumerate() {
        let r = D * p..D * p + D;
        let ds = SVector::<f64, D>::from_column_slice(&state.sigma[r.clone()])
            - SVector::<f64, D>::from_column_slice(&sigma0[r]);
        *d -= model.compliance_at(p) * ds;
    }
    Ok(element_tensor_means(model, &increments))
}

/// The VTU of `state` at `path` (`piece`: of those elements only, returning its XML); with
/// `start`, the state its step started from, it holds the step's
/// `plastic_strain_increment`.
pub(super) fn write_snapshot<const N: usize, const D: usize>(
    model: &Model<D>,
    state: &State<D>,
    start: Option<Start<N>>,
    path: &Path,
    piece: Option<std::ops::Range<usize>>,
) -> Result<Option<String>, RunError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
{
    let (stress, plastic) = element_fields(model, state);
    let strain = element_strains(model, state)?;
    let increment = start
        .map(|s| element_plastic_increments(model, state, s))
        .transpose()?;
    let material = model.element_materials();
    // The pore pressure at the state's time, per element (its points' mean).
    let pore_pressure = model.pore_pressure.iter().any(|p| *p != 0.0).then(|| {
        let f = model
            .pore_pressure_ramp
            .as_ref()
            .map_or(1.0, |r| r.at(state.time));
        let at_points: Vec<f64> = model.pore_pressure.iter().map(|p| f * p).collect();
        (element_means::<1, D>(model, &at_points).into_iter())
            .map(|[p]| p)
            .collect::<Vec<f64>>()
    });
    let velocity = model
        .assembly
        .dofs()
        .nodal_vectors::<N>(&state.velocity_free, &state.velocity_prescribed)
        .map_err(|e| {
            RunError::Output(OutputError::Invalid {
                field: "velocity",
                message: e.to_string(),
            })
        })?;
    let snapshot = FieldSnapshot {
        mesh: MeshView {
            nodes: model.mesh.node_positions(),
            elements: model.mesh.elements(),
        },
        time: state.time,
        displacement: &state.displacement,
        velocity: &velocity,
        stress: &stress,
        plastic_strain: &plastic,
        material: Some(&material),
        pore_pressure: pore_pressure.as_deref(),
    };
    let extras = FieldExtras {
        strain: Some(&strain),
        plastic_strain_increment: increment.as_deref(),
    };
    Ok(match piece {
        None => {
            output::write_vtu_with(path, &snapshot, &extras)?;
            None
        }
        Some(cells) => Some(output::write_vtu_piece(path, &snapshot, &extras, cells)?),
    })
}

/// The VTUs of a FEM run, 2D or 3D: `vtu/step_NNNNN.vtu` at step 0, every `vtu_every`
/// steps, the last step and the state a run stopped at, each listed in `solution.pvd` as
/// it is written (ParaView opens a killed run), with the last two states kept for the
/// plastic strain increment. Nothing when the run writes no fields.
#[derive(Debug)]
pub(super) struct Vtus<'a, const N: usize = 2> {
    out: &'a Path,
    write_fields: bool,
    /// (time, file) of every VTU written, from step 0 (saved in a checkpoint).
    pub(super) pvd: Vec<(f64, String)>,
    last_steps: LastSteps<N>,
}

impl<'a, const N: usize> Vtus<'a, N> {
    /// Going on from the VTUs `pvd` lists (a stage carries them to the next).
    pub(super) fn new(out: &'a Path, write_fields: bool, pvd: Vec<(f64, String)>) -> Self {
        Self {
            out,
            write_fields,
            pvd,
            last_steps: LastSteps::default(),
        }
    }

    pub(super) fn writes(&self) -> bool {
        self.write_fields
    }

    /// Keeps `state`, the state after `step` (a resumed or carried start, or a step's
    /// end), for the next VTU's increment.
    pub(super) fn keep<const D: usize>(&mut self, step: usize, state: &State<D>)
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
    {
        if self.write_fields {
            self.last_steps.push(step, state);
        }
    }

    /// After `step`: keeps `state`, and writes it at step 0, every `every` steps (0:
    /// never) and at `last`.
    pub(super) fn after_step<const D: usize>(
        &mut self,
        model: &Model<D>,
        step: usize,
        state: &State<D>,
        (every, last): (usize, usize),
    ) -> Result<(), RunError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
    {
        self.keep(step, state);
        if self.write_fields
            && (step == 0 || (every > 0 && step.is_multiple_of(every)) || step == last)
        {
            self.write(model, step, state)?;
        }
        Ok(())
    }

    /// A run that stopped early (collapse, failure, interruption) ends with its last state.
    pub(super) fn finish<const D: usize>(
        &mut self,
        model: &Model<D>,
        step: usize,
        state: &State<D>,
    ) -> Result<(), RunError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
    {
        if self.write_fields && self.pvd.last().map(|(t, _)| *t) != Some(state.time) {
            self.write(model, step, state)?;
        }
        Ok(())
    }

    /// A checkpoint's list: the VTUs of later steps, and the one an interruption wrote of
    /// its last state, are removed.
    pub(super) fn restore(&mut self, pvd: Vec<(f64, String)>) -> Result<(), RunError> {
        self.pvd = pvd;
        crate::run::pieces::drop_unlisted(self.out, &self.pvd)?;
        if self.write_fields && !self.pvd.is_empty() {
            output::write_pvd(&self.out.join("solution.pvd"), &self.pvd)?;
        }
        Ok(())
    }

    /// `vtu/step_NNNNN.vtu` of `state`, listed in the collection.
    fn write<const D: usize>(
        &mut self,
        model: &Model<D>,
        step: usize,
        state: &State<D>,
    ) -> Result<(), RunError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
    {
        let start = self.last_steps.start_of(step, state);
        let n = model.mesh.elements().len();
        let file = crate::run::pieces::write_snapshot(self.out, step, n, |path, piece| {
            write_snapshot(model, state, start, path, piece)
        })?;
        self.pvd.push((state.time, file));
        output::write_pvd(&self.out.join("solution.pvd"), &self.pvd)?;
        Ok(())
    }
}
