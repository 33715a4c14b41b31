//! Checks of the sections FEM and MPM scenes share (`[material]`, `[time]`, `[solver]`),
//! each error naming the field and its value.
use talus_bipotential::{DruckerPrager, DruckerPragerParameters, Elastic, Material, MaterialError};

use super::material::Flow;
use super::source::Locate;
use super::{
    FactorPrecision, LinearSolverKind, MaterialModel, MaterialSpec, MpmSceneSpec, PointLoadSpec,
    PressureSpec, Ramp, SceneError, SceneSpec, SceneVector, SolverSpec, TimeSpec,
};

/// The material at `field` (`material` or `material[k]`): Drucker-Prager with its
/// required keys, or elastic without them; densities finite and positive when given (the
/// density's presence is checked by its user). With `flow = "davis"` the parameters as
/// written are checked, then replaced by Davis's associated equivalent
/// (`DruckerPragerParameters::davis_equivalent`, the transform `[stability] dilatancy =
/// "davis"` uses too): `ψ* = φ*`, so every flow rule of the material is associative.
/// `relaxation_time` (finite, > 0) is checked and kept by
/// `DruckerPrager::with_relaxation_time`.
pub fn material(
    scene: &impl Locate,
    field: &str,
    m: &MaterialSpec,
) -> Result<Material, SceneError> {
    for (key, value) in [
        ("density", m.density),
        ("saturated_density", m.saturated_density),
    ] {
        if let Some(v) = value.filter(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(scene.error(
                &format!("{field}.{key}"),
                format!("{v} kg/m³ must be finite and > 0"),
            ));
        }
    }
    let named = |e: MaterialError| {
        let MaterialError::InvalidParameter { name, .. } = &e;
        let key = name.split('.').next().unwrap_or(name);
        scene.error(&format!("{field}.{key}"), e.to_string())
    };
    match m.model {
        MaterialModel::Elastic => {
            let given = [
                ("friction_angle", m.friction_angle.is_some()),
                ("cohesion", m.cohesion.is_some()),
                ("dilatancy_angle", m.dilatancy_angle.is_some()),
                ("cone_fit", m.cone_fit.is_some()),
                ("flow", m.flow.is_some()),
                ("relaxation_time", m.relaxation_time.is_some()),
            ];
            if let Some((key, _)) = given.iter().find(|(_, g)| *g) {
                return Err(scene.error(
                    &format!("{field}.{key}"),
                    "is a Drucker-Prager key; model = \"elastic\" takes young_modulus, \
                     poisson_ratio, density, saturated_density and reduce",
                ));
            }
            Ok(Material::Elastic(
                Elastic::try_new(m.young_modulus, m.poisson_ratio).map_err(named)?,
            ))
        }
        MaterialModel::DruckerPrager => {
            let required = |key: &str, value: Option<f64>| {
                value.ok_or_else(|| {
                    scene.error(
                        &format!("{field}.{key}"),
                        "is required by model = \"drucker_prager\" (the default)",
                    )
                })
            };
            let friction_angle = required("friction_angle", m.friction_angle)?;
            let cohesion = required("cohesion", m.cohesion)?;
            let cone_fit = m.cone_fit.ok_or_else(|| {
                scene.error(
                    &format!("{field}.cone_fit"),
                    "is required by model = \"drucker_prager\": one of \"plane_strain\", \
                     \"outer_cone\", \"inner_cone\" or { explicit = { k_d = ... } }",
                )
            })?;
            let flow = m.flow().map_err(|value| {
                scene.error(
                    &format!("{field}.flow"),
                    format!("\"{value}\" is not a flow: one of {}", flow_choices()),
                )
            })?;
            let given = DruckerPrager::try_new(DruckerPragerParameters {
                young_modulus: m.young_modulus,
                poisson_ratio: m.poisson_ratio,
                friction_angle,
                cohesion,
                dilatancy_angle: m.dilatancy_angle.unwrap_or(friction_angle),
                cone_fit,
            })
            .map_err(named)?;
            let dp = match flow {
                Flow::AsGiven => given,
                Flow::Davis => DruckerPrager::try_new(given.parameters().davis_equivalent())
                    .map_err(|e| {
                        scene.error(
                            &format!("{field}.flow"),
                            format!("Davis's associated equivalent: {e}"),
                        )
                    })?,
            };
            Ok(Material::DruckerPrager(
                dp.with_relaxation_time(m.relaxation_time).map_err(named)?,
            ))
        }
    }
}

/// The choices of `flow`, each with what it does, for its error.
fn flow_choices() -> String {
    Flow::ALL
        .iter()
        .map(|f| {
            format!(
                "\"{}\" ({})",
                f.name(),
                match f {
                    Flow::AsGiven => "the default: dilatancy_angle as given",
                    Flow::Davis => "Davis's associated equivalent, ψ* = φ*",
                }
            )
        })
        .collect::<Vec<_>>()
        .join(" or ")
}

/// `h` finite and positive, at least one step.
pub fn time(scene: &impl Locate, ts: &TimeSpec) -> Result<(), SceneError> {
    if !(ts.step.is_finite() && ts.step > 0.0) {
        return Err(scene.error("time.step", format!("{} s must be finite and > 0", ts.step)));
    }
    if ts.steps == 0 {
        return Err(scene.error(
            "time.steps",
            "must be at least 1 (required without [[stage]])",
        ));
    }
    Ok(())
}

/// Tolerance and ρ factor finite and positive, at least one iteration; an f32 factor
/// only with `krylov`; nested dissection only in a build with METIS.
pub fn solver(scene: &impl Locate, sv: &SolverSpec) -> Result<(), SceneError> {
    if !(sv.tolerance.is_finite() && sv.tolerance > 0.0) {
        return Err(scene.error(
            "solver.tolerance",
            format!("{} must be finite and > 0", sv.tolerance),
        ));
    }
    if !(sv.rho_factor.is_finite() && sv.rho_factor > 0.0) {
        return Err(scene.error(
            "solver.rho_factor",
            format!("{} must be finite and > 0", sv.rho_factor),
        ));
    }
    if sv.max_iterations == 0 {
        return Err(scene.error("solver.max_iterations", "must be at least 1"));
    }
    if sv.precision == FactorPrecision::Single && sv.linear_solver != LinearSolverKind::Krylov {
        return Err(scene.error(
            "solver.precision",
            "\"single\" needs linear_solver = \"krylov\": an f32 factor only preconditions \
             GMRES (docs/krylov.md)",
        ));
    }
    if !sv.reuse_factorization && sv.linear_solver != LinearSolverKind::Krylov {
        return Err(scene.error(
            "solver.reuse_factorization",
            "false needs linear_solver = \"krylov\": the direct solver factorizes every \
             Newton iteration already (docs/krylov.md)",
        ));
    }
    if sv.linear_solver == LinearSolverKind::Mumps && !cfg!(feature = "mpi") {
        return Err(scene.error(
            "solver.linear_solver",
            "\"mumps\" needs MUMPS and MPI, which this build of talus does not have: build \
             it with `cargo build --release -p talus --features mpi` (docs/distributed.md)",
        ));
    }
    if sv.linear_solver == LinearSolverKind::Mumps
        && cfg!(feature = "mpi")
        && !crate::ranks::launched_by_mpi()
    {
        return Err(scene.error(
            "solver.linear_solver",
            "\"mumps\" runs under mpirun: `mpirun -np N talus run …` (N = 1 included, \
             docs/distributed.md)",
        ));
    }
    if sv.ordering.ordering().is_none() {
        return Err(scene.error(
            "solver.ordering",
            "\"nested_dissection\" needs METIS, which this build of talus does not have: \
             build it with `cargo build --release -p talus --features metis`",
        ));
    }
    Ok(())
}

/// Every `[[pressure]]` and `[[point_load]]` of a FEM scene, finite: before the scales
/// are checked, which would otherwise name the pressure's `value` for a non-finite
/// `gradient`.
pub fn loads<V: SceneVector>(scene: &impl Locate, spec: &SceneSpec<V>) -> Result<(), SceneError> {
    let unit = spec.analysis.geometry.load_unit();
    for (k, p) in spec.pressure.iter().enumerate() {
        pressure(scene, k, p)?;
    }
    for (k, l) in spec.point_load.iter().enumerate() {
        point_load(scene, k, l, unit)?;
    }
    Ok(())
}

/// `pressure[k]`'s value (Pa) and gradient along y (Pa/m), finite: the pressure at height
/// y is `value + gradient · y` (`docs/scenes.md`).
fn pressure<V: SceneVector>(
    scene: &impl Locate,
    k: usize,
    p: &PressureSpec<V>,
) -> Result<(), SceneError> {
    if !p.value.is_finite() {
        return Err(scene.error(
            &format!("pressure[{k}].value"),
            format!("{} Pa must be finite", p.value),
        ));
    }
    match p.gradient {
        Some(g) if !g.is_finite() => Err(scene.error(
            &format!("pressure[{k}].gradient"),
            format!("{g} Pa/m must be finite"),
        )),
        _ => Ok(()),
    }
}

/// `point_load[k]`'s point and force, finite (the force in `unit`, N/m or N).
fn point_load<V: SceneVector>(
    scene: &impl Locate,
    k: usize,
    l: &PointLoadSpec<V>,
    unit: &str,
) -> Result<(), SceneError> {
    let finite = |v: &V| v.as_ref().iter().all(|c| c.is_finite());
    if !finite(&l.point) {
        return Err(scene.error(
            &format!("point_load[{k}].point"),
            format!("{:?} m must be finite", l.point),
        ));
    }
    if !finite(&l.force) {
        return Err(scene.error(
            &format!("point_load[{k}].force"),
            format!("{:?} {unit} must be finite", l.force),
        ));
    }
    Ok(())
}

/// The load programme `ramp` of `field` (`traction[1].ramp`, `gravity_ramp`), if given.
pub fn ramp(
    scene: &impl Locate,
    field: &str,
    points: &Option<Vec<[f64; 2]>>,
) -> Result<Option<Ramp>, SceneError> {
    points
        .as_deref()
        .map(|p| Ramp::try_new(p).map_err(|e| scene.error(field, e.to_string())))
        .transpose()
}

/// A load programme's field path (`traction[0].ramp`) and its points, if given.
pub type RampField<'s> = (String, &'s Option<Vec<[f64; 2]>>);

/// Every load programme of a FEM scene: `gravity_ramp`, `boundary[k].ramp`,
/// `traction[k].ramp`, `pressure[k].ramp`, `point_load[k].ramp`.
pub fn ramps<V: SceneVector>(spec: &SceneSpec<V>) -> Vec<RampField<'_>> {
    let mut ramps = vec![("gravity_ramp".to_string(), &spec.gravity_ramp)];
    let each = |name: &str, k: usize| format!("{name}[{k}].ramp");
    ramps.extend(
        spec.boundary
            .iter()
            .enumerate()
            .map(|(k, b)| (each("boundary", k), &b.ramp)),
    );
    ramps.extend(
        spec.traction
            .iter()
            .enumerate()
            .map(|(k, t)| (each("traction", k), &t.ramp)),
    );
    ramps.extend(
        spec.pressure
            .iter()
            .enumerate()
            .map(|(k, p)| (each("pressure", k), &p.ramp)),
    );
    ramps.extend(
        (spec.point_load.iter().enumerate()).map(|(k, p)| (each("point_load", k), &p.ramp)),
    );
    ramps
}

/// Every load programme of a material point scene: `gravity_ramp`, `prescribed[k].ramp`,
/// `surface_load[k].ramp`.
pub fn mpm_ramps<V: SceneVector>(spec: &MpmSceneSpec<V>) -> Vec<RampField<'_>> {
    let mut ramps = vec![("gravity_ramp".to_string(), &spec.gravity_ramp)];
    ramps.extend(
        (spec.prescribed.iter().enumerate())
            .map(|(k, p)| (format!("prescribed[{k}].ramp"), &p.ramp)),
    );
    ramps.extend(
        (spec.surface_load.iter().enumerate())
            .map(|(k, l)| (format!("surface_load[{k}].ramp"), &l.ramp)),
    );
    ramps
}

/// A warning for each ramp that changes faster than the step `h` (s) within the run's
/// time `(0, end]`: a segment shorter than `h` whose value changes. The run samples a ramp
/// at the step ends `t = n h` only (`docs/scenes.md`, 'Load programmes'), so such a
/// change is taken at once, or missed altogether (a pulse between two step ends). Each
/// warning starts with the field (`traction[0].ramp: ...`). Invalid ramps are left to
/// [`ramp`].
pub fn fast_ramps(ramps: &[RampField<'_>], h: f64, end: f64) -> Vec<String> {
    let mut warnings = Vec::new();
    for (field, points) in ramps {
        let Some(points) = points.as_deref() else {
            continue;
        };
        let fast = points.windows(2).find(|s| {
            let ([t0, f0], [t1, f1]) = (s[0], s[1]);
            t1 - t0 < h && f1 != f0 && t0 < end && t1 > 0.0
        });
        if let Some(s) = fast {
            let ([t0, f0], [t1, f1]) = (s[0], s[1]);
            warnings.push(format!(
                "{field}: goes from {f0} at t = {t0} s to {f1} at t = {t1} s, in {:.3e} s, \
                 less than the step h = {h} s: the run samples the ramp at the step ends only \
                 (t = n h), so it takes this change at once or misses it; give a step of at \
                 most {:.3e} s, or spread the change over at least one step",
                t1 - t0,
                t1 - t0
            ));
        }
    }
    warnings
}
