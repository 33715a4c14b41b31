//! Files of an MPM run besides history.csv: particle VTUs and their `.pvd` collection,
//! PNG maps of the plastic strain in the fixed frame of the grid, the reaction plot.
use std::path::Path;

use talus_mpm::{Dimension, Mandel, Particles};

use crate::output::{self, OutputError, ParticleExtras, ParticlePlot, ParticleSnapshot};
use crate::run::{io_err, RunError};

use crate::model::mpm::MpmModel;

/// Where the fields go and which steps write them.
pub struct FieldWriter<'a> {
    pub out: &'a Path,
    pub title: &'a str,
    pub vtu_every: usize,
    pub snapshot_every: usize,
    pub last_step: usize,
    /// `(time, file relative to out)` of every VTU written, for the `.pvd`.
    pub pvd: Vec<(f64, String)>,
}

/// Step 0, every `every` steps, and the last.
fn due(step: usize, every: usize, last: usize) -> bool {
    step == 0 || step == last || (every > 0 && step.is_multiple_of(every))
}

impl FieldWriter<'_> {
    /// The VTU and PNG due after `step` (state at `time`).
    pub fn after_step<const D: usize, const N: usize>(
        &mut self,
        model: &MpmModel<D>,
        particles: &Particles<D>,
        step: usize,
        time: f64,
    ) -> Result<(), RunError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
    {
        if due(step, self.vtu_every, self.last_step) {
            self.write_vtu(model, particles, step, time)?;
        }
        // Pictures are rank 0's alone; every rank writes its piece of the VTU.
        let pictures = crate::ranks::ranks().is_root();
        if pictures && due(step, self.snapshot_every, self.last_step) {
            let dir = self.out.join("snapshots");
            std::fs::create_dir_all(&dir).map_err(io_err(&dir))?;
            self.png(
                model,
                particles,
                &dir.join(format!("step_{step:05}.png")),
                time,
            )?;
        }
        Ok(())
    }

    /// `vtu/step_NNNNN.vtu` of the particles at `time` (under `mpirun`, this rank's piece,
    /// `crate::run::pieces`), listed in the collection.
    fn write_vtu<const D: usize, const N: usize>(
        &mut self,
        model: &MpmModel<D>,
        particles: &Particles<D>,
        step: usize,
        time: f64,
    ) -> Result<(), RunError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
    {
        let file =
            crate::run::pieces::write_snapshot(self.out, step, particles.len(), |path, piece| {
                write_vtu(path, &model.particles, particles, time, piece)
            })?;
        self.pvd.push((time, file));
        // The collection lists every VTU written so far: ParaView opens a killed run.
        output::write_pvd(&self.out.join("solution.pvd"), &self.pvd)?;
        Ok(())
    }

    /// The last state's VTU when a run stopped early (collapse, failure), the `.pvd`
    /// collection and the final plastic strain map `plastic_strain.png`.
    pub fn finish<const D: usize, const N: usize>(
        &mut self,
        model: &MpmModel<D>,
        particles: &Particles<D>,
        step: usize,
        time: f64,
    ) -> Result<(), RunError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
    {
        if self.pvd.last().map(|(t, _)| *t) != Some(time) {
            self.write_vtu(model, particles, step, time)?;
        }
        if !crate::ranks::ranks().is_root() {
            return Ok(());
        }
        self.png(model, particles, &self.out.join("plastic_strain.png"), time)
    }

    fn png<const D: usize, const N: usize>(
        &self,
        model: &MpmModel<D>,
        particles: &Particles<D>,
        path: &Path,
        time: f64,
    ) -> Result<(), RunError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
    {
        let title = format!("{}, t = {time:.3} s", self.title);
        // Squares of the particles' mean side √V (3D: ∛V): the material's area, without
        // the gaps a nearest-neighbour spacing leaves in a stretched lattice.
        let side = if N == 3 {
            particles.volume.iter().map(|v| v.cbrt()).sum::<f64>() / particles.len() as f64
        } else {
            particles.volume.iter().map(|v| v.sqrt()).sum::<f64>() / particles.len() as f64
        };
        // In 3D the particles seen along z (the xy plane).
        let seen: Vec<[f64; 2]> = particles.position.iter().map(|x| [x[0], x[1]]).collect();
        output::plot_particles(
            path,
            &seen,
            &particles.plastic_strain,
            ParticlePlot {
                title: &title,
                value_label: "cumulative plastic strain ∫‖ε̇ᵖ‖dt",
                bounds: Some(model.bounds),
                marker_size: Some(side),
                floor: model.floor,
            },
        )?;
        Ok(())
    }
}

/// The particle VTU of `p` at `time`, with each particle's `displacement` from its place in
/// `initial` (the run's particles at t = 0: a run neither adds nor removes particles, so
/// index `i` is the same particle) and its `material` index. Particles carry no strain
/// (no deformation gradient, no accumulated `ε`: each sub-step's strain increment lives
/// only in G2P), so the MPM VTU has neither `strain` nor `plastic_strain_increment`
/// (`docs/mpm.md`, 'Outputs').
fn write_vtu<const D: usize, const N: usize>(
    path: &Path,
    initial: &Particles<D>,
    p: &Particles<D>,
    time: f64,
    piece: Option<std::ops::Range<usize>>,
) -> Result<Option<String>, RunError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
{
    if initial.len() != p.len() {
        return Err(OutputError::invalid(
            "displacement",
            format!(
                "{} particles now, {} at t = 0: a particle's start is unknown",
                p.len(),
                initial.len()
            ),
        )
        .into());
    }
    let displacement: Vec<[f64; N]> = p
        .position
        .iter()
        .zip(&initial.position)
        .map(|(x, x0)| std::array::from_fn(|a| x[a] - x0[a]))
        .collect();
    let material: Vec<usize> = (0..p.len()).map(|i| p.material_of(i)).collect();
    let snapshot = ParticleSnapshot {
        time,
        position: &p.position,
        velocity: &p.velocity,
        volume: &p.volume,
        mass: &p.mass,
        stress: &p.stress,
        plastic_strain: &p.plastic_strain,
    };
    let extras = ParticleExtras {
        displacement: Some(&displacement),
        material: Some(&material),
    };
    Ok(match piece {
        None => {
            output::write_particle_vtu_with(path, &snapshot, &extras)?;
            None
        }
        Some(range) => Some(output::write_particle_vtu_piece(
            path, &snapshot, &extras, range,
        )?),
    })
}
