//! Mean nearest-neighbour distance of a point cloud: the default size of a particle marker,
//! so that particles on a lattice tile the plot without gaps.
use super::map_frame::BBox;

/// Mean over the points of the distance to the nearest point at another position, m;
/// `None` with fewer than two distinct positions. Points are binned in a grid of about
/// one point per cell and each searches outward ring by ring, so a lattice costs O(n).
pub(super) fn mean_spacing(points: &[[f64; 2]]) -> Option<f64> {
    let n = points.len();
    let bbox = BBox::of(points.iter().copied());
    let (w, h) = (bbox.width(), bbox.height());
    // Cells of about one point each; no more than 3n + 1 of them, even for a line of points.
    let cell = (w * h / n as f64).sqrt().max(w.max(h) / n as f64);
    if n < 2 || !(cell > 0.0 && cell.is_finite()) {
        return None;
    }
    let (nx, ny) = ((w / cell) as usize + 1, (h / cell) as usize + 1);
    let cell_of = |p: &[f64; 2]| {
        let i = (((p[0] - bbox.x.0) / cell) as usize).min(nx - 1);
        let j = (((p[1] - bbox.y.0) / cell) as usize).min(ny - 1);
        (i, j)
    };
    // Points sorted by cell; `start[c]..start[c + 1]` are those of cell c = j·nx + i.
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&k| {
        let (i, j) = cell_of(&points[k]);
        j * nx + i
    });
    let mut start = vec![0usize; nx * ny + 1];
    for p in points {
        let (i, j) = cell_of(p);
        start[j * nx + i + 1] += 1;
    }
    for c in 0..nx * ny {
        start[c + 1] += start[c];
    }

    let (mut sum, mut count) = (0.0, 0usize);
    for p in points {
        let (i, j) = cell_of(p);
        let (i, j) = (i as isize, j as isize);
        let mut best = f64::INFINITY;
        // A point in ring r + 1 or beyond is farther than r·cell.
        for r in 0..nx.max(ny) as isize {
            if best <= r as f64 * cell {
                break;
            }
            for (ci, cj) in ring(i, j, r) {
                if ci < 0 || cj < 0 || ci >= nx as isize || cj >= ny as isize {
                    continue;
                }
                let c = cj as usize * nx + ci as usize;
                for &k in &order[start[c]..start[c + 1]] {
                    let d = (points[k][0] - p[0]).hypot(points[k][1] - p[1]);
                    if d > 0.0 && d < best {
                        best = d;
                    }
                }
            }
        }
        if best.is_finite() {
            sum += best;
            count += 1;
        }
    }
    (count > 0).then(|| sum / count as f64)
}

/// The cells at Chebyshev distance exactly `r` from `(i, j)`.
fn ring(i: isize, j: isize, r: isize) -> impl Iterator<Item = (isize, isize)> {
    (-r..=r).flat_map(move |di| {
        (-r..=r)
            .filter(move |&dj| di.abs() == r || dj.abs() == r)
            .map(move |dj| (i + di, j + dj))
    })
}
