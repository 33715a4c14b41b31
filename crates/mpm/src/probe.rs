//! The value at a point of a field the particles carry (displacement, velocity), through
//! the grid as every transfer goes: the mass-weighted P2G of eq. 11,
//! `u_i = Σ_p N_i(x_p) m_p u_p / m_i`, then the shape functions at the point,
//! `u(x) = Σ_i N_i(x) u_i / Σ_i N_i(x)` over the nodes that carry mass (a rigid motion is
//! reproduced exactly, also next to the material's edge).
use crate::dimension::{Dimension, Mandel, Vector};
use crate::error::MpmError;
use crate::grid::Grid;
use crate::particles::Particles;

/// `field` (one vector per particle) at `point` (m), or `None` when no node of the point's
/// stencil carries mass (no material around the point). The point must lie in the grid.
pub fn grid_value_at<const D: usize>(
    grid: &Grid<D>,
    particles: &Particles<D>,
    field: &[Vector<D>],
    point: Vector<D>,
) -> Result<Option<Vector<D>>, MpmError>
where
    Mandel<D>: Dimension,
{
    let n = Mandel::<D>::AXES;
    if field.len() != particles.len() {
        return Err(MpmError::invalid(
            "field",
            format!("{} values for {} particles", field.len(), particles.len()),
        ));
    }
    let (lo, hi) = (grid.origin(), grid.end());
    if !(0..n).all(|a| (lo[a]..=hi[a]).contains(&point[a])) {
        return Err(MpmError::invalid(
            "point",
            format!("{point:?} m is outside the grid [{lo:?}, {hi:?}]"),
        ));
    }
    let at = grid.stencil(0, point)?;
    let nodes = &at.nodes.as_ref()[..at.len];
    let mut mass = vec![0.0; at.len];
    let mut moment = vec![Vector::<D>::default(); at.len];
    // Sequential in particle order: the same sums whatever the thread count.
    for (p, x) in particles.position.iter().enumerate() {
        for (i, w, _) in grid.stencil(p, *x)?.iter() {
            if let Some(k) = nodes.iter().position(|&n| n == i) {
                let m = w * particles.mass[p];
                mass[k] += m;
                for a in 0..n {
                    moment[k][a] += m * field[p][a];
                }
            }
        }
    }
    let (mut value, mut weight) = (Vector::<D>::default(), 0.0);
    for k in 0..at.len {
        if mass[k] > 0.0 {
            let w = at.weights.as_ref()[k];
            for a in 0..n {
                value[a] += w * moment[k][a] / mass[k];
            }
            weight += w;
        }
    }
    Ok((weight > 0.0).then(|| {
        for a in 0..n {
            value[a] /= weight;
        }
        value
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::ShapeFunction;

    fn block() -> (Grid, Particles) {
        let grid =
            Grid::try_new([0.0, 0.0], 0.1, [10, 10], ShapeFunction::QuadraticBSpline).unwrap();
        let p = Particles::fill_rectangle([[0.2, 0.2], [0.6, 0.5]], 0.1, 2, 1000.0).unwrap();
        (grid, p)
    }

    #[test]
    fn a_uniform_field_is_reproduced_inside_and_at_the_edge() {
        let (grid, p) = block();
        let field = vec![[1.5e-3, -2.0e-3]; p.len()];
        for point in [[0.4, 0.3], [0.2, 0.5], [0.63, 0.21]] {
            let v = grid_value_at(&grid, &p, &field, point).unwrap().unwrap();
            assert!((v[0] - 1.5e-3).abs() < 1e-18 && (v[1] + 2.0e-3).abs() < 1e-18);
        }
    }

    #[test]
    fn a_linear_field_is_reproduced_inside_the_material() {
        // Quadratic B-splines reproduce linear functions (partition of unity and
        // Σ N_i x_i = x), and P2G of a linear field gives it back at the nodes only
        // approximately: the interpolated value is within O(dx²) of the field.
        let (grid, p) = block();
        let field: Vec<[f64; 2]> = p.position.iter().map(|x| [x[0], 2.0 * x[1]]).collect();
        let v = grid_value_at(&grid, &p, &field, [0.4, 0.35])
            .unwrap()
            .unwrap();
        assert!((v[0] - 0.4).abs() < 1e-3, "{v:?}");
        assert!((v[1] - 0.7).abs() < 2e-3, "{v:?}");
    }

    #[test]
    fn no_material_around_the_point_is_none_and_outside_the_grid_an_error() {
        let (grid, p) = block();
        let field = vec![[1.0, 0.0]; p.len()];
        assert_eq!(
            grid_value_at(&grid, &p, &field, [0.95, 0.95]).unwrap(),
            None
        );
        let err = grid_value_at(&grid, &p, &field, [1.2, 0.5]).unwrap_err();
        assert!(err.to_string().contains("point"), "{err}");
        assert!(grid_value_at(&grid, &p, &field[1..], [0.4, 0.3]).is_err());
    }
}
