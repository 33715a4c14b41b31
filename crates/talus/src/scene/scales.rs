//! A scene against its own scales (`docs/scenes.md`, 'Limits'): the time step against the
//! elastic wave time of the smallest cell and against the prescribed motion, the stresses
//! the scene imposes against the Young modulus, and the caps on steps and halvings. Each
//! refusal names the field, its value and the range that works.
use super::source::Locate;
use super::{InitialStressSpec, MaterialSpec, SceneError, SceneVector, StageSpec, TimeSpec};

/// `h / t_w` (t_w = Δx √(ρ/E), the elastic wave time across the smallest cell) must lie in
/// `[MIN_STEP_RATIO, MAX_STEP_RATIO]`. Above, `h² B M⁻¹ Bᵀ` exceeds `S` in `W` by
/// `(h/t_w)² > 1e16`: the elastic compliance is below round-off. Below, `S` exceeds the
/// inertia term by as much: a step changes nothing the arithmetic can hold.
pub const MAX_STEP_RATIO: f64 = 1e8;
pub const MIN_STEP_RATIO: f64 = 1e-8;
/// The largest stress of the scene over E: at least `MIN_STRESS_RATIO` counting the
/// cohesion (below, elastic strains sit under the round-off of the stresses), at most
/// `MAX_STRESS_RATIO` counting the loads, weight and initial stress (above, elastic strains
/// exceed 100%, far from small strains).
pub const MIN_STRESS_RATIO: f64 = 1e-12;
pub const MAX_STRESS_RATIO: f64 = 1.0;
/// The cohesion over E at most: a cohesion far above every stress keeps a material
/// elastic (the elastic verification cases use 2e4 E); beyond, the cone's apex outgrows
/// the arithmetic.
pub const MAX_COHESION_RATIO: f64 = 1e6;
/// At most this many steps (`time.steps`, or the stages' `steps` in all).
pub const MAX_STEPS: usize = 100_000_000;
/// At most this many nested halvings (`solver.max_step_halvings`): a step may then take
/// up to 2¹⁶ sub-steps.
pub const MAX_STEP_HALVINGS: usize = 16;

/// The lengths of a built model.
#[derive(Debug, Clone, PartialEq)]
pub struct Scales {
    /// The smallest cell: element (√(2A) of the smallest triangle) or grid spacing (m).
    pub cell: f64,
    /// How far a prescribed boundary may move in one step (m): the body's smallest side
    /// (FEM, small strains) or one grid cell (MPM: particles cross at most a cell).
    pub max_step_motion: f64,
    /// What `max_step_motion` is, in words.
    pub motion_limit: &'static str,
    /// Whether inertia is physical (dynamic analysis): then `h` is checked against t_w.
    pub dynamic: bool,
}

/// What a scene imposes, gathered by its method's model for [`check_scales`]; `V` the
/// scene's vectors (its initial stress's size).
#[derive(Debug, Clone, PartialEq)]
pub struct Imposed<'a, V: SceneVector = [f64; 2]> {
    /// Each material with its field (`material` or `material[k]`): each is checked as if
    /// it filled the body.
    pub materials: Vec<(String, &'a MaterialSpec)>,
    pub time: &'a TimeSpec,
    /// `|g|` (m/s²), [`norm`] of the scene's gravity.
    pub gravity: Option<f64>,
    /// The body's lowest and highest y (m).
    pub heights: [f64; 2],
    pub initial_stress: Option<&'a InitialStressSpec<V>>,
    /// Each load's field and its largest stress over its ramp ([`ramp_max`]) (Pa).
    pub loads: Vec<(String, f64)>,
    /// Each prescribed motion's field and its largest speed over its ramp (m/s).
    pub speeds: Vec<(String, f64)>,
}

/// The largest |multiplier| of a ramp (1 without one).
pub fn ramp_max(ramp: &Option<Vec<[f64; 2]>>) -> f64 {
    ramp.as_ref()
        .map_or(1.0, |r| r.iter().fold(0.0, |m, p| m.max(p[1].abs())))
}

/// Steps and halvings within their caps.
pub fn caps(scene: &impl Locate, time: &TimeSpec, halvings: usize) -> Result<(), SceneError> {
    if time.steps > MAX_STEPS {
        return Err(scene.error(
            "time.steps",
            format!(
                "{} is more than the {MAX_STEPS} steps a run may take",
                time.steps
            ),
        ));
    }
    if halvings > MAX_STEP_HALVINGS {
        return Err(scene.error(
            "solver.max_step_halvings",
            format!(
                "{halvings} is more than {MAX_STEP_HALVINGS} (a step would split into up to \
                 2^{halvings} sub-steps); use 0 to {MAX_STEP_HALVINGS}"
            ),
        ));
    }
    Ok(())
}

/// The stages' steps within [`MAX_STEPS`] in all: the first stage that takes the run past
/// it is named (`stage[k].steps`).
pub fn stage_steps_cap(scene: &impl Locate, stages: &[StageSpec]) -> Result<(), SceneError> {
    // u128: the sum of any usize steps fits.
    let mut total = 0u128;
    for (k, s) in stages.iter().enumerate() {
        total += s.steps as u128;
        if total > MAX_STEPS as u128 {
            return Err(scene.error(
                &format!("stage[{k}].steps"),
                format!(
                    "{} brings the stages' steps to {total}, more than the {MAX_STEPS} steps \
                     a run may take",
                    s.steps
                ),
            ));
        }
    }
    Ok(())
}

/// The stresses a scene imposes (Pa), with their fields: cohesion, the weight of the body
/// (from `bottom` to `top`, m), the initial stress (the K₀ procedure's at `bottom`, whose
/// `surface` may lie far above the body). The caller adds its loads.
fn material_stresses<V: SceneVector>(
    field: &str,
    m: &MaterialSpec,
    gravity: Option<f64>,
    [bottom, top]: [f64; 2],
    initial: Option<&InitialStressSpec<V>>,
) -> Vec<(String, f64)> {
    let depth = top - bottom;
    let mut s = vec![(format!("{field}.cohesion"), m.cohesion().abs())];
    if let (Some(g), Some(rho)) = (gravity, m.density) {
        // Named as the user reads it: the weight of the body's height, from the density.
        s.push((
            format!("ρ |g| H from {field}.density, H = {depth:.4e} m"),
            rho * g * depth,
        ));
    }
    if let Some(i) = initial {
        if let Some(q) = i.surcharge {
            s.push(("initial_stress.surcharge".into(), q.abs()));
        }
        // A K₀ surface above the body adds the weight of the ground between them, which the
        // body's own height does not count: σ_yy at the lowest point (infinite on overflow).
        if let (Some(_), Some(surface)) = (i.k0, i.surface) {
            if surface > top {
                let weight = match (gravity, m.density) {
                    (Some(g), Some(rho)) => rho * g * (surface - bottom),
                    _ => 0.0,
                };
                s.push((
                    "initial_stress.surface".into(),
                    i.surcharge.unwrap_or(0.0).abs() + weight,
                ));
            }
        }
        if let Some(st) = i.stress {
            let largest = (st.as_ref().iter()).fold(0.0f64, |a, v| a.max(v.abs()));
            s.push(("initial_stress.stress".into(), largest));
        }
    }
    s
}

/// The scene against its own scales, FEM and MPM alike: `h` against the wave time of the
/// smallest cell and the fastest prescribed motion, the stresses against E.
pub fn check_scales<V: SceneVector>(
    scene: &impl Locate,
    imposed: &Imposed<V>,
    s: &Scales,
) -> Result<(), SceneError> {
    for (field, m) in &imposed.materials {
        check_material(scene, field, m, imposed, s)?;
    }
    Ok(())
}

/// [`check_scales`] for the material `m` at `prefix` (`material` or `material[k]`).
fn check_material<V: SceneVector>(
    scene: &impl Locate,
    prefix: &str,
    m: &MaterialSpec,
    imposed: &Imposed<V>,
    s: &Scales,
) -> Result<(), SceneError> {
    let time = imposed.time;
    let cohesion_field = format!("{prefix}.cohesion");
    let mut stresses = material_stresses(
        prefix,
        m,
        imposed.gravity,
        imposed.heights,
        imposed.initial_stress,
    );
    stresses.extend(imposed.loads.iter().cloned());
    let speed = imposed
        .speeds
        .iter()
        .filter(|(_, v)| *v > 0.0)
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let e = m.young_modulus;
    let h = time.step;
    let largest = |cohesion: bool| {
        stresses
            .iter()
            // An infinite stress is an overflow to refuse, not a value to skip.
            .filter(|(f, v)| !v.is_nan() && (cohesion || *f != cohesion_field))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .filter(|(_, v)| *v > 0.0)
    };
    let refuse = |field: &str, sigma: f64, bound: f64, low: bool| {
        let (lo, hi) = if low {
            (MIN_STRESS_RATIO, f64::INFINITY)
        } else {
            (0.0, bound)
        };
        scene.error(
            &format!("{prefix}.young_modulus"),
            format!(
                "{e:e} Pa against {sigma:.4e} Pa ({field}): their ratio {:.3e} must be {} \
                 {:e}, i.e. E {} {:.3e} Pa",
                sigma / e,
                if low { "at least" } else { "at most" },
                if low { lo } else { hi },
                if low { "at most" } else { "at least" },
                if low { sigma / lo } else { sigma / hi }
            ),
        )
    };
    // The lower bound counts the cohesion; the upper one does not: a cohesion far above
    // E is the usual way to keep a material elastic, capped where it would overflow.
    if let Some((field, sigma)) = largest(true) {
        if !(sigma / e >= MIN_STRESS_RATIO) {
            return Err(refuse(field, *sigma, MIN_STRESS_RATIO, true));
        }
    }
    if let Some((field, sigma)) = largest(false) {
        if sigma.is_infinite() {
            return Err(scene.error(
                field,
                "overflows: the stress it imposes (a load times its largest ramp multiplier; \
                 the density times |gravity| times a depth) exceeds 1.8e308 Pa",
            ));
        }
        if !(sigma / e <= MAX_STRESS_RATIO) {
            return Err(refuse(field, *sigma, MAX_STRESS_RATIO, false));
        }
    }
    if !(m.cohesion() / e <= MAX_COHESION_RATIO) {
        return Err(scene.error(
            &cohesion_field,
            format!(
                "{:e} Pa is {:.3e} times {prefix}.young_modulus ({e:e} Pa): at most \
                 {MAX_COHESION_RATIO:e} (a material that never yields needs no more)",
                m.cohesion(),
                m.cohesion() / e
            ),
        ));
    }
    if s.dynamic {
        if let Some(rho) = m.density {
            let wave = s.cell * (rho / e).sqrt();
            let ratio = h / wave;
            if !(ratio.is_finite() && (MIN_STEP_RATIO..=MAX_STEP_RATIO).contains(&ratio)) {
                return Err(scene.error(
                    "time.step",
                    format!(
                        "{h:e} s is {ratio:.3e} times the elastic wave time across the smallest \
                         cell ({:.3e} m · √(ρ/E) = {wave:.3e} s, from {prefix}.density and \
                         {prefix}.young_modulus): use h from {:.3e} to {:.3e} s",
                        s.cell,
                        MIN_STEP_RATIO * wave,
                        MAX_STEP_RATIO * wave
                    ),
                ));
            }
        }
    }
    if let Some((field, v)) = speed {
        let motion = h * v;
        if !(motion <= s.max_step_motion) {
            return Err(scene.error(
                "time.step",
                format!(
                    "{h:e} s moves {field} ({v:e} m/s) by {motion:.3e} m per step, more than \
                     {} ({:.3e} m): use h ≤ {:.3e} s",
                    s.motion_limit,
                    s.max_step_motion,
                    s.max_step_motion / v
                ),
            ));
        }
    }
    Ok(())
}

/// The Euclidean norm of a vector of the scene (a force, a velocity, gravity): in 2D
/// `x.hypot(y)`, as every 2D check and summary always computed it.
pub fn norm(v: &[f64]) -> f64 {
    match v {
        [x, y] => x.hypot(*y),
        _ => v.iter().map(|c| c * c).sum::<f64>().sqrt(),
    }
}
