//! Construction in stages against path independence (`docs/scenes.md`, 'Stages'):
//! associative perfect plasticity has a unique limit load (the bound theorems of limit
//! analysis, e.g. Chen 1975, ch. 2), so `scenes/cut_in_lifts.toml`, dug in three lifts
//! from K₀, and the same final geometry loaded by gravity in one stage must have one
//! factor of safety.
use std::time::Instant;

use super::{case_dir, CaseResult, Check};
use crate::run::fem::run_scene;
use crate::run::RunOptions;
use crate::scene::Scene;

/// The scene's text.
pub const CUT_IN_LIFTS: &str = include_str!("../../../../../scenes/cut_in_lifts.toml");

/// `scenes/cut_in_lifts.toml`, and the same cut dug at once: its lifts never there,
/// gravity ramped on over 4 steps (K₀ would load the cut's floor with the soil above it).
pub fn cut_scenes() -> Result<(Scene, Scene), String> {
    let lifts = Scene::parse(CUT_IN_LIFTS, None).map_err(|e| e.to_string())?;
    let cut = |from: &str, to: &str| -> Result<(usize, usize), String> {
        let text = CUT_IN_LIFTS;
        match (text.find(from), text.find(to)) {
            (Some(a), Some(b)) if a < b => Ok((a, b)),
            _ => Err(format!(
                "scenes/cut_in_lifts.toml has no {from} before {to}"
            )),
        }
    };
    let (k0, analysis) = cut("[initial_stress]", "[analysis]")?;
    let (stages, stability) = cut("[[stage]]", "[stability]")?;
    let once = format!(
        "{}{}[[stage]]\nname = \"cut\"\nsteps = 4\n\
         deactivate = [\"lift 1\", \"lift 2\", \"lift 3\"]\nfactor_of_safety = true\n\n{}",
        &CUT_IN_LIFTS[..k0],
        &CUT_IN_LIFTS[analysis..stages],
        &CUT_IN_LIFTS[stability..]
    )
    .replace(
        "gravity = [0.0, -10.0]\n",
        "gravity = [0.0, -10.0]\ngravity_ramp = [[0.0, 0.0], [4.0, 1.0]]\n",
    );
    let once = Scene::parse(&once, None).map_err(|e| e.to_string())?;
    Ok((lifts, once))
}

/// The last stage's factor of safety of a staged scene run into `out`.
pub fn staged_factor(scene: &Scene, out: &std::path::Path) -> Option<(f64, [f64; 2])> {
    run_scene(scene, &RunOptions::new(out)).ok()?;
    let text = std::fs::read_to_string(out.join("summary.json")).ok()?;
    let summary: crate::output::Summary = serde_json::from_str(&text).ok()?;
    let f = summary.stages.last()?.factor_of_safety.as_ref()?;
    Some((f.value?, [f.bracket[0]?, f.bracket[1]?]))
}

/// The cut in lifts against the cut at once: their factors of safety agree to the
/// bracket's tolerance.
pub fn cut_in_lifts_case() -> Vec<CaseResult> {
    let start = Instant::now();
    let factors = cut_scenes().ok().and_then(|(lifts, once)| {
        Some((
            staged_factor(&lifts, &case_dir("cut-lifts"))?,
            staged_factor(&once, &case_dir("cut-once"))?,
        ))
    });
    let (computed, reference) = match factors {
        Some(((a, _), (b, _))) => (a, b),
        None => (f64::NAN, f64::NAN),
    };
    vec![CaseResult {
        case: "cut_in_three_lifts_equals_cut_at_once".into(),
        quantity: "F in lifts (reference: F of the cut dug at once; scenes/cut_in_lifts.toml)"
            .into(),
        reference,
        computed,
        tolerance: 0.005,
        check: Check::Relative,
        seconds: start.elapsed().as_secs_f64(),
        source: "uniqueness of the limit load of associative perfect plasticity \
                 (Chen 1975, Limit Analysis and Soil Plasticity, ch. 2)"
            .into(),
    }]
}
