//! A 3D finite-element [`Model`] from a scene (`[analysis] geometry = "3d"`,
//! `docs/3d.md`): a `[mesh.box]` of tetrahedra or a Gmsh file of them, the materials and
//! `[[region]]` boxes, the `[[boundary]]` conditions with their reaction, gravity, a water
//! table (pore pressure, saturated weight, its push on the free faces below it), face
//! tractions and pressures, point loads, the quasi-static masses and the K₀ initial
//! stress; what 3D does not run yet (stages, a uniform initial stress) is refused naming
//! its field; `[stability]` runs by `analysis::stability`. The parts shared with 2D are
//! the same functions: densities, weight and water (`super::build`), materials
//! (`super::materials`), prescribed motion (`super::motion`), quasi-static masses
//! (`super::quasi_static`), the initial stress (`crate::model::initial_stress`), the checks
//! of `scene::check`.
use talus_fem::{BoundaryFace, Constraint, DofMap, ElementOrder, Model, State, TetrahedralMesh};

use crate::scene::{
    check, scales,
    scales::{norm, ramp_max},
    AnalysisKind, Fix, MeshSpec, Order, Ramp, Scene3, SceneError, Selection,
};

/// A model of 3D stress points: Mandel size 6.
pub type Model3 = Model<6>;
/// Its state.
pub type State3 = State<6>;

/// Why a 3D scene refuses a section: it runs in 2D only, for now.
fn not_in_3d(scene: &Scene3, field: &str, what: &str) -> SceneError {
    scene.error(
        field,
        format!(
            "{what} is not supported in 3D yet (docs/3d.md, 'Next'); it runs in 2D \
             (plane strain, axisymmetry)"
        ),
    )
}

/// The sections a 3D scene may not use yet, refused naming the first one given.
fn refuse_unsupported(scene: &Scene3) -> Result<(), SceneError> {
    let spec = &scene.spec;
    if !spec.stage.is_empty() {
        return Err(not_in_3d(
            scene,
            "stage",
            "a staged construction ([[stage]])",
        ));
    }
    if spec.initial_stress.is_some_and(|i| i.stress.is_some()) {
        return Err(not_in_3d(
            scene,
            "initial_stress.stress",
            "a uniform initial stress (its 4 components are 2D's; the K₀ procedure runs)",
        ));
    }
    Ok(())
}

/// The 3D model of `scene`.
pub fn model_3d(scene: &Scene3) -> Result<Model3, SceneError> {
    crate::scene::dimension::check(scene, &scene.source, &scene.spec)?;
    refuse_unsupported(scene)?;
    let spec = &scene.spec;
    let time = spec.time;
    check::time(scene, &time)?;
    // Loads finite before the scales read them (`check::loads`).
    check::loads(scene, &scene.spec)?;
    check::solver(scene, &spec.solver)?;
    scales::caps(scene, &time, spec.solver.max_step_halvings)?;
    let mesh = build_mesh(scene)?;
    let ground = super::materials::ground(scene, &mesh)?;
    check_scales(scene, &mesh)?;
    let geometry = spec.analysis.geometry.fem();

    let mut constraints = Vec::new();
    let mut boundary_ramps = Vec::new();
    for (k, b) in spec.boundary.iter().enumerate() {
        let nodes = select_nodes(scene, &mesh, &b.nodes, &format!("boundary[{k}].nodes"))?;
        let c = match b.fix {
            Fix::X => Constraint::FixX,
            Fix::Y => Constraint::FixY,
            Fix::Z => Constraint::FixZ,
            Fix::Xy => Constraint::FixXY,
            Fix::Xz => Constraint::FixXZ,
            Fix::Yz => Constraint::FixYZ,
            Fix::Xyz => Constraint::Fixed,
        };
        if !b.velocity.iter().all(|v| v.is_finite()) {
            return Err(scene.error(&format!("boundary[{k}].velocity"), "must be finite"));
        }
        boundary_ramps.push(check::ramp(scene, &format!("boundary[{k}].ramp"), &b.ramp)?);
        constraints.push((nodes, c));
    }
    let dofs = DofMap::with_components(mesh.nodes.len(), 3, &constraints)
        .map_err(|e| scene.error("boundary", e.to_string()))?;
    if dofs.n_free() == 0 {
        return Err(scene.error("boundary", "every degree of freedom is prescribed"));
    }
    let water = super::build::water_table(scene)?;
    let (assembly, point_density) = super::build::assembly_with_densities(
        scene,
        &mesh,
        &dofs,
        &ground.element_material,
        water.as_ref(),
        geometry,
    )?;
    let point_material: Vec<usize> = (assembly.gauss_element.iter())
        .map(|&e| ground.element_material[e])
        .collect();

    let boundary_nodes: Vec<Vec<usize>> = constraints.iter().map(|(n, _)| n.clone()).collect();
    let motion =
        super::motion::prescribed_motion(scene, &boundary_nodes, boundary_ramps, &dofs, false)?;

    // Added in the order of the scene, as in 2D: a load without a ramp into the constant
    // forces, a ramped one kept apart at multiplier 1 (`Model::add_load`).
    let mut loads: Vec<((Vec<f64>, Vec<f64>), Option<Ramp>)> = Vec::new();
    let gravity_ramp = check::ramp(scene, "gravity_ramp", &spec.gravity_ramp)?;
    match spec.gravity {
        Some(g) => loads.push((
            super::build::point_weight(scene, &assembly, &point_density, g)?,
            gravity_ramp.clone(),
        )),
        None if gravity_ramp.is_some() => {
            return Err(scene.error("gravity_ramp", "multiplies `gravity`, which is not given"))
        }
        None => {}
    }
    // The water's push on the free faces below the table, following the weight's ramp
    // as the pore pressure does (2D's edges, `super::build::free_below`).
    if let Some(w) = &water {
        let faces = super::build::free_below(
            mesh.boundary_faces(),
            |f| &f.nodes[..],
            &mesh.nodes,
            &dofs,
            w,
        );
        if !faces.is_empty() {
            loads.push((
                assembly
                    .pressure_with(&mesh, &faces, |x| w.pore_pressure(x))
                    .map_err(|e| scene.error("water", e.to_string()))?,
                gravity_ramp.clone(),
            ));
        }
    }
    for (k, t) in spec.traction.iter().enumerate() {
        let field = format!("traction[{k}].faces");
        let faces = select_faces(scene, &mesh, &t.edges, &field)?;
        let ramp = check::ramp(scene, &format!("traction[{k}].ramp"), &t.ramp)?;
        let forces = assembly
            .traction(&mesh, &faces, t.value)
            .map_err(|e| scene.error(&format!("traction[{k}].value"), e.to_string()))?;
        loads.push((forces, ramp));
    }
    for (k, p) in spec.pressure.iter().enumerate() {
        let field = format!("pressure[{k}].faces");
        let faces = select_faces(scene, &mesh, &p.edges, &field)?;
        let ramp = check::ramp(scene, &format!("pressure[{k}].ramp"), &p.ramp)?;
        // As in 2D, `gradient` varies the pressure along y (water against a wall).
        let forces = match p.gradient {
            None => assembly.pressure(&mesh, &faces, p.value),
            Some(g) => assembly.pressure_with(&mesh, &faces, |x| p.value + g * x[1]),
        };
        loads.push((
            forces.map_err(|e| scene.error(&field, e.to_string()))?,
            ramp,
        ));
    }
    for (k, l) in spec.point_load.iter().enumerate() {
        let field = format!("point_load[{k}]");
        let ramp = check::ramp(scene, &format!("{field}.ramp"), &l.ramp)?;
        let node = nearest_node(&mesh, l.point);
        let forces = assembly
            .point_force(node, l.force)
            .map_err(|e| scene.error(&format!("{field}.force"), e.to_string()))?;
        loads.push((forces, ramp));
    }
    let mut model = Model::with_materials(mesh, assembly, ground.materials, point_material)
        .map_err(|e| scene.error("material", e.to_string()))?;
    if let Some(w) = &water {
        model.pore_pressure = (model.assembly.gauss_points.iter())
            .map(|&x| w.pore_pressure(x))
            .collect();
        model.pore_pressure_ramp = gravity_ramp;
    }
    for (forces, ramp) in loads {
        model.add_load(forces, ramp);
    }
    super::quasi_static::scale_masses(scene, &mut model)?;
    model.prescribed_velocity = motion.velocity;
    model.velocity_ramps = motion.velocity_ramps;
    model.reaction_dofs = motion.reaction_dofs;
    model.dof_owner = motion.owner;
    Ok(model)
}

/// The mesh of `[mesh.box]` or `[mesh.gmsh]`.
fn build_mesh(scene: &Scene3) -> Result<TetrahedralMesh, SceneError> {
    match &scene.spec.mesh {
        MeshSpec::Box {
            x,
            y,
            z,
            cells,
            order,
            focus,
            ratio,
        } => {
            // Before any coordinate is allocated, as `[mesh.rectangle]`.
            if cells.contains(&0) {
                return Err(scene.error(
                    "mesh.box.cells",
                    format!("{cells:?}: the number of cells must be ≥ 1 in x, y and z"),
                ));
            }
            let per_axis = |c: usize| match order {
                Order::P1 => c as f64 + 1.0,
                Order::P2 => 2.0 * c as f64 + 1.0,
            };
            let nodes = per_axis(cells[0]) * per_axis(cells[1]) * per_axis(cells[2]);
            refuse_too_large(scene, "mesh.box.cells", nodes)?;
            let focus = focus.unwrap_or([x[0], y[0], z[0]]);
            let mut axes = Vec::with_capacity(3);
            for (k, (name, range)) in [("x", x), ("y", y), ("z", z)].into_iter().enumerate() {
                let coords =
                    talus_fem::graded_coordinates(range[0], range[1], cells[k], focus[k], ratio[k])
                        .map_err(|e| scene.error(&format!("mesh.box.{name}"), e.to_string()))?;
                axes.push(coords);
            }
            let order = match order {
                Order::P1 => ElementOrder::P1,
                Order::P2 => ElementOrder::P2,
            };
            TetrahedralMesh::block(&axes[0], &axes[1], &axes[2], order)
                .map_err(|e| scene.error("mesh.box", e.to_string()))
        }
        MeshSpec::Gmsh {
            path,
            order,
            extrude: Some(z),
            layers,
        } => extruded_mesh(scene, path, *order, *z, *layers),
        MeshSpec::Gmsh {
            layers: Some(_), ..
        } => Err(scene.error(
            "mesh.gmsh.layers",
            "divides an extrusion: give `extrude = [z0, z1]` with it, or leave it out",
        )),
        MeshSpec::Gmsh { path, order, .. } => {
            let file = scene.resolve(path);
            let mesh = TetrahedralMesh::from_msh(&file)
                .map_err(|e| scene.error("mesh.gmsh.path", format!("{}: {e}", file.display())))?;
            refuse_too_large(scene, "mesh.gmsh.path", mesh.nodes.len() as f64)?;
            match (order, mesh.order) {
                (Some(Order::P2), ElementOrder::P1) | (Some(Order::P1), ElementOrder::P2) => {
                    Err(scene.error(
                        "mesh.gmsh.order",
                        format!(
                            "{:?}: {} holds {:?} tetrahedra; in 3D a mesh is used at the order \
                             it was meshed with (leave `order` out)",
                            order.unwrap_or(Order::P1),
                            file.display(),
                            mesh.order
                        ),
                    ))
                }
                _ => Ok(mesh),
            }
        }
        MeshSpec::Rectangle { .. } => Err(scene.error(
            "mesh.rectangle",
            "is 2D: a 3D scene is meshed by [mesh.box] or [mesh.gmsh] (tetrahedra)",
        )),
    }
}

/// Refuses a mesh of `nodes` nodes whose Newton factorization would not fit this
/// machine's memory (`super::memory`), naming `field` and the estimate.
fn refuse_too_large(scene: &Scene3, field: &str, nodes: f64) -> Result<(), SceneError> {
    let machine = super::memory::machine_mib().unwrap_or(super::memory::UNKNOWN_MACHINE_MIB);
    // Every node's 3 components: the free ones are fewer, by the boundary's.
    let unknowns = 3.0 * nodes;
    let associative = super::memory::associative(scene.spec.material.all());
    let need = super::memory::peak_mib(unknowns, associative);
    if need <= machine {
        return Ok(());
    }
    Err(scene.error(
        field,
        format!(
            "{nodes:.0} nodes, up to {unknowns:.3e} unknowns: a Newton step would need about \
             {:.1} GiB ({} flow; estimated from the peaks measured in docs/3d.md, 'Memory \
             and speed in 3D'), more than this machine's {:.1} GiB; coarsen the mesh",
            need / 1024.0,
            if associative {
                "associative"
            } else {
                "non-associative"
            },
            machine / 1024.0
        ),
    ))
}

/// Layers of an extrusion at most: a cap before anything is allocated.
const MAX_LAYERS: usize = 10_000;

/// `[mesh.gmsh]` with `extrude = [z0, z1]`: the file's 2D triangle mesh (raised to P2 by
/// `order = "P2"`, as in 2D) extruded along z in `layers` equal layers (default 1).
fn extruded_mesh(
    scene: &Scene3,
    path: &str,
    order: Option<Order>,
    [z0, z1]: [f64; 2],
    layers: Option<usize>,
) -> Result<TetrahedralMesh, SceneError> {
    if !(z0.is_finite() && z1.is_finite() && z1 > z0) {
        return Err(scene.error(
            "mesh.gmsh.extrude",
            format!("[{z0}, {z1}] m must be finite with z0 < z1"),
        ));
    }
    let layers = layers.unwrap_or(1);
    if !(1..=MAX_LAYERS).contains(&layers) {
        return Err(scene.error(
            "mesh.gmsh.layers",
            format!("{layers} must be between 1 and {MAX_LAYERS}"),
        ));
    }
    let file = scene.resolve(path);
    let mesh = talus_fem::Mesh::from_msh(&file).map_err(|e| {
        scene.error(
            "mesh.gmsh.path",
            format!(
                "{}: {e} (`extrude` reads a 2D triangle mesh)",
                file.display()
            ),
        )
    })?;
    let mesh = match (order, mesh.order) {
        (Some(Order::P2), ElementOrder::P1) => mesh
            .to_p2()
            .map_err(|e| scene.error("mesh.gmsh.order", e.to_string()))?,
        (Some(Order::P1), ElementOrder::P2) => {
            return Err(scene.error(
                "mesh.gmsh.order",
                format!(
                    "\"P1\": {} holds P2 (6-node) triangles; a P2 mesh is not lowered \
                     (mesh it with order 1, or leave `order` out)",
                    file.display()
                ),
            ))
        }
        _ => mesh,
    };
    // Nodes per layer boundary: the vertices (P1), or every node and the mid-layer ones
    // (P2), before the extrusion allocates them.
    let planes = match mesh.order {
        ElementOrder::P1 => layers as f64 + 1.0,
        ElementOrder::P2 => 2.0 * layers as f64 + 1.0,
    };
    refuse_too_large(scene, "mesh.gmsh.layers", mesh.nodes.len() as f64 * planes)?;
    let zs: Vec<f64> = (0..=layers)
        .map(|k| match k {
            0 => z0,
            k if k == layers => z1,
            k => z0 + (z1 - z0) * k as f64 / layers as f64,
        })
        .collect();
    TetrahedralMesh::extrude(&mesh, &zs).map_err(|e| {
        scene.error(
            "mesh.gmsh.extrude",
            format!("{} extruded over [{z0}, {z1}] m: {e}", file.display()),
        )
    })
}

/// The scene against its own scales (`scene::scales`), as 2D's `check_scales`: the cell
/// is the cube root of the smallest tetrahedron's volume.
fn check_scales(scene: &Scene3, mesh: &TetrahedralMesh) -> Result<(), SceneError> {
    let spec = &scene.spec;
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in &mesh.nodes {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let cell = (mesh.tetrahedra.iter())
        .map(|t| {
            let [a, b, c, d] = [t[0], t[1], t[2], t[3]].map(|n| mesh.nodes[n]);
            let e = |p: [f64; 3]| [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
            let (u, v, w) = (e(b), e(c), e(d));
            let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                + u[2] * (v[0] * w[1] - v[1] * w[0]);
            (det.abs() / 6.0).cbrt()
        })
        .fold(f64::INFINITY, f64::min);
    let tractions = spec.traction.iter().enumerate().map(|(k, t)| {
        (
            format!("traction[{k}].value"),
            norm(&t.value) * ramp_max(&t.ramp),
        )
    });
    let pressures = spec.pressure.iter().enumerate().map(|(k, p)| {
        let at = |y: f64| (p.value + p.gradient.unwrap_or(0.0) * y).abs();
        (
            format!("pressure[{k}].value"),
            at(lo[1]).max(at(hi[1])) * ramp_max(&p.ramp),
        )
    });
    // A point force spread over the smallest cell's face, as a stress.
    let points = spec.point_load.iter().enumerate().map(|(k, l)| {
        let v = norm(&l.force) * ramp_max(&l.ramp) / (cell * cell);
        (format!("point_load[{k}].force"), v)
    });
    let speeds = spec.boundary.iter().enumerate().map(|(k, b)| {
        (
            format!("boundary[{k}].velocity"),
            norm(&b.velocity) * ramp_max(&b.ramp),
        )
    });
    let imposed = scales::Imposed {
        materials: (spec.material.all().iter().enumerate())
            .map(|(k, m)| (spec.material.field(k), m))
            .collect(),
        time: &spec.time,
        // The scales read |g| only.
        gravity: spec.gravity.map(|g| norm(&g)),
        heights: [lo[1], hi[1]],
        initial_stress: spec.initial_stress.as_ref(),
        loads: tractions.chain(pressures).chain(points).collect(),
        speeds: speeds.collect(),
    };
    let body = scales::Scales {
        cell,
        max_step_motion: (0..3).map(|k| hi[k] - lo[k]).fold(f64::INFINITY, f64::min),
        motion_limit: "the body's smallest side",
        dynamic: spec.analysis.kind == AnalysisKind::Dynamic,
    };
    scales::check_scales(scene, &imposed, &body)
}

/// The node nearest `point` (the first of equally near ones).
fn nearest_node(mesh: &TetrahedralMesh, point: [f64; 3]) -> usize {
    let d = |n: &[f64; 3]| (0..3).map(|k| (n[k] - point[k]).powi(2)).sum::<f64>();
    (0..mesh.nodes.len())
        .min_by(|&a, &b| d(&mesh.nodes[a]).total_cmp(&d(&mesh.nodes[b])))
        .unwrap_or(0)
}

fn select_nodes(
    scene: &Scene3,
    mesh: &TetrahedralMesh,
    sel: &Selection<[f64; 3]>,
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

/// A face set by name, or the boundary faces whose nodes all lie in a box.
fn select_faces(
    scene: &Scene3,
    mesh: &TetrahedralMesh,
    sel: &Selection<[f64; 3]>,
    field: &str,
) -> Result<Vec<BoundaryFace>, SceneError> {
    let faces = match sel {
        Selection::Named(name) => mesh.face_sets.get(name).cloned().ok_or_else(|| {
            scene.error(
                field,
                format!(
                    "no face set named `{name}` (the mesh has: {})",
                    names(mesh.face_sets.keys())
                ),
            )
        })?,
        Selection::Box { corners } => mesh
            .boundary_faces_in_box(corners[0], corners[1])
            .map_err(|e| scene.error(field, e.to_string()))?,
    };
    if faces.is_empty() {
        return Err(scene.error(field, "selects no boundary face"));
    }
    Ok(faces)
}

fn names<'a>(keys: impl Iterator<Item = &'a String>) -> String {
    keys.map(String::as_str).collect::<Vec<_>>().join(", ")
}
