//! `[[monitor]]` on a finite-element model, 2D or 3D: the node nearest to each point,
//! whose displacement and velocity are recorded.
use talus_fem::{Dimension, ElementMesh, Mandel, Model, State};

use crate::scene::{SceneError, SceneOf, SceneVector};

/// The monitored nodes, in the scene's order.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeMonitors {
    /// `(field, name)` of each monitor.
    pub names: Vec<(String, String)>,
    pub nodes: Vec<usize>,
}

impl NodeMonitors {
    /// Each point must lie in the mesh (in an element through its corner nodes, or on a
    /// node); its node is the nearest one (the first of equally near ones).
    pub fn new<const N: usize, const D: usize>(
        scene: &SceneOf<N>,
        model: &Model<D>,
    ) -> Result<Self, SceneError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
        [f64; N]: SceneVector,
    {
        let nodes = model.mesh.node_positions();
        let size = (nodes.iter().flatten())
            .fold(0.0f64, |m, c| m.max(c.abs()))
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
            let distance = |n: &[f64; N]| distance(n, &x);
            let node = (0..nodes.len())
                .min_by(|&a, &b| distance(&nodes[a]).total_cmp(&distance(&nodes[b])))
                .ok_or_else(|| scene.error(&field, "the mesh has no node"))?;
            // Corner nodes come first in every element (P1 and P2, triangles and tetrahedra).
            let inside = distance(&nodes[node]) <= tol
                || (model.mesh.elements().iter()).any(|e| {
                    let corners: Vec<[f64; N]> = e[..N + 1].iter().map(|&n| nodes[n]).collect();
                    in_simplex(&x, &corners, tol)
                });
            if !inside {
                let at: Vec<String> = x.iter().map(|c| c.to_string()).collect();
                return Err(
                    scene.error(&field, format!("({}) m is outside the mesh", at.join(", ")))
                );
            }
            monitors
                .names
                .push((format!("monitor[{k}].name"), m.name.clone()));
            monitors.nodes.push(node);
        }
        Ok(monitors)
    }

    /// The node of the `[[monitor]]` named `name` (`[stability] monitor`), refused naming
    /// `stability.monitor` with the scene's monitors when there is none.
    pub fn node_named<const N: usize, const D: usize>(
        scene: &SceneOf<N>,
        model: &Model<D>,
        name: &str,
    ) -> Result<usize, SceneError>
    where
        Mandel<D>: Dimension<Point = [f64; N]>,
        [f64; N]: SceneVector,
    {
        let monitors = Self::new(scene, model)?;
        let k = (monitors.names.iter())
            .position(|(_, n)| n == name)
            .ok_or_else(|| {
                let known: Vec<&str> = monitors.names.iter().map(|(_, n)| n.as_str()).collect();
                scene.error(
                    "stability.monitor",
                    format!(
                        "\"{name}\" names no [[monitor]] (the scene has: {})",
                        if known.is_empty() {
                            "none".into()
                        } else {
                            known.join(", ")
                        }
                    ),
                )
            })?;
        Ok(monitors.nodes[k])
    }

    /// `[ux, uy, vx, vy]` of each monitored node (3D: `[ux, uy, uz, vx, vy, vz]`).
    pub fn values<const D: usize>(
        &self,
        model: &Model<D>,
        state: &State<D>,
    ) -> Vec<Option<Vec<f64>>>
    where
        Mandel<D>: Dimension,
    {
        let dofs = model.assembly.dofs();
        let velocity = |n: usize, c: usize| {
            dofs.free(n, c)
                .map(|j| state.velocity_free[j])
                .or_else(|| dofs.prescribed(n, c).map(|j| state.velocity_prescribed[j]))
                .unwrap_or(0.0)
        };
        let components = <Mandel<D> as Dimension>::COMPONENTS;
        self.nodes
            .iter()
            .map(|&n| {
                let u = state.displacement[n].as_ref();
                Some(
                    u.iter()
                        .copied()
                        .chain((0..components).map(|c| velocity(n, c)))
                        .collect(),
                )
            })
            .collect()
    }
}

fn distance<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    match N {
        2 => (a[0] - b[0]).hypot(a[1] - b[1]),
        _ => a
            .iter()
            .zip(b)
            .map(|(p, q)| (p - q) * (p - q))
            .sum::<f64>()
            .sqrt(),
    }
}

/// Whether `x` lies in the triangle or tetrahedron of `corners` (either orientation),
/// within `tol` (m) of each side.
fn in_simplex<const N: usize>(x: &[f64; N], corners: &[[f64; N]], tol: f64) -> bool {
    match (x.as_slice(), corners) {
        ([x0, x1], [a, b, c]) => in_triangle([*x0, *x1], [a, b, c].map(|p| [p[0], p[1]]), tol),
        ([..], [a, b, c, d]) if N == 3 => {
            let p = |q: &[f64; N]| [q[0], q[1], q[2]];
            in_tetrahedron([x[0], x[1], x[2]], [p(a), p(b), p(c), p(d)], tol)
        }
        _ => false,
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

/// Whether `x` lies in the tetrahedron `t` (either orientation), within `tol` (m): its
/// signed distances to the four face planes, each face's normal taken towards the
/// opposite corner, are all ≥ −tol.
fn in_tetrahedron(x: [f64; 3], t: [[f64; 3]; 4], tol: f64) -> bool {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    (0..4).all(|k| {
        let [a, b, c] = [t[(k + 1) % 4], t[(k + 2) % 4], t[(k + 3) % 4]];
        let n = cross(sub(b, a), sub(c, a));
        let norm = dot(n, n).sqrt().max(f64::MIN_POSITIVE);
        let towards = dot(n, sub(t[k], a)).signum();
        towards * dot(n, sub(x, a)) / norm >= -tol
    })
}

#[cfg(test)]
mod tests {
    use super::{in_tetrahedron, in_triangle};

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

    #[test]
    fn points_in_and_out_of_a_tetrahedron() {
        let t = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        assert!(in_tetrahedron([0.1, 0.2, 0.3], t, 1e-12));
        assert!(
            in_tetrahedron([1.0 / 3.0; 3], t, 1e-12),
            "on the slanted face"
        );
        assert!(
            in_tetrahedron([0.0, 0.5, 0.5], t, 1e-12),
            "on the face x = 0"
        );
        assert!(!in_tetrahedron([0.4, 0.4, 0.4], t, 1e-12));
        assert!(!in_tetrahedron([-0.01, 0.2, 0.2], t, 1e-12));
        let mirrored = [t[0], t[2], t[1], t[3]];
        assert!(in_tetrahedron([0.1, 0.2, 0.3], mirrored, 1e-12));
        assert!(!in_tetrahedron([0.4, 0.4, 0.4], mirrored, 1e-12));
    }
}
