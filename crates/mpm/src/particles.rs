//! Material points: the Lagrangian carriers of mass, momentum, volume, stress and history.
use crate::dimension::{stress_serde, Dimension, Mandel, Vector};
use crate::error::MpmError;

/// Structure-of-arrays particle set. Units: m, m/s, Pa (Mandel `(xx, yy, zz, √2 xy)` in
/// 2D, `(xx, yy, zz, √2 yz, √2 xz, √2 xy)` in 3D, tension positive); in 2D kg/m and m²
/// (per metre of thickness, plane strain), in 3D kg and m³.
/// Serialized field by field (a checkpoint of a run's state).
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, bound = "")]
pub struct Particles<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub position: Vec<Vector<D>>,
    pub velocity: Vec<Vector<D>>,
    pub mass: Vec<f64>,
    pub volume: Vec<f64>,
    #[serde(with = "stress_serde")]
    pub stress: Vec<[f64; D]>,
    /// Cumulative equivalent plastic strain `∫ ‖ε̇ᵖ‖ dt`.
    pub plastic_strain: Vec<f64>,
    /// Constant external force on the particle besides gravity (N/m), e.g. a surcharge
    /// carried by the surface particles.
    pub external_force: Vec<Vector<D>>,
    /// Each particle's index into the [`Mpm`](crate::Mpm)'s materials
    /// ([`Mpm::with_materials`](crate::Mpm::with_materials)). Empty: every particle is of
    /// material 0 (a set built without materials, or a checkpoint written before them).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub material: Vec<usize>,
}

impl<const D: usize> Particles<D>
where
    Mandel<D>: Dimension,
{
    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// The same particles, all of material `material` (an index into the
    /// [`Mpm`](crate::Mpm)'s materials).
    pub fn with_material(mut self, material: usize) -> Self {
        self.material = vec![material; self.len()];
        self
    }

    /// The material index of particle `p` (0 when [`Particles::material`] is empty).
    pub fn material_of(&self, p: usize) -> usize {
        self.material.get(p).copied().unwrap_or(0)
    }

    /// Appends a particle at rest, stress free, of material 0.
    pub fn push(&mut self, position: Vector<D>, mass: f64, volume: f64) {
        if !self.material.is_empty() {
            self.material.push(0);
        }
        self.position.push(position);
        self.velocity.push(Vector::<D>::default());
        self.mass.push(mass);
        self.volume.push(volume);
        self.stress.push([0.0; D]);
        self.plastic_strain.push(0.0);
        self.external_force.push(Vector::<D>::default());
    }

    /// Appends every particle of `other`, with its material.
    pub fn extend(&mut self, other: &Particles<D>) {
        // Both without material indices: all of material 0, the list stays empty.
        if !(self.material.is_empty() && other.material.is_empty()) {
            if self.material.is_empty() {
                self.material = vec![0; self.len()];
            }
            if other.material.is_empty() {
                self.material.extend(std::iter::repeat_n(0, other.len()));
            } else {
                self.material.extend_from_slice(&other.material);
            }
        }
        self.position.extend_from_slice(&other.position);
        self.velocity.extend_from_slice(&other.velocity);
        self.mass.extend_from_slice(&other.mass);
        self.volume.extend_from_slice(&other.volume);
        self.stress.extend_from_slice(&other.stress);
        self.plastic_strain.extend_from_slice(&other.plastic_strain);
        self.external_force.extend_from_slice(&other.external_force);
    }

    /// Equal lengths (`material` may be empty), finite values, positive mass and volume.
    pub fn validate(&self) -> Result<(), MpmError> {
        let n = self.len();
        let lens = [
            ("velocity", self.velocity.len()),
            ("mass", self.mass.len()),
            ("volume", self.volume.len()),
            ("stress", self.stress.len()),
            ("plastic_strain", self.plastic_strain.len()),
            ("external_force", self.external_force.len()),
        ];
        if !(self.material.is_empty() || self.material.len() == n) {
            return Err(MpmError::invalid(
                "particles.material",
                format!(
                    "{} entries for {n} particles (empty: all of material 0)",
                    self.material.len()
                ),
            ));
        }
        for (field, len) in lens {
            if len != n {
                return Err(MpmError::invalid(
                    format!("particles.{field}"),
                    format!("{len} entries for {n} particles"),
                ));
            }
        }
        let bad = |field: &str, p: usize, v: String| {
            Err(MpmError::invalid(
                format!("particles.{field}[{p}]"),
                format!("{v} must be finite"),
            ))
        };
        for p in 0..n {
            if !self.position[p].as_ref().iter().all(|v| v.is_finite()) {
                return bad("position", p, format!("{:?}", self.position[p]));
            }
            if !self.velocity[p].as_ref().iter().all(|v| v.is_finite()) {
                return bad("velocity", p, format!("{:?}", self.velocity[p]));
            }
            if !self.stress[p].iter().all(|v| v.is_finite()) {
                return bad("stress", p, format!("{:?}", self.stress[p]));
            }
            if !self.external_force[p]
                .as_ref()
                .iter()
                .all(|v| v.is_finite())
            {
                return bad("external_force", p, format!("{:?}", self.external_force[p]));
            }
            if !self.plastic_strain[p].is_finite() {
                return bad("plastic_strain", p, format!("{}", self.plastic_strain[p]));
            }
            for (field, v) in [("mass", self.mass[p]), ("volume", self.volume[p])] {
                if !(v.is_finite() && v > 0.0) {
                    return Err(MpmError::invalid(
                        format!("particles.{field}[{p}]"),
                        format!("{v} must be finite and > 0"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Total mass (kg/m in 2D, kg in 3D) and linear momentum.
    pub fn mass_and_momentum(&self) -> (f64, Vector<D>) {
        let mut momentum = Vector::<D>::default();
        for (m, v) in self.mass.iter().zip(&self.velocity) {
            for a in 0..Mandel::<D>::AXES {
                momentum[a] += m * v[a];
            }
        }
        (self.mass.iter().sum(), momentum)
    }
}

impl Particles<4> {
    /// Fills the rectangle `[[xmin, ymin], [xmax, ymax]]` with `per_cell × per_cell`
    /// particles per square of side `spacing` (the grid's `dx`), at rest and stress free,
    /// each carrying its share of the area and `density · area` of mass.
    pub fn fill_rectangle(
        rectangle: [[f64; 2]; 2],
        spacing: f64,
        per_cell: usize,
        density: f64,
    ) -> Result<Self, MpmError> {
        let [[x0, y0], [x1, y1]] = rectangle;
        if !(rectangle.iter().flatten().all(|v| v.is_finite()) && x1 > x0 && y1 > y0) {
            return Err(MpmError::invalid(
                "rectangle",
                format!("{rectangle:?} must be finite with max > min"),
            ));
        }
        check_fill(spacing, per_cell, density)?;
        let d = spacing / per_cell as f64;
        let nx = ((x1 - x0) / d).round().max(1.0) as usize;
        let ny = ((y1 - y0) / d).round().max(1.0) as usize;
        let (dx, dy) = ((x1 - x0) / nx as f64, (y1 - y0) / ny as f64);
        let mut p = Particles::default();
        for j in 0..ny {
            for i in 0..nx {
                let area = dx * dy;
                p.push(
                    [x0 + (i as f64 + 0.5) * dx, y0 + (j as f64 + 0.5) * dy],
                    density * area,
                    area,
                );
            }
        }
        Ok(p)
    }

    /// Angular momentum about `centre` (kg m²/s per m).
    pub fn angular_momentum(&self, centre: [f64; 2]) -> f64 {
        self.position
            .iter()
            .zip(&self.velocity)
            .zip(&self.mass)
            .map(|((x, v), m)| m * ((x[0] - centre[0]) * v[1] - (x[1] - centre[1]) * v[0]))
            .sum()
    }
}

impl Particles<6> {
    /// Fills the box `[[xmin, ymin, zmin], [xmax, ymax, zmax]]` with `per_cell³`
    /// particles per cube of side `spacing` (the grid's `dx`), at rest and stress free,
    /// each carrying its share of the volume and `density · volume` of mass.
    pub fn fill_box(
        cuboid: [[f64; 3]; 2],
        spacing: f64,
        per_cell: usize,
        density: f64,
    ) -> Result<Self, MpmError> {
        let [lo, hi] = cuboid;
        if !(cuboid.iter().flatten().all(|v| v.is_finite()) && (0..3).all(|a| hi[a] > lo[a])) {
            return Err(MpmError::invalid(
                "box",
                format!("{cuboid:?} must be finite with max > min on every axis"),
            ));
        }
        check_fill(spacing, per_cell, density)?;
        Ok(Self::lattice(cuboid, spacing, per_cell, density, |_| true))
    }

    /// Fills the vertical cylinder (axis along y) of base centre `base = [x_c, y₀, z_c]`,
    /// `radius` and `height` (m): the particles of the box lattice of [`Particles::fill_box`]
    /// around it whose centre lies within `radius` of the axis.
    pub fn fill_cylinder(
        base: [f64; 3],
        radius: f64,
        height: f64,
        spacing: f64,
        per_cell: usize,
        density: f64,
    ) -> Result<Self, MpmError> {
        Self::cylinder(base, radius, height, false, spacing, per_cell, density)
    }

    /// The quarter `x ≥ x_c, z ≥ z_c` of [`Particles::fill_cylinder`]: with slip walls on
    /// the planes `x = x_c` and `z = z_c` it stands for the whole cylinder at a quarter of
    /// the cost (symmetry).
    pub fn fill_quarter_cylinder(
        base: [f64; 3],
        radius: f64,
        height: f64,
        spacing: f64,
        per_cell: usize,
        density: f64,
    ) -> Result<Self, MpmError> {
        Self::cylinder(base, radius, height, true, spacing, per_cell, density)
    }

    fn cylinder(
        base: [f64; 3],
        radius: f64,
        height: f64,
        quarter: bool,
        spacing: f64,
        per_cell: usize,
        density: f64,
    ) -> Result<Self, MpmError> {
        if !base.iter().all(|v| v.is_finite()) {
            return Err(MpmError::invalid(
                "cylinder.base",
                format!("{base:?} must be finite"),
            ));
        }
        for (field, v) in [("cylinder.radius", radius), ("cylinder.height", height)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(MpmError::invalid(
                    field,
                    format!("{v} m must be finite and > 0"),
                ));
            }
        }
        check_fill(spacing, per_cell, density)?;
        let [xc, y0, zc] = base;
        let low = if quarter { 0.0 } else { radius };
        let cuboid = [
            [xc - low, y0, zc - low],
            [xc + radius, y0 + height, zc + radius],
        ];
        let inside = |x: [f64; 3]| (x[0] - xc).powi(2) + (x[2] - zc).powi(2) <= radius * radius;
        Ok(Self::lattice(cuboid, spacing, per_cell, density, inside))
    }

    /// The lattice of `per_cell³` particles per cube of side `spacing` over `cuboid`, those
    /// whose centre `keep` accepts; x fastest, then y, then z.
    fn lattice(
        cuboid: [[f64; 3]; 2],
        spacing: f64,
        per_cell: usize,
        density: f64,
        keep: impl Fn([f64; 3]) -> bool,
    ) -> Self {
        let [lo, hi] = cuboid;
        let d = spacing / per_cell as f64;
        let n = [0, 1, 2].map(|a| ((hi[a] - lo[a]) / d).round().max(1.0) as usize);
        let step = [0, 1, 2].map(|a| (hi[a] - lo[a]) / n[a] as f64);
        let volume = step[0] * step[1] * step[2];
        let mut p = Particles::default();
        for k in 0..n[2] {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    let x = [
                        lo[0] + (i as f64 + 0.5) * step[0],
                        lo[1] + (j as f64 + 0.5) * step[1],
                        lo[2] + (k as f64 + 0.5) * step[2],
                    ];
                    if keep(x) {
                        p.push(x, density * volume, volume);
                    }
                }
            }
        }
        p
    }

    /// Angular momentum `Σ m (x − c) × v` about `centre` (kg m²/s).
    pub fn angular_momentum(&self, centre: [f64; 3]) -> [f64; 3] {
        let mut l = [0.0; 3];
        for ((x, v), m) in self.position.iter().zip(&self.velocity).zip(&self.mass) {
            let r = [x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]];
            l[0] += m * (r[1] * v[2] - r[2] * v[1]);
            l[1] += m * (r[2] * v[0] - r[0] * v[2]);
            l[2] += m * (r[0] * v[1] - r[1] * v[0]);
        }
        l
    }
}

/// The checks every fill makes on its lattice and density.
fn check_fill(spacing: f64, per_cell: usize, density: f64) -> Result<(), MpmError> {
    if !(spacing.is_finite() && spacing > 0.0) {
        return Err(MpmError::invalid(
            "spacing",
            format!("{spacing} m must be > 0"),
        ));
    }
    if per_cell == 0 || per_cell > 16 {
        return Err(MpmError::invalid(
            "particles_per_cell",
            format!("{per_cell} must be between 1 and 16 per axis"),
        ));
    }
    if !(density.is_finite() && density > 0.0) {
        return Err(MpmError::invalid(
            "density",
            format!("{density} kg/m³ must be finite and > 0"),
        ));
    }
    Ok(())
}
