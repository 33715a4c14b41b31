//! The prescribed motion of a FEM scene in either dimension: each `[[boundary]]`'s
//! velocity on the dofs it fixes, the condition that owns each prescribed dof (its
//! velocity, ramp and reaction), and the reported boundary's dofs (`[output] reaction`).
use talus_fem::DofMap;

use crate::scene::{Ramp, SceneDocument, SceneError, SceneSpec, SceneVector};

/// What the `[[boundary]]` conditions prescribe, per prescribed dof.
pub(super) struct PrescribedMotion {
    /// Velocity at multiplier 1 (m/s).
    pub velocity: Vec<f64>,
    /// The condition (`boundary[k]`) whose velocity the dof follows: the last in file order
    /// that fixes it; `boundary.len()` for a dof no condition fixes (the axis).
    pub owner: Vec<usize>,
    /// The reported boundary's dofs and their component.
    pub reaction_dofs: Vec<(usize, usize)>,
    /// The component and sign its reaction and displacement are reported along
    /// ([`reaction_direction`]).
    pub reaction_direction: (usize, f64),
    /// The dofs that follow each ramp.
    pub velocity_ramps: Vec<(Ramp, Vec<usize>)>,
}

/// The motion of `scene`'s boundaries on `dofs`: `nodes[k]` the nodes of `boundary[k]`
/// (empty when it does not act), `ramps[k]` its checked ramp; `switched_off`: the reported
/// boundary does not act here (a stage), so that it may hold no dof.
pub(super) fn prescribed_motion<V: SceneVector>(
    scene: &SceneDocument<SceneSpec<V>>,
    nodes: &[Vec<usize>],
    ramps: Vec<Option<Ramp>>,
    dofs: &DofMap,
    switched_off: bool,
) -> Result<PrescribedMotion, SceneError> {
    let spec = &scene.spec;
    // Prescribed velocities: later conditions win where sets overlap.
    let mut velocity = vec![0.0; dofs.n_prescribed()];
    let mut owner = vec![spec.boundary.len(); dofs.n_prescribed()];
    let mut reaction_dofs = Vec::new();
    for (k, (b, nodes)) in spec.boundary.iter().zip(nodes).enumerate() {
        let is_reaction = b.name.is_some() && b.name == spec.output.reaction;
        for &n in nodes {
            for comp in 0..V::DIM {
                let fixed = b.fix.fixes(comp);
                if let (true, Some(j)) = (fixed, dofs.prescribed(n, comp)) {
                    velocity[j] = b.velocity.as_ref()[comp];
                    owner[j] = k;
                    if is_reaction && !reaction_dofs.contains(&(j, comp)) {
                        reaction_dofs.push((j, comp));
                    }
                }
            }
        }
    }
    // A dof follows the ramp of the condition that set its velocity.
    let velocity_ramps: Vec<(Ramp, Vec<usize>)> = ramps
        .into_iter()
        .enumerate()
        .filter_map(|(k, ramp)| {
            let dofs: Vec<usize> = (0..owner.len()).filter(|&j| owner[j] == k).collect();
            ramp.filter(|_| !dofs.is_empty()).map(|r| (r, dofs))
        })
        .collect();
    if let Some(name) = &spec.output.reaction {
        if reaction_dofs.is_empty() && !switched_off {
            return Err(scene.error(
                "output.reaction",
                format!("no boundary named `{name}` with fixed components"),
            ));
        }
    }
    // The reported boundary's velocity on the components it fixes (the last of that name
    // that acts here: a stage's conditions).
    let reported: Option<Vec<f64>> = (spec.boundary.iter().zip(nodes).rev())
        .find(|(b, nodes)| !nodes.is_empty() && b.name.is_some() && b.name == spec.output.reaction)
        .map(|(b, _)| {
            (0..V::DIM)
                .map(|c| {
                    if b.fix.fixes(c) {
                        b.velocity.as_ref()[c]
                    } else {
                        0.0
                    }
                })
                .collect()
        });
    Ok(PrescribedMotion {
        velocity,
        owner,
        reaction_dofs,
        reaction_direction: reaction_direction(reported.as_deref()),
        velocity_ramps,
    })
}

/// The direction a reported boundary's reaction and displacement are measured along, from
/// its prescribed velocity on the components it fixes: the one axis it moves along, in the
/// sense of its motion (a footing pushed down: downward positive; a cavity wall pushed out
/// along x: outward positive); downward (`(1, −1)`) when it does not move, or moves along
/// more than one axis, as a footing's reaction is read.
pub(super) fn reaction_direction(velocity: Option<&[f64]>) -> (usize, f64) {
    let moving: Vec<(usize, f64)> = velocity
        .unwrap_or_default()
        .iter()
        .enumerate()
        .filter(|(_, v)| **v != 0.0)
        .map(|(c, v)| (c, v.signum()))
        .collect();
    match moving[..] {
        [one] => one,
        _ => (1, -1.0),
    }
}

#[cfg(test)]
mod tests {
    use super::reaction_direction;

    /// Along the one axis the boundary moves on, in its sense; downward at rest, with no
    /// reported boundary, or moving along two axes.
    #[test]
    fn the_reported_direction_follows_a_motion_along_one_axis() {
        assert_eq!(reaction_direction(Some(&[0.0, -1e-3])), (1, -1.0));
        assert_eq!(reaction_direction(Some(&[1e-3, 0.0])), (0, 1.0));
        assert_eq!(reaction_direction(Some(&[-2.0, 0.0])), (0, -1.0));
        assert_eq!(reaction_direction(Some(&[0.0, 0.0, 5e-4])), (2, 1.0));
        assert_eq!(reaction_direction(Some(&[0.0, 1e-3])), (1, 1.0));
        assert_eq!(reaction_direction(Some(&[0.0, 0.0])), (1, -1.0));
        assert_eq!(reaction_direction(Some(&[1e-4, -1e-3])), (1, -1.0));
        assert_eq!(reaction_direction(None), (1, -1.0));
    }
}
