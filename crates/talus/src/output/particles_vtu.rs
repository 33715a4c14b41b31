//! ParaView snapshot of the material points of one time step: VTK XML `UnstructuredGrid`,
//! ASCII, one `VTK_VERTEX` cell per particle.
use std::fmt::Write as _;
use std::path::Path;

use super::mesh::{check_finite, check_finite_scalars, check_finite_value, check_len};
use super::vtu::{
    begin_piece, derived, end_piece, indices, points_and_cells, scalars, stress_and_invariants,
    vectors, Derived,
};
use super::OutputError;

const VTK_VERTEX: u8 = 1;

/// The particle fields of one time step, one entry per particle in every slice; `N` = 2
/// (plane strain, Mandel size `D` = 4) or 3 (3D, `D` = 6).
///
/// Units: time s, position m, velocity m/s, volume m³ and mass kg per metre of thickness
/// (plane strain; in 3D m³ and kg), stress Pa (tension positive), plastic strain
/// dimensionless.
#[derive(Debug, Clone, Copy)]
pub struct ParticleSnapshot<'a, const N: usize = 2, const D: usize = 4> {
    pub time: f64,
    /// m.
    pub position: &'a [[f64; N]],
    /// m/s.
    pub velocity: &'a [[f64; N]],
    /// m³ per metre of thickness.
    pub volume: &'a [f64],
    /// kg per metre of thickness.
    pub mass: &'a [f64],
    /// Mandel `(xx, yy, zz, √2 xy)` (3D: `(xx, yy, zz, √2 yz, √2 xz, √2 xy)`), Pa,
    /// tension positive.
    pub stress: &'a [[f64; D]],
    /// Cumulative equivalent plastic strain `∫‖ε̇ᵖ‖ dt`.
    pub plastic_strain: &'a [f64],
}

impl<const N: usize, const D: usize> ParticleSnapshot<'_, N, D> {
    /// At least one particle, one entry per particle in every field, all finite; with the
    /// stress's derived values (computed once: checked, then written).
    fn validate(&self) -> Result<Derived, OutputError> {
        check_finite_value("time", self.time)?;
        let n = self.position.len();
        if n == 0 {
            return Err(OutputError::invalid("position", "there are no particles"));
        }
        check_len("velocity", self.velocity.len(), n, "particle")?;
        check_len("volume", self.volume.len(), n, "particle")?;
        check_len("mass", self.mass.len(), n, "particle")?;
        check_len("stress", self.stress.len(), n, "particle")?;
        check_len("plastic_strain", self.plastic_strain.len(), n, "particle")?;
        check_finite("position", self.position)?;
        check_finite("velocity", self.velocity)?;
        check_finite_scalars("volume", self.volume)?;
        check_finite_scalars("mass", self.mass)?;
        check_finite("stress", self.stress)?;
        let derived = derived(self.stress)?;
        check_finite_scalars("plastic_strain", self.plastic_strain)?;
        Ok(derived)
    }
}

/// Particle fields an MPM run adds to a [`ParticleSnapshot`] ([`write_particle_vtu_with`]),
/// one entry per particle; each `None` is left out of the file.
#[derive(Debug, Clone, Copy, Default)]
pub struct ParticleExtras<'a, const N: usize = 2> {
    /// Position minus the particle's position at t = 0, m.
    pub displacement: Option<&'a [[f64; N]]>,
    /// The particle's material index in the scene's list (from 0).
    pub material: Option<&'a [usize]>,
}

impl<const N: usize> ParticleExtras<'_, N> {
    fn validate(&self, n: usize) -> Result<(), OutputError> {
        if let Some(u) = self.displacement {
            check_len("displacement", u.len(), n, "particle")?;
            check_finite("displacement", u)?;
        }
        if let Some(m) = self.material {
            check_len("material", m.len(), n, "particle")?;
        }
        Ok(())
    }
}

/// Writes `s` to `path` as a VTK XML unstructured grid (ASCII) of one vertex per particle
/// at its position (z = 0 in 2D).
///
/// Point data: `velocity` (m/s, 3-vector, z = 0 in 2D), `volume`, `mass`, `stress` as a
/// symmetric tensor in plain components, VTK order `XX, YY, ZZ, XY, YZ, XZ` (the shear
/// components are the Mandel ones over √2; in 2D YZ = XZ = 0; Pa, tension positive), `von_mises` (Pa), `pressure` (−tr σ/3, Pa,
/// compression positive), `principal_stress` (3 components `σ1 ≥ σ2 ≥ σ3`, Pa, tension
/// positive) and `plastic_strain`. The time (s) is the `TimeValue` field. Numbers are
/// written in Rust's shortest round-trip form. Errors (`Invalid`, nothing written): no
/// particles, a field whose length differs from `position`'s, a non-finite value.
pub fn write_particle_vtu<const N: usize, const D: usize>(
    path: &Path,
    s: &ParticleSnapshot<N, D>,
) -> Result<(), OutputError> {
    write_particle_vtu_with(path, s, &ParticleExtras::default())
}

/// [`write_particle_vtu`] with the point data of `extras`: `displacement` (m, 3-vector with
/// z = 0) and `material` (`Int32`). Errors as [`write_particle_vtu`]'s, for these fields
/// too.
pub fn write_particle_vtu_with<const N: usize, const D: usize>(
    path: &Path,
    s: &ParticleSnapshot<N, D>,
    extras: &ParticleExtras<N>,
) -> Result<(), OutputError> {
    let derived = s.validate()?;
    extras.validate(s.position.len())?;
    let xml = particle_vtu_string(s, extras, &derived);
    super::atomic::write(path, xml)
}

/// The piece of [`write_particle_vtu_with`]'s file holding the particles `particles` (a
/// non-empty range; a piece of a `.pvtu`, [`super::write_pvtu`]); returns the XML written.
/// Errors as [`write_particle_vtu_with`]'s, checked on all the particles, and a range
/// past them or empty.
pub fn write_particle_vtu_piece<const N: usize, const D: usize>(
    path: &Path,
    s: &ParticleSnapshot<N, D>,
    extras: &ParticleExtras<N>,
    particles: std::ops::Range<usize>,
) -> Result<String, OutputError> {
    let derived = s.validate()?;
    let n = s.position.len();
    extras.validate(n)?;
    if particles.end > n || particles.start >= particles.end {
        return Err(OutputError::invalid(
            "particles",
            format!("{particles:?} is not a non-empty range of the {n} particles"),
        ));
    }
    let r = particles;
    let piece = ParticleSnapshot {
        time: s.time,
        position: &s.position[r.clone()],
        velocity: &s.velocity[r.clone()],
        volume: &s.volume[r.clone()],
        mass: &s.mass[r.clone()],
        stress: &s.stress[r.clone()],
        plastic_strain: &s.plastic_strain[r.clone()],
    };
    let piece_extras = ParticleExtras {
        displacement: extras.displacement.map(|u| &u[r.clone()]),
        material: extras.material.map(|m| &m[r.clone()]),
    };
    let xml = particle_vtu_string(&piece, &piece_extras, &derived.slice(r));
    super::atomic::write(path, &xml)?;
    Ok(xml)
}

fn particle_vtu_string<const N: usize, const D: usize>(
    s: &ParticleSnapshot<N, D>,
    extras: &ParticleExtras<N>,
    derived: &Derived,
) -> String {
    let n = s.position.len();
    let mut x = String::with_capacity(200 * n + 2000);
    begin_piece(&mut x, s.time, n, n);
    // Writing to a String cannot fail.
    let _ = writeln!(
        x,
        r#"      <PointData Vectors="velocity" Tensors="stress" Scalars="plastic_strain">"#
    );
    vectors(&mut x, "velocity", s.velocity);
    if let Some(u) = extras.displacement {
        vectors(&mut x, "displacement", u);
    }
    scalars(&mut x, "volume", s.volume);
    scalars(&mut x, "mass", s.mass);
    stress_and_invariants(&mut x, s.stress, derived);
    scalars(&mut x, "plastic_strain", s.plastic_strain);
    if let Some(m) = extras.material {
        indices(&mut x, "material", m);
    }
    let _ = writeln!(x, "      </PointData>");
    let vertices: Vec<[usize; 1]> = (0..n).map(|i| [i]).collect();
    points_and_cells(&mut x, s.position, &vertices, |_| VTK_VERTEX);
    end_piece(&mut x);
    x
}
