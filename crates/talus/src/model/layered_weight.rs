//! The K₀ procedure in layers: the vertical stress at a point is the weight of the ground
//! above it, `∫ γ(x, s) ds` from the point up to the surface, which with a unit weight per
//! element is a sum over the elements the vertical through the point crosses.
use talus_fem::Model;

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

/// Per Gauss point, the weight (Pa) of the elements above it up to `surface` (m), each with
/// the unit weight `gammas[m]` (N/m³) of its material `m`, and below the water table
/// `below = (buoyant, table)` the buoyant one `buoyant[m]` (`γ_sat − γ_w`: the effective
/// weight): exact for straight-sided elements. The ground between the mesh's top and a
/// higher `surface` weighs nothing here (a surcharge stands for it).
pub fn layered_weight(
    model: &Model,
    gammas: &[f64],
    below: Option<(&[f64], &crate::scene::WaterTable)>,
    surface: f64,
) -> Vec<f64> {
    let mesh = &model.mesh;
    let asm = &model.assembly;
    let n_e = mesh.triangles.len();
    let triangles: Vec<[[f64; 2]; 3]> = mesh
        .triangles
        .iter()
        .map(|t| [mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]]])
        .collect();
    // Each element's material: that of its points.
    let mut material = vec![0; n_e];
    for (p, &e) in asm.gauss_element.iter().enumerate() {
        material[e] = model.point_material[p];
    }
    // Elements binned by their x-range, so that a vertical meets only its bin's elements.
    let (x0, x1) = triangles
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p[0]), b.max(p[0]))
        });
    let bins = ((n_e as f64).sqrt() as usize).max(1);
    let width = (x1 - x0).max(f64::MIN_POSITIVE) / bins as f64;
    let bin = |x: f64| (((x - x0) / width) as usize).min(bins - 1);
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); bins];
    for (e, t) in triangles.iter().enumerate() {
        let lo = t.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min);
        let hi = t.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max);
        for b in bin(lo)..=bin(hi) {
            members[b].push(e);
        }
    }
    asm.gauss_points
        .iter()
        .map(|&[x, y]| {
            members[bin(x)]
                .iter()
                .filter_map(|&e| {
                    let (lo, hi) = crossing(triangles[e], x)?;
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
    use super::crossing;

    #[test]
    fn a_vertical_crosses_a_triangle_between_its_edges() {
        let t = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]];
        assert_eq!(crossing(t, 0.5), Some((0.0, 1.5)));
        assert_eq!(crossing(t, 2.5), None);
        assert_eq!(crossing(t, 0.0), Some((0.0, 2.0)));
    }
}
