//! Coulomb friction on the walls, settled by an active set over successive solves of one
//! sub-step: from the states the last stresses predict (`MpmSettings::contact_predictor`:
//! [`update`] applied to the reactions that would hold every friction node at rest), or every
//! node stuck;
//! a node whose tangential reaction exceeds μ times its normal one
//! slides under the force μ R_n; a sliding node whose velocity turns against that force
//! sticks again.
use crate::boundary::NodeCondition;

/// Stick or slide of a node on a friction wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Contact {
    Stick,
    /// Tangential force the wall applies to the body (N/m).
    Slide(f64),
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

/// Updates `contact` of the `friction_nodes` from a solve's reactions and velocities;
/// returns what changed enough to solve again.
pub(crate) fn update(
    conditions: &[NodeCondition],
    friction_nodes: &[usize],
    reaction: &[[f64; 2]],
    velocity: &[[f64; 2]],
    contact: &mut [Contact],
) -> ContactChanges {
    // Slide forces are settled to 1% of the largest friction force the floor can carry:
    // below the uncertainty of μ itself. The fixed point f = μ R_n(f) contracts by about 3
    // per pass.
    let force_scale = friction_nodes
        .iter()
        .filter_map(|&i| {
            let (axis, sign, mu) = conditions[i].friction?;
            Some(mu * (sign * reaction[i][axis]).max(0.0))
        })
        .fold(0.0, f64::max);
    let mut changes = ContactChanges::default();
    for &i in friction_nodes {
        let Some((axis, sign, mu)) = conditions[i].friction else {
            continue;
        };
        let t = 1 - axis;
        let normal = (sign * reaction[i][axis]).max(0.0);
        let next = match contact[i] {
            Contact::Stick if reaction[i][t].abs() > mu * normal => {
                Contact::Slide(mu * normal * reaction[i][t].signum())
            }
            Contact::Stick => Contact::Stick,
            // Friction opposes sliding: a velocity along the force means stick.
            Contact::Slide(f) if velocity[i][t] * f > 0.0 => Contact::Stick,
            Contact::Slide(f) => Contact::Slide(mu * normal * f.signum()),
        };
        match (contact[i], next) {
            (Contact::Slide(a), Contact::Slide(b)) => {
                changes.forces += ((a - b).abs() > 1e-2 * force_scale) as usize
            }
            (Contact::Stick, Contact::Slide(_)) => changes.to_slide += 1,
            (Contact::Slide(_), Contact::Stick) => changes.to_stick += 1,
            (Contact::Stick, Contact::Stick) => {}
        }
        contact[i] = next;
    }
    changes
}
