//! Material points: the Lagrangian carriers of mass, momentum, volume, stress and history.
use crate::error::MpmError;

/// Structure-of-arrays particle set. Units: m, m/s, kg/m and m²·(1 m) per metre of
/// thickness (plane strain), Pa (Mandel `(xx, yy, zz, √2 xy)`, tension positive).
/// Serialized field by field (a checkpoint of a run's state).
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Particles {
    pub position: Vec<[f64; 2]>,
    pub velocity: Vec<[f64; 2]>,
    pub mass: Vec<f64>,
    pub volume: Vec<f64>,
    pub stress: Vec<[f64; 4]>,
    /// Cumulative equivalent plastic strain `∫ ‖ε̇ᵖ‖ dt`.
    pub plastic_strain: Vec<f64>,
    /// Constant external force on the particle besides gravity (N/m), e.g. a surcharge
    /// carried by the surface particles.
    pub external_force: Vec<[f64; 2]>,
    /// Each particle's index into the [`Mpm`](crate::Mpm)'s materials
    /// ([`Mpm::with_materials`](crate::Mpm::with_materials)). Empty: every particle is of
    /// material 0 (a set built without materials, or a checkpoint written before them).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub material: Vec<usize>,
}

impl Particles {
    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

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
    pub fn push(&mut self, position: [f64; 2], mass: f64, volume: f64) {
        if !self.material.is_empty() {
            self.material.push(0);
        }
        self.position.push(position);
        self.velocity.push([0.0; 2]);
        self.mass.push(mass);
        self.volume.push(volume);
        self.stress.push([0.0; 4]);
        self.plastic_strain.push(0.0);
        self.external_force.push([0.0; 2]);
    }

    /// Appends every particle of `other`, with its material.
    pub fn extend(&mut self, other: &Particles) {
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
            if !self.position[p].iter().all(|v| v.is_finite()) {
                return bad("position", p, format!("{:?}", self.position[p]));
            }
            if !self.velocity[p].iter().all(|v| v.is_finite()) {
                return bad("velocity", p, format!("{:?}", self.velocity[p]));
            }
            if !self.stress[p].iter().all(|v| v.is_finite()) {
                return bad("stress", p, format!("{:?}", self.stress[p]));
            }
            if !self.external_force[p].iter().all(|v| v.is_finite()) {
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

    /// Total mass (kg/m) and linear momentum (kg/s per m).
    pub fn mass_and_momentum(&self) -> (f64, [f64; 2]) {
        let mut momentum = [0.0; 2];
        for (m, v) in self.mass.iter().zip(&self.velocity) {
            momentum[0] += m * v[0];
            momentum[1] += m * v[1];
        }
        (self.mass.iter().sum(), momentum)
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
