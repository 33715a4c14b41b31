//! Coulomb friction on the walls, settled by an active set over successive solves of one
//! sub-step: from the states the last stresses predict (`MpmSettings::contact_predictor`:
//! [`update`] applied to the reactions that would hold every friction node at rest), or every
//! node stuck;
//! a node whose tangential reaction exceeds μ times its normal one
//! slides under the force μ R_n along its tangential reaction; a sliding node whose
//! velocity turns against that force sticks again. In 3D the tangential reaction and the
//! friction force are vectors of the wall's plane and the test is Coulomb's cone,
//! `‖R_t‖ > μ R_n`; with one tangential component (2D) the norms are absolute values, and
//! the arithmetic is 2D's to the bit.
use crate::boundary::NodeCondition;

/// Stick or slide of a node on a friction wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Contact {
    Stick,
    /// Tangential force the wall applies to the body (N/m in 2D, N in 3D), per component
    /// (0 on the normal one).
    Slide([f64; 3]),
}

/// Passes of the friction active set before the last one is accepted.
pub(crate) const MAX_CONTACT_PASSES: usize = 8;

/// What one update of the friction nodes changed (logged per friction pass).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct ContactChanges {
    /// Nodes that went from stick to slide, and from slide to stick.
    to_slide: usize,
    to_stick: usize,
    /// Sliding nodes whose friction force moved by more than the settling tolerance.
    forces: usize,
}

impl ContactChanges {
    /// Whether any state changed enough to solve again.
    pub(crate) fn any(&self) -> bool {
        self.to_slide + self.to_stick + self.forces > 0
    }
}

/// `‖v‖` over the tangential components `t`: `|v|` for one, so that 2D rounds as before.
fn norm(v: &[f64; 3], t: &[usize]) -> f64 {
    match t {
        [a] => v[*a].abs(),
        _ => t.iter().map(|&a| v[a] * v[a]).sum::<f64>().sqrt(),
    }
}

/// `μ R_n` along the unit vector of `direction` (tangential components `t`): 2D's
/// `μ R_n sign(d)`. A zero 3D direction gives no force.
fn along(magnitude: f64, direction: &[f64; 3], t: &[usize]) -> [f64; 3] {
    let mut f = [0.0; 3];
    match t {
        [a] => f[*a] = magnitude * direction[*a].signum(),
        _ => {
            let n = norm(direction, t);
            if n > 0.0 {
                for &a in t {
                    f[a] = magnitude * (direction[a] / n);
                }
            }
        }
    }
    f
}

/// Updates `contact` of the `friction_nodes` from a solve's reactions and velocities;
/// returns what changed enough to solve again.
pub(crate) fn update<V: std::ops::Index<usize, Output = f64>>(
    conditions: &[NodeCondition],
    friction_nodes: &[usize],
    reaction: &[V],
    velocity: &[V],
    contact: &mut [Contact],
) -> ContactChanges {
    // Slide forces are settled to 1% of the largest friction force the floor can carry:
    // below the uncertainty of μ itself. The fixed point f = μ R_n(f) contracts by about 3
    // per pass.
    let force_scale = friction_nodes
        .iter()
        .filter_map(|&i| {
            let f = conditions[i].friction?;
            Some(f.mu * (f.sign * reaction[i][f.axis]).max(0.0))
        })
        .fold(0.0, f64::max);
    let mut changes = ContactChanges::default();
    for &i in friction_nodes {
        let Some(friction) = conditions[i].friction else {
            continue;
        };
        let t: Vec<usize> = friction.components().collect();
        let mut r_t = [0.0; 3];
        let mut v_t = [0.0; 3];
        for &a in &t {
            r_t[a] = reaction[i][a];
            v_t[a] = velocity[i][a];
        }
        let normal = (friction.sign * reaction[i][friction.axis]).max(0.0);
        let limit = friction.mu * normal;
        let next = match contact[i] {
            Contact::Stick if norm(&r_t, &t) > limit => Contact::Slide(along(limit, &r_t, &t)),
            Contact::Stick => Contact::Stick,
            // Friction opposes sliding: a velocity along the force means stick.
            Contact::Slide(f) if t.iter().map(|&a| v_t[a] * f[a]).sum::<f64>() > 0.0 => {
                Contact::Stick
            }
            Contact::Slide(f) if t.len() > 1 && norm(&f, &t) == 0.0 => {
                Contact::Slide(along(limit, &r_t, &t))
            }
            Contact::Slide(f) => Contact::Slide(along(limit, &f, &t)),
        };
        match (contact[i], next) {
            (Contact::Slide(a), Contact::Slide(b)) => {
                let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
                changes.forces += (norm(&d, &t) > 1e-2 * force_scale) as usize
            }
            (Contact::Stick, Contact::Slide(_)) => changes.to_slide += 1,
            (Contact::Slide(_), Contact::Stick) => changes.to_stick += 1,
            (Contact::Stick, Contact::Stick) => {}
        }
        contact[i] = next;
    }
    changes
}
