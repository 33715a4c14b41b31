//! The K₀ procedure in layers: the vertical stress at a point is the weight of the ground
//! above it, `∫ γ(x, s) ds` from the point up to the surface, which with a unit weight per
//! element is a sum over the elements the vertical through the point crosses (triangles
//! in 2D, tetrahedra in 3D; y is vertical in both).
use talus_fem::{Dimension, ElementMesh, Mandel, Model};

/// The interval of y (m) where the vertical line at `x` crosses the straight triangle
/// `t`, if it does.
fn crossing(t: [[f64; 2]; 3], x: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
        let (x0, x1) = (a[0].min(b[0]), a[0].max(b[0]));
        if x < x0 || x > x1 {
            continue;
        }
        let ys = if x1 > x0 {
            let y = a[1] + (b[1] - a[1]) * (x - a[0]) / (b[0] - a[0]);
            [y, y]
        } else {
            [a[1], b[1]] // a vertical edge on the line itself
        };
        for y in ys {
            lo = lo.min(y);
            hi = hi.max(y);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// The interval of y (m) where the vertical line through `(x, z)` crosses the straight
/// tetrahedron `t`, if it does: along the line each barycentric coordinate is affine in y,
/// `λ_i(y) = a_i + b_i y` (a ratio of signed volumes), and the line is inside where all
/// four are ≥ 0.
fn crossing_tetrahedron(t: [[f64; 3]; 4], x: f64, z: f64) -> Option<(f64, f64)> {
    let volume = |p: [[f64; 3]; 4]| {
        let e = |k: usize| [0, 1, 2].map(|c| p[k][c] - p[0][c]);
        let (u, v, w) = (e(1), e(2), e(3));
        u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0])
    };
    let whole = volume(t);
    if whole == 0.0 {
        return None;
    }
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for i in 0..4 {
        let at = |y: f64| {
            let mut p = t;
            p[i] = [x, y, z];
            volume(p) / whole
        };
        let a = at(0.0);
        let b = at(1.0) - a;
        if b > 0.0 {
            lo = lo.max(-a / b);
        } else if b < 0.0 {
            hi = hi.min(-a / b);
        } else if a < 0.0 {
            return None;
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// Per Gauss point, the weight (Pa) of the elements above it up to `surface` (m), each with
/// the unit weight `gammas[m]` (N/m³) of its material `m`, and below the water table
/// `below = (buoyant, table)` the buoyant one `buoyant[m]` (`γ_sat − γ_w`: the effective
/// weight): exact for straight-sided elements. The ground between the mesh's top and a
/// higher `surface` weighs nothing here (a surcharge stands for it).
pub fn layered_weight<const N: usize, const D: usize>(
    model: &Model<D>,
    gammas: &[f64],
    below: Option<(&[f64], &crate::scene::WaterTable)>,
    surface: f64,
) -> Vec<f64>
where
    Mandel<D>: Dimension<Point = [f64; N]>,
{
    let nodes = model.mesh.node_positions();
    let asm = &model.assembly;
    let n_e = model.mesh.elements().len();
    // Each element's corners (they come first in P1 and P2 elements alike).
    let corners: Vec<Vec<[f64; N]>> = (model.mesh.elements().iter())
        .map(|e| e[..N + 1].iter().map(|&n| nodes[n]).collect())
        .collect();
    let crossing_at = |e: usize, p: &[f64; N]| match corners[e][..] {
        [a, b, c] if N == 2 => crossing([a, b, c].map(|q| [q[0], q[1]]), p[0]),
        [a, b, c, d] => crossing_tetrahedron([a, b, c, d].map(|q| [q[0], q[1], q[2]]), p[0], p[2]),
        _ => None,
    };
    // Each element's material: that of its points.
    let mut material = vec![0; n_e];
    for (p, &e) in asm.gauss_element.iter().enumerate() {
        material[e] = model.point_material[p];
    }
    // Elements binned by their x-range, so that a vertical meets only its bin's elements.
    let (x0, x1) = corners
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p[0]), b.max(p[0]))
        });
    let bins = ((n_e as f64).sqrt() as usize).max(1);
    let width = (x1 - x0).max(f64::MIN_POSITIVE) / bins as f64;
    let bin = |x: f64| (((x - x0) / width) as usize).min(bins - 1);
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); bins];
    for (e, t) in corners.iter().enumerate() {
        let lo = t.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min);
        let hi = t.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max);
        for b in bin(lo)..=bin(hi) {
            members[b].push(e);
        }
    }
    asm.gauss_points
        .iter()
        .map(|p| {
            let (x, y) = (p[0], p[1]);
            members[bin(x)]
                .iter()
                .filter_map(|&e| {
                    let (lo, hi) = crossing_at(e, p)?;
                    let (lo, hi) = (lo.max(y), hi.min(surface));
                    let m = material[e];
                    Some(match below {
                        None => gammas[m] * (hi - lo).max(0.0),
                        Some((buoyant, table)) => {
                            let h = table.height(x);
                            buoyant[m] * (hi.min(h) - lo).max(0.0)
                                + gammas[m] * (hi - lo.max(h)).max(0.0)
                        }
                    })
                })
                .sum()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{crossing, crossing_tetrahedron};

    #[test]
    fn a_vertical_crosses_a_triangle_between_its_edges() {
        let t = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]];
        assert_eq!(crossing(t, 0.5), Some((0.0, 1.5)));
        assert_eq!(crossing(t, 2.5), None);
        assert_eq!(crossing(t, 0.0), Some((0.0, 2.0)));
    }

    #[test]
    fn a_vertical_crosses_a_tetrahedron_between_its_faces() {
        let t = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.0, 0.0, 2.0],
        ];
        // Inside where x + y + z ≤ 2 above y = 0: y from 0 to 2 − x − z.
        let (lo, hi) = crossing_tetrahedron(t, 0.5, 0.25).unwrap();
        assert!(lo.abs() < 1e-15 && (hi - 1.25).abs() < 1e-15, "{lo} {hi}");
        assert_eq!(crossing_tetrahedron(t, 1.5, 1.0), None);
        assert_eq!(crossing_tetrahedron(t, -0.1, 0.5), None);
        let mirrored = [t[0], t[2], t[1], t[3]];
        let (lo, hi) = crossing_tetrahedron(mirrored, 0.5, 0.25).unwrap();
        assert!(lo.abs() < 1e-15 && (hi - 1.25).abs() < 1e-15, "{lo} {hi}");
    }
}
