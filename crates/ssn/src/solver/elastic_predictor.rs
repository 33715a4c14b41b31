//! The elastic predictor: one Newton step with every point interior.
use super::{block, Solver};
use crate::error::invalid;
use crate::{Report, SolveError};

impl<const D: usize> Solver<D> {
    /// Moves `sigma` to the solution of the purely elastic problem `Wσ + q = 0`: one Newton
    /// step with every point treated as interior (`D = I`). From there the next
    /// linearization sees the return mapping of the elastic trial, the classical elastic
    /// predictor. Fails like a Newton step when `W` is singular.
    pub fn elastic_predictor(&mut self, sigma: &mut [f64]) -> Result<(), SolveError> {
        let n = self.problem.operator.size();
        if sigma.len() != n {
            return Err(invalid(
                "sigma",
                format!("length {} for an operator of size {n}", sigma.len()),
            ));
        }
        self.evaluate(sigma, false);
        for l in self.lin.iter_mut() {
            // Interior everywhere: F = ρ z, D = I, G = I.
            l.projection_jacobian = nalgebra::SMatrix::identity();
            l.coupling = nalgebra::SMatrix::identity();
            l.region = talus_bipotential::Region::Interior;
        }
        for (i, l) in self.lin.iter_mut().enumerate() {
            l.residual = block::<D>(&self.z, i) * self.rho[i];
        }
        let mut report = Report::start((0.0, 0.0));
        if let Err(status) = self.newton_direction(&mut report, 0.0) {
            return Err(SolveError::NotConverged(Box::new(Report {
                status,
                ..report
            })));
        }
        for (s, d) in sigma.iter_mut().zip(&self.direction) {
            *s += d;
        }
        // A rank's direction is 0 at the points it does not own; `z()` whole too.
        self.gather(sigma);
        self.gather_z();
        Ok(())
    }
}
