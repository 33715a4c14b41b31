//! Coulomb friction on the walls, settled by an active set over successive solves of one
//! sub-step: from the states the last stresses predict ([`predict`]), or every node stuck;
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

/// The contact states a sub-step's first solve starts from (`MpmSettings::contact_predictor`):
/// the rule of [`update`] applied to the reactions the last stresses `σₙ` would need to hold
/// every friction node at rest, `R = M (0 − vₙ)/h + Bᵀσₙ − f` (the stress predictor's own
/// reactions). A node under a body that slides needs more than μ Rₙ to stop and starts
/// sliding; one at rest, or where σₙ presses little, starts stuck. The passes then settle the
/// states as before: only their start changes.
pub(crate) fn predict(
    conditions: &[NodeCondition],
    friction_nodes: &[usize],
    stuck_reaction: &[[f64; 2]],
    velocity: &[[f64; 2]],
    contact: &mut [Contact],
) {
    for &i in friction_nodes {
        contact[i] = Contact::Stick;
    }
    update(
        conditions,
        friction_nodes,
        stuck_reaction,
        velocity,
        contact,
    );
}

/// What one update of the friction nodes changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ContactChanges {
    /// Nodes that went from stick to slide, and from slide to stick.
    pub to_slide: usize,
    pub to_stick: usize,
    /// Sliding nodes whose friction force moved by more than the settling tolerance.
    pub forces: usize,
}

impl ContactChanges {
    /// Whether any state changed enough to solve again.
    pub fn any(&self) -> bool {
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
