//! ρ per point, for the iteration and for the stopping test.
use crate::error::invalid;
use crate::{Operator, Rho, SolveError};

/// The ρ of the stopping test, whatever ρ the iteration uses: `F_ρ(σ) = 0` for one ρ > 0
/// iff for all, but the size of `F_ρ` scales with ρ, so measuring with a fixed convention
/// keeps the tolerance meaning the same when the iteration's ρ is tuned.
pub(super) const RESIDUAL_RHO: Rho = Rho::PerPointDiagonal { factor: 1.0 };

pub(super) fn choose_rho<const D: usize>(
    rule: &Rho,
    diagonal: &[f64],
    operator: &Operator<D>,
) -> Result<Vec<f64>, SolveError> {
    let n_points = diagonal.len() / D;
    let point_max = |i: usize| {
        diagonal[D * i..D * i + D]
            .iter()
            .fold(0.0f64, |m, v| m.max(*v))
    };
    let rho: Vec<f64> = match *rule {
        Rho::Fixed(r) => vec![r; n_points],
        Rho::GlobalDiagonal { factor } => {
            let m = diagonal.iter().fold(0.0f64, |m, v| m.max(*v));
            vec![factor / m; n_points]
        }
        Rho::PerPointDiagonal { factor } => (0..n_points).map(|i| factor / point_max(i)).collect(),
        Rho::PerPointCompliance { factor } => match operator {
            Operator::Structured(s) => s
                .compliance
                .iter()
                .map(|c| factor / (0..D).fold(0.0f64, |m, k| m.max(c[(k, k)])))
                .collect(),
            _ => {
                return Err(invalid(
                    "settings.rho",
                    "PerPointCompliance needs a structured operator",
                ))
            }
        },
    };
    if let Some(i) = rho.iter().position(|r| !(r.is_finite() && *r > 0.0)) {
        return Err(invalid(
            "W",
            format!(
                "diagonal block of point {i} has no positive entry (max {}): ρ cannot be scaled",
                point_max(i)
            ),
        ));
    }
    Ok(rho)
}
