use talus_bipotential::DruckerPrager;
use talus_fem::{Dimension, Mandel, Model};

use crate::scene::{InitialStressSpec, Locate, SceneError, SceneOf, SceneVector};

/// The initial stress at every Gauss point (Mandel, flat), each checked against its
/// material's yield cone (an elastic point has none). With layers of different densities
/// or under a water table the K₀ procedure's vertical effective stress is the (buoyant,
/// below the table) weight of the elements above the point ([`super::layered_weight`]);
/// else `γ (surface − y)` as for one dry material. The total stress subtracts the pore
/// pressure from the normal components. In 3D (Mandel size 6) the same procedure, y
/// vertical: `σ_xx = σ_zz = K₀ σ'_yy`, no shear; a uniform `stress` has six components.
pub fn initial_stress<const N: usize, const D: usize>(
    scene: &SceneOf<N>,
    model: &Model<D>,
    spec: &InitialStressSpec<[f64; N]>,
) -> Result<Vec<f64>, SceneError>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
    [f64; N]: SceneVector,
{
    // In equilibrium with the gravity of the start, t = 0 (`gravity_ramp` scales it).
    let ramp = crate::scene::check::ramp(scene, "gravity_ramp", &scene.spec.gravity_ramp)?;
    let g = scene.spec.gravity.map(|g| -g[1]).unwrap_or(0.0);
    let ramp0 = ramp.as_ref().map_or(1.0, |r| r.at(0.0));
    let g = ramp.map_or(g, |r| g * r.at(0.0));
    let materials = scene.spec.material.all();
    // Without gravity the density is not needed (and may be absent).
    let gammas: Vec<f64> = materials
        .iter()
        .map(|m| {
            if g == 0.0 {
                0.0
            } else {
                m.density.unwrap_or(0.0) * g
            }
        })
        .collect();
    let points = &model.assembly.gauss_points;
    // The water: its pressure at t = 0 and the buoyant (effective) unit weight below it.
    let water = crate::model::fem::water_table(scene)?;
    let buoyant: Vec<f64> = materials
        .iter()
        .map(|m| {
            let sat = m.saturated_density.or(m.density).unwrap_or(0.0);
            let gamma_w = water.as_ref().map_or(0.0, |w| w.unit_weight * ramp0);
            if g == 0.0 {
                0.0
            } else {
                sat * g - gamma_w
            }
        })
        .collect();
    let layered = gammas.iter().any(|x| *x != gammas[0]);
    let weight = match (spec.k0, spec.surface) {
        (Some(_), Some(surface)) if layered || water.is_some() => Some(super::layered_weight(
            model,
            &gammas,
            water.as_ref().map(|w| (&buoyant[..], w)),
            surface,
        )),
        _ => None,
    };
    let mut sigma = vec![[0.0; D]; points.len()];
    for (m, gamma) in gammas.iter().enumerate() {
        let at: Vec<usize> = (0..points.len())
            .filter(|&p| model.point_material[p] == m)
            .collect();
        if at.is_empty() {
            continue;
        }
        let these: Vec<[f64; N]> = at.iter().map(|&p| points[p]).collect();
        let above: Option<Vec<f64>> = weight.as_ref().map(|w| at.iter().map(|&p| w[p]).collect());
        let values = initial_stress_at(
            scene,
            model.materials[m].drucker_prager(),
            *gamma,
            spec,
            &these,
            above.as_deref(),
        )?;
        for (&p, v) in at.iter().zip(values) {
            sigma[p] = v;
        }
    }
    // The K₀ procedure and the cone act on the effective stress; the total stress carries
    // the pore pressure: σ = σ' − p_w I (tension positive).
    if let Some(w) = &water {
        for (s, &x) in sigma.iter_mut().zip(points) {
            let p = ramp0 * w.pore_pressure(x);
            for c in &mut s[..3] {
                *c -= p;
            }
        }
    }
    Ok(sigma.into_iter().flatten().collect())
}

/// The initial stress (Mandel of size `D`, Pa) of `spec` at each of `points` (m, y
/// vertical; 2 or 3 coordinates): the K₀ procedure ([`k0_stress_at`]) or a uniform
/// `stress` ([`uniform_stress`]). Errors name `initial_stress.*`: neither or both forms, a
/// point above the surface, a state outside the cone.
pub fn initial_stress_at<const D: usize, V: SceneVector>(
    scene: &impl Locate,
    material: Option<&DruckerPrager>,
    gamma: f64,
    spec: &InitialStressSpec<V>,
    points: &[impl AsRef<[f64]>],
    weight_above: Option<&[f64]>,
) -> Result<Vec<[f64; D]>, SceneError> {
    let k0_fields = [
        ("k0", spec.k0.is_some()),
        ("surface", spec.surface.is_some()),
        ("surcharge", spec.surcharge.is_some()),
    ];
    let given: Vec<&str> = k0_fields.iter().filter(|f| f.1).map(|f| f.0).collect();
    match (spec.stress, spec.k0, spec.surface) {
        (Some(_), _, _) if !given.is_empty() => Err(scene.error(
            "initial_stress.stress",
            format!(
                "a uniform `stress` excludes the K₀ procedure, but `{}` is given too",
                given.join("`, `")
            ),
        )),
        (Some(stress), _, _) => {
            let s = uniform_stress(scene, material, stress.as_ref())?;
            Ok(vec![s; points.len()])
        }
        (None, Some(k0), Some(surface)) => k0_stress_at(
            scene,
            material,
            gamma,
            k0,
            surface,
            spec.surcharge.unwrap_or(0.0),
            points,
            weight_above,
        ),
        (None, None, _) => Err(scene.error(
            "initial_stress",
            format!(
                "give either `stress = {}` or the K₀ procedure (`k0`, `surface`, `surcharge`)",
                V::STRESS_FORM
            ),
        )),
        (None, Some(_), None) => Err(scene.error(
            "initial_stress.surface",
            "the K₀ procedure needs the height of the ground surface",
        )),
    }
}

/// A uniform stress's plain components (Pa, tension positive) as the Mandel vector
/// (`docs/conventions.md`, 'Stress space'): 2D's `[σxx, σyy, σxy, σzz]` as
/// `(σxx, σyy, σzz, √2 σxy)`, 3D's `[σxx, σyy, σzz, σyz, σxz, σxy]` as
/// `(σxx, σyy, σzz, √2 σyz, √2 σxz, √2 σxy)`.
pub fn mandel_from_components<const D: usize>(stress: [f64; D]) -> [f64; D] {
    let mut m = stress;
    if D == 4 {
        // 2D gives σxy before σzz.
        m.swap(2, 3);
    }
    for c in &mut m[3..] {
        *c *= std::f64::consts::SQRT_2;
    }
    m
}

/// The uniform initial stress `stress` (plain components, [`mandel_from_components`]; Pa)
/// in Mandel form, refused (naming `initial_stress.stress`) when not finite, not of `D`
/// components or outside the yield cone, with the distance.
pub fn uniform_stress<const D: usize>(
    scene: &impl Locate,
    material: Option<&DruckerPrager>,
    stress: &[f64],
) -> Result<[f64; D], SceneError> {
    let Ok(plain) = <[f64; D]>::try_from(stress) else {
        return Err(scene.error(
            "initial_stress.stress",
            format!(
                "{stress:?} has {} components, the stress of this scene {D}",
                stress.len()
            ),
        ));
    };
    if !stress.iter().all(|s| s.is_finite()) {
        return Err(scene.error(
            "initial_stress.stress",
            format!("{stress:?} Pa must be finite"),
        ));
    }
    let m = mandel_from_components(plain);
    let Some(material) = material else {
        return Ok(m);
    };
    let s = nalgebra::SVector::<f64, D>::from(m);
    let f = material.yield_function(&s);
    if f > 1e-9 * s.norm().max(material.parameters().cohesion) {
        let order = if D == 6 {
            "(σxx, σyy, σzz, σyz, σxz, σxy)"
        } else {
            "(σxx, σyy, σxy, σzz)"
        };
        // f = ‖dev σ‖/k_d + p tan φ − c: f > 0 is how far outside, in Pa of cohesion.
        return Err(scene.error(
            "initial_stress.stress",
            format!(
                "{stress:?} Pa {order} lies outside the yield cone: f = {f:.4e} Pa > 0 \
                 (p = {:.4e} Pa, ‖dev σ‖ = {:.4e} Pa; the cohesion would have to be {:.4e} Pa larger)",
                (s[0] + s[1] + s[2]) / 3.0,
                deviator_norm(&s),
                f
            ),
        ));
    }
    Ok(m)
}

fn deviator_norm<const D: usize>(s: &nalgebra::SVector<f64, D>) -> f64 {
    let p = (s[0] + s[1] + s[2]) / 3.0;
    let normal = (s[0] - p).powi(2) + (s[1] - p).powi(2) + (s[2] - p).powi(2);
    (3..D).fold(normal, |sum, c| sum + s[c].powi(2)).sqrt()
}

/// The K₀ stress (Mandel of size `D`, Pa) at each of `points` (m, y vertical) under a
/// ground of unit weight `gamma = ρ g` (N/m³): `σ_yy = −(surcharge + γ (surface − y))`, or
/// with `weight_above[i]` (Pa) in place of `γ (surface − y)` (layers),
/// `σ_xx = σ_zz = K₀ σ_yy`, no shear. Errors name `initial_stress.*`: a point above the
/// surface, a state outside the cone (of `material`; none for an elastic one).
#[allow(clippy::too_many_arguments)]
pub fn k0_stress_at<const D: usize>(
    scene: &impl Locate,
    material: Option<&DruckerPrager>,
    gamma: f64,
    k0: f64,
    surface: f64,
    surcharge: f64,
    points: &[impl AsRef<[f64]>],
    weight_above: Option<&[f64]>,
) -> Result<Vec<[f64; D]>, SceneError> {
    if !(k0.is_finite() && k0 > 0.0) {
        return Err(scene.error("initial_stress.k0", format!("{k0} must be finite and > 0")));
    }
    if !surface.is_finite() {
        return Err(scene.error("initial_stress.surface", "must be finite"));
    }
    if !(surcharge.is_finite() && surcharge >= 0.0) {
        return Err(scene.error(
            "initial_stress.surcharge",
            format!("{surcharge} Pa must be finite and >= 0"),
        ));
    }
    let mut sigma = Vec::with_capacity(points.len());
    for (i, x) in points.iter().enumerate() {
        let x = x.as_ref();
        let depth = surface - x[1];
        if depth < -1e-9 * surface.abs().max(1.0) {
            let at: Vec<String> = x.iter().map(|c| format!("{c:.4}")).collect();
            return Err(scene.error(
                "initial_stress.surface",
                format!(
                    "point ({}) lies above the surface y = {surface}",
                    at.join(", ")
                ),
            ));
        }
        let vertical = match weight_above {
            Some(w) => -(surcharge + w[i]),
            None => -(surcharge + gamma * depth.max(0.0)),
        };
        let s = nalgebra::SVector::<f64, D>::from_fn(|c, _| match c {
            0 | 2 => k0 * vertical,
            1 => vertical,
            _ => 0.0,
        });
        if !(k0 * vertical).is_finite() {
            // The cone test below cannot judge an infinite stress (its f is NaN).
            return Err(scene.error(
                "initial_stress.k0",
                format!(
                    "K₀ = {k0:e} times σ_yy = {vertical:.4e} Pa at depth {depth:.3} m overflows"
                ),
            ));
        }
        let Some(material) = material else {
            sigma.push(s.into());
            continue;
        };
        let f = material.yield_function(&s);
        if f > 1e-9 * s.norm().max(material.parameters().cohesion) {
            let (lo, hi) = k0_bounds(material);
            return Err(scene.error(
                "initial_stress.k0",
                format!(
                    "K₀ = {k0} puts the point at depth {depth:.3} m outside the yield cone (f = {f:.3e} Pa); \
                     without cohesion the cone admits {lo:.4} ≤ K₀ ≤ {hi:.4} (Jaky's 1 − sin φ = {:.4})",
                    1.0 - material.parameters().friction_angle.to_radians().sin()
                ),
            ));
        }
        sigma.push(s.into());
    }
    Ok(sigma)
}

/// The K₀ for which `(−K₀ s, −s, −K₀ s)` lies in the cone for every depth when c = 0:
/// `|1 − K₀| √(2/3) / k_d ≤ tan φ (1 + 2K₀) / 3` (cohesion only widens the interval).
/// Jaky's `1 − sin φ` falls below it for φ ≳ 36° with the plane-strain fit, because the fit
/// matches Mohr-Coulomb in plastic flow, not in this stress state.
pub fn k0_bounds_without_cohesion(model: &Model) -> (f64, f64) {
    match model.materials.first().and_then(|m| m.drucker_prager()) {
        Some(m) => k0_bounds(m),
        None => (0.0, f64::INFINITY),
    }
}

/// [`k0_bounds_without_cohesion`] of a material.
pub fn k0_bounds(material: &DruckerPrager) -> (f64, f64) {
    let a = (2.0f64 / 3.0).sqrt() / material.k_d();
    let t = material.parameters().friction_angle.to_radians().tan() / 3.0;
    // K₀ ≤ 1: a (1 − K₀) ≤ t (1 + 2K₀); K₀ ≥ 1: a (K₀ − 1) ≤ t (1 + 2K₀).
    let lo = (a - t) / (a + 2.0 * t);
    let hi = if a > 2.0 * t {
        (a + t) / (a - 2.0 * t)
    } else {
        f64::INFINITY
    };
    (lo.max(0.0), hi)
}
