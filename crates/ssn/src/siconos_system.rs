use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use nalgebra::SVector;
use talus_bipotential::FlowRule;
use talus_cone::{SecondOrderCone, VonMisesCylinder};

use crate::error::invalid;
use crate::siconos::{SiconosMatrix, SiconosModel, SiconosProblem};
use crate::{Operator, ReducedSystem, SolveError};

/// The Siconos problem as a [`ReducedSystem`]: cones in their own axis coordinates (axis
/// `e_0`, apex at the origin), Siconos' `theta` as the shift `κ` of `y = z + κ‖z_t‖ n`.
pub fn reduced_system_from_siconos<const D: usize>(
    p: &SiconosProblem,
) -> Result<ReducedSystem<D>, SolveError> {
    if p.cone_dimension != D {
        return Err(invalid(
            "cone_dimension",
            format!("{} in the file, {D} expected", p.cone_dimension),
        ));
    }
    let n = p.n();
    let operator = match &p.matrix {
        SiconosMatrix::Dense { n: m, values } => {
            if *m != n || values.len() != n * n {
                return Err(invalid(
                    "matrix",
                    format!("dense matrix of size {m} for n = {n}"),
                ));
            }
            Operator::Dense(Mat::from_fn(n, n, |i, j| values[i * n + j]))
        }
        SiconosMatrix::Sparse { n: m, triplets } => {
            if *m != n {
                return Err(invalid(
                    "matrix",
                    format!("sparse matrix of size {m} for n = {n}"),
                ));
            }
            let t: Vec<_> = triplets
                .iter()
                .map(|&(i, j, v)| Triplet::new(i, j, v))
                .collect();
            let w = SparseColMat::try_new_from_triplets(n, n, &t)
                .map_err(|e| invalid("matrix", format!("sparse triplets: {e:?}")))?;
            Operator::Sparse(w)
        }
    };
    let axis = SVector::<f64, D>::from_fn(|i, _| if i == 0 { 1.0 } else { 0.0 });
    let rules = match &p.model {
        SiconosModel::DruckerPrager { eta, theta } => eta
            .iter()
            .zip(theta)
            .map(|(&eta, &theta)| {
                let cone = SecondOrderCone::try_new(axis, SVector::zeros(), eta)
                    .map_err(|e| invalid("eta", e.to_string()))?;
                if !(theta.is_finite() && theta >= 0.0) {
                    return Err(invalid("theta", format!("{theta} must be finite and >= 0")));
                }
                Ok(FlowRule::cone(cone, theta))
            })
            .collect::<Result<Vec<_>, _>>()?,
        SiconosModel::VonMises { sigma_y } => sigma_y
            .iter()
            .map(|&r| {
                VonMisesCylinder::try_new(axis, r)
                    .map(FlowRule::cylinder)
                    .map_err(|e| invalid("sigma_y", e.to_string()))
            })
            .collect::<Result<Vec<_>, _>>()?,
    };
    ReducedSystem::try_new(operator, p.q.clone(), rules)
}
