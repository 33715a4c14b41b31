use nalgebra::{SMatrix, SVector};
use talus_bipotential::{DruckerPrager, FlowRule};
use talus_fem::{
    Assembly, BoundaryEdge, Constraint, DofMap, ElementOrder, FemError, Geometry, Mesh,
};
use talus_ssn::{
    reduced_rhs, FreeVelocities, Operator, PrescribedVelocities, ReducedSystem, SolveError,
    Structured,
};

use super::State;

use crate::scene::{
    check, scales, AnalysisKind, Fix, MeshSpec, Order, Ramp, Scene, SceneError, Selection,
};

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

/// Everything fixed during a run: mesh, operators, material, loads, prescribed motion.
pub struct Model {
    pub mesh: Mesh,
    pub assembly: Assembly,
    pub material: DruckerPrager,
    pub flow_rule: FlowRule<4>,
    /// Elastic compliance `S₀` (1/Pa, Mandel).
    pub compliance: SMatrix<f64, 4, 4>,
    /// External forces without a ramp (gravity, tractions, pressures), N/m, on free and
    /// prescribed dofs: the whole load of a scene without load programmes.
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
    /// Per prescribed dof, the `[[boundary]]` whose velocity it follows (the last that
    /// fixes it), which also owns its reaction (`ReactionGroups`); `boundary.len()` for an
    /// axis node's radial dof that no `[[boundary]]` fixes (axisymmetric).
    pub dof_owner: Vec<usize>,
    /// The smallest side of the mesh's bounding box (m): the body's scale for the collapse
    /// criterion (`docs/scenes.md`, 'Collapse').
    pub size: f64,
}

impl Model {
    pub fn from_scene(scene: &Scene) -> Result<Self, SceneError> {
        let spec = &scene.spec;
        let mesh = build_mesh(scene)?;
        let m = &spec.material;
        let material = check::material(scene, m)?;
        check::time(scene, &spec.time)?;
        check::solver(scene, &spec.solver)?;
        check_scales(scene, &mesh)?;

        // Axisymmetric: the axis nodes' radial velocity is 0, first, so that a
        // `[[boundary]]` naming them later owns them (and their reaction).
        let geometry = spec.analysis.geometry.fem();
        geometry
            .check_mesh(&mesh)
            .map_err(|e| scene.error("analysis.geometry", e.to_string()))?;
        let axis = geometry.axis_nodes(&mesh);
        let mut constraints = Vec::new();
        if !axis.is_empty() {
            constraints.push((axis.clone(), Constraint::FixX));
        }
        let axis_constraints = constraints.len();
        let mut boundary_ramps = Vec::new();
        for (k, b) in spec.boundary.iter().enumerate() {
            let nodes = select_nodes(scene, &mesh, &b.nodes, &format!("boundary[{k}].nodes"))?;
            let c = match b.fix {
                Fix::X => Constraint::FixX,
                Fix::Y => Constraint::FixY,
                Fix::Xy => Constraint::Fixed,
            };
            if !b.velocity.iter().all(|v| v.is_finite()) {
                return Err(scene.error(&format!("boundary[{k}].velocity"), "must be finite"));
            }
            // The axis r = 0 cannot move radially (docs/axisymmetry.md): a radial velocity
            // there would tear the body open along its axis.
            let radial = matches!(b.fix, Fix::X | Fix::Xy) && b.velocity[0] != 0.0;
            if let Some(&n) = nodes.iter().find(|n| radial && axis.contains(n)) {
                return Err(scene.error(
                    &format!("boundary[{k}].velocity"),
                    format!(
                        "[{:e}, {:e}] m/s moves node {n} on the axis r = 0 radially; the \
                         axis has no radial velocity: use velocity = [0, {:e}] or leave the \
                         axis out of the set",
                        b.velocity[0], b.velocity[1], b.velocity[1]
                    ),
                ));
            }
            boundary_ramps.push(check::ramp(scene, &format!("boundary[{k}].ramp"), &b.ramp)?);
            constraints.push((nodes, c));
        }
        let dofs = DofMap::new(mesh.nodes.len(), &constraints)
            .map_err(|e| scene.error("boundary", e.to_string()))?;
        if dofs.n_free() == 0 {
            return Err(scene.error("boundary", "every degree of freedom is prescribed"));
        }
        let density = required_density(scene)?;
        let mut assembly =
            Assembly::with_geometry(&mesh, &dofs, density, geometry).map_err(|e| {
                let field = match &e {
                    FemError::InvalidInput {
                        field: "density", ..
                    } => "material.density",
                    _ if geometry == Geometry::Axisymmetric => "analysis.geometry",
                    _ => "material.density",
                };
                scene.error(field, e.to_string())
            })?;

        // Prescribed velocities: later conditions win where sets overlap.
        let mut prescribed_velocity = vec![0.0; dofs.n_prescribed()];
        // A dof no `[[boundary]]` fixes (the axis) belongs to no condition: index
        // `boundary.len()`, which names no reaction group and follows no ramp.
        let mut owner = vec![spec.boundary.len(); dofs.n_prescribed()];
        let mut reaction_dofs = Vec::new();
        let boundary_constraints = &constraints[axis_constraints..];
        for (k, (b, (nodes, _))) in spec.boundary.iter().zip(boundary_constraints).enumerate() {
            let is_reaction = b.name.is_some() && b.name == spec.output.reaction;
            for &n in nodes {
                for comp in 0..2 {
                    let fixed = matches!((b.fix, comp), (Fix::Xy, _) | (Fix::X, 0) | (Fix::Y, 1));
                    if let (true, Some(j)) = (fixed, dofs.prescribed(n, comp)) {
                        prescribed_velocity[j] = b.velocity[comp];
                        owner[j] = k;
                        if is_reaction && !reaction_dofs.contains(&(j, comp)) {
                            reaction_dofs.push((j, comp));
                        }
                    }
                }
            }
        }
        // A dof follows the ramp of the condition that set its velocity.
        let velocity_ramps: Vec<(Ramp, Vec<usize>)> = boundary_ramps
            .into_iter()
            .enumerate()
            .filter_map(|(k, ramp)| {
                let dofs: Vec<usize> = (0..owner.len()).filter(|&j| owner[j] == k).collect();
                ramp.filter(|_| !dofs.is_empty()).map(|r| (r, dofs))
            })
            .collect();
        if let Some(name) = &spec.output.reaction {
            if reaction_dofs.is_empty() {
                return Err(scene.error(
                    "output.reaction",
                    format!("no boundary named `{name}` with fixed components"),
                ));
            }
        }

        let mut force_free = vec![0.0; dofs.n_free()];
        let mut force_prescribed = vec![0.0; dofs.n_prescribed()];
        let mut ramped_forces = Vec::new();
        // A load without a ramp goes into the constant forces, in the order of the scene,
        // as it always did; a ramped one is kept apart at multiplier 1.
        let mut add_load = |(free, prescribed): (Vec<f64>, Vec<f64>), ramp: Option<Ramp>| match ramp
        {
            None => {
                add(&mut force_free, &free);
                add(&mut force_prescribed, &prescribed);
            }
            Some(ramp) => ramped_forces.push(RampedForce {
                ramp,
                free,
                prescribed,
            }),
        };
        let gravity_ramp = check::ramp(scene, "gravity_ramp", &spec.gravity_ramp)?;
        match spec.gravity {
            Some(g) => add_load(
                assembly
                    .body_force(density, g)
                    .map_err(|e| scene.error("gravity", e.to_string()))?,
                gravity_ramp,
            ),
            None if gravity_ramp.is_some() => {
                return Err(scene.error("gravity_ramp", "multiplies `gravity`, which is not given"))
            }
            None => {}
        }
        for (k, t) in spec.traction.iter().enumerate() {
            let field = format!("traction[{k}].edges");
            let edges = select_edges(scene, &mesh, &t.edges, &field)?;
            let ramp = check::ramp(scene, &format!("traction[{k}].ramp"), &t.ramp)?;
            add_load(
                assembly
                    .traction(&mesh, &edges, t.value)
                    .map_err(|e| scene.error(&format!("traction[{k}].value"), e.to_string()))?,
                ramp,
            );
        }
        for (k, p) in spec.pressure.iter().enumerate() {
            let field = format!("pressure[{k}].edges");
            let edges = select_edges(scene, &mesh, &p.edges, &field)?;
            let ramp = check::ramp(scene, &format!("pressure[{k}].ramp"), &p.ramp)?;
            if !p.value.is_finite() {
                return Err(scene.error(
                    &format!("pressure[{k}].value"),
                    format!("{} Pa must be finite", p.value),
                ));
            }
            add_load(
                assembly
                    .pressure(&mesh, &edges, p.value)
                    .map_err(|e| scene.error(&field, e.to_string()))?,
                ramp,
            );
        }
        let compliance = material.compliance::<4>();
        super::quasi_static::scale_masses(scene, &mut assembly, &compliance)?;
        let (lo, hi) = bounding_box(&mesh.nodes);
        let size = (hi[0] - lo[0]).min(hi[1] - lo[1]);
        Ok(Self {
            size,
            compliance,
            flow_rule: material.flow_rule::<4>(),
            material,
            mesh,
            assembly,
            force_free,
            force_prescribed,
            ramped_forces,
            prescribed_velocity,
            velocity_ramps,
            reaction_dofs,
            dof_owner: owner,
        })
    }

    pub fn n_points(&self) -> usize {
        self.assembly.n_points()
    }

    /// The state at the start of a run: at rest, with the scene's initial stress (K₀
    /// procedure or uniform) or stress free.
    pub fn initial_state(&self, scene: &Scene) -> Result<State, SceneError> {
        let dofs = self.assembly.dofs();
        let mut state = State::at_rest(
            self.n_points(),
            dofs.n_free(),
            dofs.n_prescribed(),
            self.mesh.nodes.len(),
        );
        if let Some(initial) = &scene.spec.initial_stress {
            state.sigma = super::initial_stress(scene, self, initial)?;
        }
        Ok(state)
    }

    /// The reduced problem of eq. 16 for steps of length `h`: `W = S + h² B M⁻¹ Bᵀ` kept in
    /// factors, `q = 0` until [`Solver::set_q`](talus_ssn::Solver::set_q) with
    /// [`reduced_rhs`](Self::reduced_rhs).
    pub fn reduced_system(&self, h: f64) -> Result<ReducedSystem<4>, SolveError> {
        let asm = &self.assembly;
        let operator = Operator::Structured(Structured {
            compliance: asm.compliance_blocks(&self.compliance),
            b: asm.b_free.clone(),
            lumped_mass: asm.lumped_mass_free.clone(),
            h,
        });
        let rules = vec![self.flow_rule; asm.n_points()];
        ReducedSystem::try_new(operator, vec![0.0; 4 * asm.n_points()], rules)
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

    /// `q` of eq. 16 for the step of length `h` after `state`:
    /// `q = −(S σₙ + h B vₙ + h² B M⁻¹ f + h B_D v_D)` (`docs/derivations.md`, 'The reduced
    /// system': `B v` is the strain rate; prescribed velocities enter through `B_D`), with
    /// `f` and `v_D` those of the end of the step, `tₙ + h` (implicit).
    pub fn reduced_rhs(&self, state: &State, h: f64) -> Vec<f64> {
        self.reduced_rhs_with(state, h, &self.loads_at(state.time + h))
    }

    /// [`reduced_rhs`](Self::reduced_rhs) with the step's loads already evaluated.
    pub fn reduced_rhs_with(&self, state: &State, h: f64, loads: &Loads) -> Vec<f64> {
        let asm = &self.assembly;
        let mut s_sigma = vec![0.0; 4 * asm.n_points()];
        for (p, v) in asm.gauss_volumes.iter().enumerate() {
            let s = self.compliance
                * SVector::<f64, 4>::from_column_slice(&state.sigma[4 * p..4 * p + 4])
                * *v;
            s_sigma[4 * p..4 * p + 4].copy_from_slice(s.as_slice());
        }
        let free = FreeVelocities {
            b: &asm.b_free,
            velocity: &state.velocity_free,
            force: &loads.force_free,
            lumped_mass: &asm.lumped_mass_free,
        };
        let prescribed = PrescribedVelocities {
            b: &asm.b_prescribed,
            velocity: &loads.prescribed_velocity,
        };
        // The lengths come from the same assembly: they agree by construction.
        reduced_rhs(h, &s_sigma, &free, &prescribed)
            .expect("the assembly's operators and velocities have matching sizes")
    }
}

/// The density (kg/m³) the assembly takes: the scene's, required by a dynamic analysis (the
/// mass) and by gravity (the weight); a weightless quasi-static scene may leave it out (its
/// masses are scaled from the stiffness, `super::quasi_static`).
fn required_density(scene: &Scene) -> Result<f64, SceneError> {
    let spec = &scene.spec;
    match spec.material.density {
        Some(d) => Ok(d),
        None if spec.gravity.is_some() => Err(scene.error(
            "material.density",
            "is required with `gravity` (the weight of the ground)",
        )),
        None if spec.analysis.kind == AnalysisKind::Dynamic => Err(scene.error(
            "material.density",
            "is required by a dynamic analysis (the mass); a quasi-static one \
             ([analysis] kind = \"quasi_static\") without gravity does not need it",
        )),
        None => Ok(1.0),
    }
}

/// The bounding box of `nodes` (m).
fn bounding_box(nodes: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// The largest |multiplier| of a ramp (1 without one).
fn ramp_max(ramp: &Option<Vec<[f64; 2]>>) -> f64 {
    ramp.as_ref()
        .map_or(1.0, |r| r.iter().fold(0.0, |m, p| m.max(p[1].abs())))
}

/// The scene against its own scales (`scene::scales`): caps, `h` against the wave time of
/// the smallest element and the boundaries' motion, the stresses against E.
fn check_scales(scene: &Scene, mesh: &Mesh) -> Result<(), SceneError> {
    let spec = &scene.spec;
    scales::caps(scene, &spec.time, spec.solver.max_step_halvings)?;
    let (lo, hi) = bounding_box(&mesh.nodes);
    let cell = mesh
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = [mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]]];
            ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
                .abs()
                .sqrt()
        })
        .fold(f64::INFINITY, f64::min);
    let mut stresses = scales::material_stresses(
        &spec.material,
        spec.gravity,
        [lo[1], hi[1]],
        spec.initial_stress.as_ref(),
    );
    for (k, t) in spec.traction.iter().enumerate() {
        let v = t.value[0].hypot(t.value[1]) * ramp_max(&t.ramp);
        stresses.push((format!("traction[{k}].value"), v));
    }
    for (k, p) in spec.pressure.iter().enumerate() {
        stresses.push((
            format!("pressure[{k}].value"),
            p.value.abs() * ramp_max(&p.ramp),
        ));
    }
    let speed = spec
        .boundary
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let v = b.velocity[0].hypot(b.velocity[1]) * ramp_max(&b.ramp);
            (format!("boundary[{k}].velocity"), v)
        })
        .filter(|(_, v)| *v > 0.0)
        .max_by(|a, b| a.1.total_cmp(&b.1));
    scales::check(
        scene,
        &spec.material,
        &spec.time,
        &stresses,
        &scales::Scales {
            cell,
            max_step_motion: (hi[0] - lo[0]).min(hi[1] - lo[1]),
            motion_limit: "the body's smallest side",
            speed,
            dynamic: spec.analysis.kind == AnalysisKind::Dynamic,
        },
    )
}

fn add(into: &mut [f64], from: &[f64]) {
    for (a, b) in into.iter_mut().zip(from) {
        *a += b;
    }
}

fn add_scaled(into: &mut [f64], factor: f64, from: &[f64]) {
    for (a, b) in into.iter_mut().zip(from) {
        *a += factor * b;
    }
}

fn build_mesh(scene: &Scene) -> Result<Mesh, SceneError> {
    match &scene.spec.mesh {
        MeshSpec::Rectangle {
            x,
            y,
            cells,
            order,
            focus,
            ratio,
        } => {
            // Before any coordinate is allocated: `[4294967295, 0]` has no Gauss point, so
            // the size estimate lets it through, yet its x coordinates alone take 34 GB.
            if cells.contains(&0) {
                return Err(scene.error(
                    "mesh.rectangle.cells",
                    format!("{cells:?}: the number of cells must be ≥ 1 in x and in y"),
                ));
            }
            let focus = focus.unwrap_or([x[0], y[0]]);
            let xs = talus_fem::graded_coordinates(x[0], x[1], cells[0], focus[0], ratio[0])
                .map_err(|e| scene.error("mesh.rectangle.x", e.to_string()))?;
            let ys = talus_fem::graded_coordinates(y[0], y[1], cells[1], focus[1], ratio[1])
                .map_err(|e| scene.error("mesh.rectangle.y", e.to_string()))?;
            let order = match order {
                Order::P1 => ElementOrder::P1,
                Order::P2 => ElementOrder::P2,
            };
            Mesh::rectangle(&xs, &ys, order)
                .map_err(|e| scene.error("mesh.rectangle", e.to_string()))
        }
        MeshSpec::Gmsh { path } => {
            // The .msh file named as well as the scene's line: the error is in it.
            let file = scene.resolve(path);
            Mesh::from_msh(&file)
                .map_err(|e| scene.error("mesh.gmsh.path", format!("{}: {e}", file.display())))
        }
    }
}

fn select_nodes(
    scene: &Scene,
    mesh: &Mesh,
    sel: &Selection,
    field: &str,
) -> Result<Vec<usize>, SceneError> {
    let nodes = match sel {
        Selection::Named(name) => mesh.node_sets.get(name).cloned().ok_or_else(|| {
            scene.error(
                field,
                format!(
                    "no node set named `{name}` (the mesh has: {})",
                    names(mesh.node_sets.keys())
                ),
            )
        })?,
        Selection::Box { corners } => mesh
            .nodes_in_box(corners[0], corners[1])
            .map_err(|e| scene.error(field, e.to_string()))?,
    };
    if nodes.is_empty() {
        return Err(scene.error(field, "selects no node"));
    }
    Ok(nodes)
}

fn select_edges(
    scene: &Scene,
    mesh: &Mesh,
    sel: &Selection,
    field: &str,
) -> Result<Vec<BoundaryEdge>, SceneError> {
    let edges = match sel {
        Selection::Named(name) => mesh.edge_sets.get(name).cloned().ok_or_else(|| {
            scene.error(
                field,
                format!(
                    "no edge set named `{name}` (the mesh has: {})",
                    names(mesh.edge_sets.keys())
                ),
            )
        })?,
        Selection::Box { corners } => {
            check_box_does_not_cut_edges(scene, mesh, corners, field)?;
            mesh.boundary_edges_in_box(corners[0], corners[1])
                .map_err(|e| scene.error(field, e.to_string()))?
        }
    };
    if edges.is_empty() {
        return Err(scene.error(field, "selects no boundary edge"));
    }
    Ok(edges)
}

/// A traction box whose side falls inside a boundary edge loads part of the surface with no
/// edge to carry it: an error, naming the edge, rather than a silently wrong load.
fn check_box_does_not_cut_edges(
    scene: &Scene,
    mesh: &Mesh,
    corners: &[[f64; 2]; 2],
    field: &str,
) -> Result<(), SceneError> {
    let (lo, hi) = (corners[0], corners[1]);
    let size = mesh
        .nodes
        .iter()
        .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()))
        .max(1.0);
    let tol = 1e-9 * size;
    let inside = |p: [f64; 2]| (0..2).all(|k| p[k] >= lo[k] - tol && p[k] <= hi[k] + tol);
    let strictly = |p: [f64; 2]| {
        (0..2).all(|k| p[k] > lo[k] + tol && p[k] < hi[k] - tol) || {
            // On a degenerate (flat) box, "strictly" means strictly between its ends.
            let flat: Vec<usize> = (0..2).filter(|&k| hi[k] - lo[k] <= 2.0 * tol).collect();
            !flat.is_empty()
                && (0..2)
                    .filter(|k| !flat.contains(k))
                    .all(|k| p[k] > lo[k] + tol && p[k] < hi[k] - tol)
                && inside(p)
        }
    };
    for edge in mesh.boundary_edges() {
        let pts: Vec<[f64; 2]> = edge.nodes.iter().map(|&n| mesh.nodes[n]).collect();
        let n_in = pts.iter().filter(|p| inside(**p)).count();
        if n_in > 0 && n_in < pts.len() && pts.iter().any(|p| strictly(*p)) {
            let (a, b) = (pts[0], pts[1]);
            return Err(scene.error(
                field,
                format!(
                    "the box cuts the boundary edge ({:.4}, {:.4})–({:.4}, {:.4}); put mesh nodes on the box's sides",
                    a[0], a[1], b[0], b[1]
                ),
            ));
        }
    }
    Ok(())
}

fn names<'a>(keys: impl Iterator<Item = &'a String>) -> String {
    keys.map(String::as_str).collect::<Vec<_>>().join(", ")
}
