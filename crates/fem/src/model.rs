//! A finite-element model: everything fixed during a run (mesh, operators, material,
//! loads, prescribed motion). Stepped by talus-engine through its [`Discretization`]
//! (`crate::reduced_problem`).
//!
//! [`Discretization`]: talus_engine::Discretization
use nalgebra::SMatrix;
use talus_bipotential::{FlowRule, Material};
use talus_engine::Ramp;

use crate::assembly::Assembly;
use crate::dimension::{Dimension, ElementMesh, Mandel};
use crate::error::FemError;

/// A load that follows a ramp: its nodal forces at multiplier 1 (N/m).
#[derive(Debug, Clone, PartialEq)]
pub struct RampedForce {
    pub ramp: Ramp,
    pub free: Vec<f64>,
    pub prescribed: Vec<f64>,
}

/// The loading of one instant: forces (N/m) and prescribed velocities (m/s).
#[derive(Debug, Clone, PartialEq)]
pub struct Loads {
    pub force_free: Vec<f64>,
    pub force_prescribed: Vec<f64>,
    pub prescribed_velocity: Vec<f64>,
}

/// Everything fixed during a run: mesh, operators, material, loads, prescribed motion; in
/// plane strain or axisymmetry (`D = 4`, triangles) or 3D (`D = 6`, tetrahedra).
#[derive(Clone)]
pub struct Model<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub mesh: <Mandel<D> as Dimension>::Mesh,
    pub assembly: Assembly<D>,
    /// The materials, and the one of each Gauss point (an index into them).
    pub materials: Vec<Material>,
    pub point_material: Vec<usize>,
    /// Elastic compliance `S₀` of each material (1/Pa, Mandel).
    pub compliances: Vec<SMatrix<f64, D, D>>,
    /// Pore pressure at each Gauss point (Pa, compression positive; 0 when dry): yield
    /// acts on the effective stress `σ + p_w I` (`Material::flow_rule`). A field the
    /// mechanics reads, whoever fills it (a water table, a seepage solve).
    pub pore_pressure: Vec<f64>,
    /// The multiplier of `pore_pressure` in time (the water follows the weight's ramp);
    /// `None`: constant.
    pub pore_pressure_ramp: Option<Ramp>,
    /// External forces without a ramp (gravity, tractions, pressures), N/m, on free and
    /// prescribed dofs: the whole load of a model without load programmes.
    pub force_free: Vec<f64>,
    pub force_prescribed: Vec<f64>,
    /// Forces following a ramp, at multiplier 1: `f(t) = force + Σ_k ramp_k(t) f_k`.
    pub ramped_forces: Vec<RampedForce>,
    /// Velocity of every prescribed dof at multiplier 1 (m/s).
    pub prescribed_velocity: Vec<f64>,
    /// The prescribed dofs whose velocity follows a ramp, per ramp.
    pub velocity_ramps: Vec<(Ramp, Vec<usize>)>,
    /// Prescribed dofs of the boundary whose reaction is reported, with their component.
    pub reaction_dofs: Vec<(usize, usize)>,
    /// The direction the reported reaction and displacement are measured along: a
    /// component and its sign (`(1, −1)`, downward, by default; the app takes the reported
    /// boundary's motion when it moves along one axis).
    pub reaction_direction: (usize, f64),
    /// Per prescribed dof, the boundary condition whose velocity it follows (a scene's
    /// `[[boundary]]` index, the last that fixes it), which also owns its reaction.
    pub dof_owner: Vec<usize>,
    /// The smallest side of the mesh's bounding box (m): the body's scale for the collapse
    /// criterion (`docs/scenes.md`, 'Collapse').
    pub size: f64,
}

impl<const D: usize> Model<D>
where
    Mandel<D>: Dimension,
{
    /// `material` everywhere on `mesh` with the operators of `assembly`, dry and at rest:
    /// no load, every prescribed velocity 0, no reported boundary. Loads are added with
    /// [`Model::add_load`], velocities set in [`Model::prescribed_velocity`].
    pub fn new(
        mesh: <Mandel<D> as Dimension>::Mesh,
        assembly: Assembly<D>,
        material: impl Into<Material>,
    ) -> Self {
        let n = assembly.n_points();
        Self::build(mesh, assembly, vec![material.into()], vec![0; n])
    }

    /// [`Model::new`] with `materials`, point `p` made of `materials[point_material[p]]`.
    pub fn with_materials(
        mesh: <Mandel<D> as Dimension>::Mesh,
        assembly: Assembly<D>,
        materials: Vec<Material>,
        point_material: Vec<usize>,
    ) -> Result<Self, FemError> {
        if point_material.len() != assembly.n_points() {
            return Err(FemError::invalid(
                "point_material",
                format!(
                    "has {} entries for {} Gauss points",
                    point_material.len(),
                    assembly.n_points()
                ),
            ));
        }
        if let Some((p, &m)) = point_material
            .iter()
            .enumerate()
            .find(|(_, &m)| m >= materials.len())
        {
            return Err(FemError::invalid(
                "point_material",
                format!("point {p} names material {m} of {}", materials.len()),
            ));
        }
        Ok(Self::build(mesh, assembly, materials, point_material))
    }

    fn build(
        mesh: <Mandel<D> as Dimension>::Mesh,
        assembly: Assembly<D>,
        materials: Vec<Material>,
        point_material: Vec<usize>,
    ) -> Self {
        let dofs = assembly.dofs();
        let (n_free, n_prescribed) = (dofs.n_free(), dofs.n_prescribed());
        let size = smallest_side(mesh.node_positions());
        Self {
            size,
            compliances: materials.iter().map(|m| m.compliance::<D>()).collect(),
            pore_pressure: vec![0.0; point_material.len()],
            pore_pressure_ramp: None,
            materials,
            point_material,
            mesh,
            assembly,
            force_free: vec![0.0; n_free],
            force_prescribed: vec![0.0; n_prescribed],
            ramped_forces: Vec::new(),
            prescribed_velocity: vec![0.0; n_prescribed],
            velocity_ramps: Vec::new(),
            reaction_dofs: Vec::new(),
            reaction_direction: (1, -1.0),
            dof_owner: vec![0; n_prescribed],
        }
    }

    pub fn n_points(&self) -> usize {
        self.assembly.n_points()
    }

    /// The material of Gauss point `p`.
    pub fn material_at(&self, p: usize) -> &Material {
        &self.materials[self.point_material[p]]
    }

    /// Each element's material (that of its Gauss points).
    pub fn element_materials(&self) -> Vec<usize> {
        let mut m = vec![0; self.mesh.elements().len()];
        for (p, &e) in self.assembly.gauss_element.iter().enumerate() {
            m[e] = self.point_material[p];
        }
        m
    }

    /// The elastic compliance `S₀` of Gauss point `p` (1/Pa).
    pub fn compliance_at(&self, p: usize) -> &SMatrix<f64, D, D> {
        &self.compliances[self.point_material[p]]
    }

    /// Each Gauss point's rate-independent flow rule: its material's, under its pore
    /// pressure. The rules of a step of length `h` are [`Model::step_flow_rules`].
    pub fn flow_rules(&self) -> Vec<FlowRule<D>> {
        (0..self.n_points())
            .map(|p| self.material_at(p).flow_rule::<D>(self.pore_pressure[p]))
            .collect()
    }

    /// Each Gauss point's flow rule in a step of length `h` (s): [`Model::flow_rules`], with
    /// the Duvaut–Lions relaxation `N = (τ/h)(V_p S₀)⁻¹` of a material that has a
    /// relaxation time (`Material::point_flow_rule`); exactly [`Model::flow_rules`] without.
    pub fn step_flow_rules(&self, h: f64) -> Result<Vec<FlowRule<D>>, FemError> {
        self.point_rules(1.0, h)
    }

    /// [`Model::step_flow_rules`] at time `t` (s) when the pore pressure follows a ramp;
    /// `None` when it is constant (the rules of [`Model::reduced_system`] hold).
    pub fn flow_rules_at(&self, t: f64, h: f64) -> Option<Result<Vec<FlowRule<D>>, FemError>> {
        let f = self.pore_pressure_ramp.as_ref()?.at(t);
        Some(self.point_rules(f, h))
    }

    /// The step rules under `factor` times the pore pressure.
    fn point_rules(&self, factor: f64, h: f64) -> Result<Vec<FlowRule<D>>, FemError> {
        let volumes = &self.assembly.gauss_volumes;
        (0..self.n_points())
            .map(|p| {
                self.material_at(p)
                    .point_flow_rule::<D>(factor * self.pore_pressure[p], h, volumes[p])
                    .map_err(|e| FemError::invalid("relaxation_time", e.to_string()))
            })
            .collect()
    }

    /// Sets the materials again (strength reduction: the same points, weaker materials);
    /// the compliances follow.
    pub fn set_materials(&mut self, materials: Vec<Material>) -> Result<(), FemError> {
        if materials.len() != self.materials.len() {
            return Err(FemError::invalid(
                "materials",
                format!("{} given for {}", materials.len(), self.materials.len()),
            ));
        }
        self.compliances = materials.iter().map(|m| m.compliance::<D>()).collect();
        self.materials = materials;
        Ok(())
    }

    /// Adds the nodal forces `(free, prescribed)` (N/m, as the [`Assembly`]'s load
    /// methods return them): to the constant forces without a ramp, else kept apart at
    /// multiplier 1.
    pub fn add_load(&mut self, (free, prescribed): (Vec<f64>, Vec<f64>), ramp: Option<Ramp>) {
        match ramp {
            None => {
                add_scaled(&mut self.force_free, 1.0, &free);
                add_scaled(&mut self.force_prescribed, 1.0, &prescribed);
            }
            Some(ramp) => self.ramped_forces.push(RampedForce {
                ramp,
                free,
                prescribed,
            }),
        }
    }

    /// The forces and prescribed velocities at time `t` (s): each ramp's multiplier times
    /// its load, plus the loads without a ramp. Without ramps, the constant vectors.
    pub fn loads_at(&self, t: f64) -> Loads {
        let mut loads = Loads {
            force_free: self.force_free.clone(),
            force_prescribed: self.force_prescribed.clone(),
            prescribed_velocity: self.prescribed_velocity_at(t),
        };
        for r in &self.ramped_forces {
            let f = r.ramp.at(t);
            add_scaled(&mut loads.force_free, f, &r.free);
            add_scaled(&mut loads.force_prescribed, f, &r.prescribed);
        }
        loads
    }

    /// The velocity of every prescribed dof at time `t` (m/s).
    pub fn prescribed_velocity_at(&self, t: f64) -> Vec<f64> {
        let mut v = self.prescribed_velocity.clone();
        for (ramp, dofs) in &self.velocity_ramps {
            let f = ramp.at(t);
            for &j in dofs {
                v[j] *= f;
            }
        }
        v
    }

    /// Whether the loading rate of the step from `t0` to `t1` differs from the last step's,
    /// so that the last stress rate does not predict this step: a force ramp's slope
    /// changes at the step's start or inside it, or a velocity ramp changes faster than the
    /// step resolves (a velocity is continuous across a kink: stress rates follow it).
    pub fn loading_rate_changes_from(&self, t0: f64, t1: f64) -> bool {
        self.loading_rate_changes(t0, t1, Ramp::slope_changes_from)
    }

    /// Whether the loading rate changes inside the step from `t0` to `t1`, so that its
    /// stress rate will not predict the next step.
    pub fn loading_rate_changes_inside(&self, t0: f64, t1: f64) -> bool {
        self.loading_rate_changes(t0, t1, Ramp::slope_changes_inside)
    }

    /// A force ramp's slope changes by `force_kink`, or a velocity ramp changes within the
    /// step.
    fn loading_rate_changes(
        &self,
        t0: f64,
        t1: f64,
        force_kink: fn(&Ramp, f64, f64) -> bool,
    ) -> bool {
        self.ramped_forces
            .iter()
            .any(|r| force_kink(&r.ramp, t0, t1))
            || self
                .velocity_ramps
                .iter()
                .any(|(r, _)| r.changes_within(t0, t1))
    }
}

/// The bounding box of `nodes` (m).
pub fn bounding_box(nodes: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// The smallest side of the bounding box of `nodes` (m), over all their coordinates.
fn smallest_side<P: AsRef<[f64]>>(nodes: &[P]) -> f64 {
    let dim = nodes.first().map_or(0, |p| p.as_ref().len());
    (0..dim)
        .map(|k| {
            let (lo, hi) = nodes
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p.as_ref()[k]), hi.max(p.as_ref()[k]))
                });
            hi - lo
        })
        .fold(f64::INFINITY, f64::min)
}

fn add_scaled(into: &mut [f64], factor: f64, from: &[f64]) {
    for (a, b) in into.iter_mut().zip(from) {
        *a += factor * b;
    }
}
