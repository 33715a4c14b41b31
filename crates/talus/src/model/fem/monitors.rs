//! `[[monitor]]` on a finite-element model: the node nearest to each point, whose
//! displacement and velocity are recorded.
use crate::scene::{Scene, SceneError};

use super::{Model, State};

/// The monitored nodes, in the scene's order.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeMonitors {
    /// `(field, name)` of each monitor.
    pub names: Vec<(String, String)>,
    pub nodes: Vec<usize>,
}

impl NodeMonitors {
    /// Each point must lie in the mesh (in a triangle through its corner nodes, or on a
    /// node); its node is the nearest one (the first of equally near ones).
    pub fn new(scene: &Scene, model: &Model) -> Result<Self, SceneError> {
        let mesh = &model.mesh;
        let size = mesh
            .nodes
            .iter()
            .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()))
            .max(1.0);
        let tol = 1e-9 * size;
        let mut monitors = Self {
            names: Vec::new(),
            nodes: Vec::new(),
        };
        for (k, m) in scene.spec.monitor.iter().enumerate() {
            let field = format!("monitor[{k}].point");
            let x = m.point;
            if !x.iter().all(|v| v.is_finite()) {
                return Err(scene.error(&field, format!("{x:?} m must be finite")));
            }
            let distance = |n: &[f64; 2]| (n[0] - x[0]).hypot(n[1] - x[1]);
            let node = (0..mesh.nodes.len())
                .min_by(|&a, &b| distance(&mesh.nodes[a]).total_cmp(&distance(&mesh.nodes[b])))
                .ok_or_else(|| scene.error(&field, "the mesh has no node"))?;
            let inside = distance(&mesh.nodes[node]) <= tol
                || mesh.triangles.iter().any(|t| {
                    in_triangle(
                        x,
                        [mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]]],
                        tol,
                    )
                });
            if !inside {
                return Err(scene.error(
                    &field,
                    format!("({}, {}) m is outside the mesh", x[0], x[1]),
                ));
            }
            monitors
                .names
                .push((format!("monitor[{k}].name"), m.name.clone()));
            monitors.nodes.push(node);
        }
        Ok(monitors)
    }

    /// `[ux, uy, vx, vy]` of each monitored node.
    pub fn values(&self, model: &Model, state: &State) -> Vec<Option<[f64; 4]>> {
        let dofs = model.assembly.dofs();
        let velocity = |n: usize, c: usize| {
            dofs.free(n, c)
                .map(|j| state.velocity_free[j])
                .or_else(|| dofs.prescribed(n, c).map(|j| state.velocity_prescribed[j]))
                .unwrap_or(0.0)
        };
        self.nodes
            .iter()
            .map(|&n| {
                let u = state.displacement[n];
                Some([u[0], u[1], velocity(n, 0), velocity(n, 1)])
            })
            .collect()
    }
}

/// Whether `x` lies in the triangle `t` (either orientation), within `tol` (m).
fn in_triangle(x: [f64; 2], t: [[f64; 2]; 3], tol: f64) -> bool {
    let side = |a: [f64; 2], b: [f64; 2]| {
        let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
        ((x[0] - a[0]) * ey - (x[1] - a[1]) * ex) / ex.hypot(ey).max(f64::MIN_POSITIVE)
    };
    let d = [side(t[0], t[1]), side(t[1], t[2]), side(t[2], t[0])];
    d.iter().all(|&v| v <= tol) || d.iter().all(|&v| v >= -tol)
}

#[cfg(test)]
mod tests {
    use super::in_triangle;

    #[test]
    fn points_in_and_out_of_a_triangle() {
        let t = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(in_triangle([0.2, 0.2], t, 1e-12));
        assert!(in_triangle([0.5, 0.5], t, 1e-12), "on the hypotenuse");
        assert!(!in_triangle([0.6, 0.6], t, 1e-12));
        assert!(!in_triangle([-0.1, 0.5], t, 1e-12));
        let clockwise = [t[0], t[2], t[1]];
        assert!(in_triangle([0.2, 0.2], clockwise, 1e-12));
    }
}
