use talus_bipotential::FlowRule;

use crate::error::invalid;
use crate::{Operator, SolveError};

/// One reduced problem (eqs. 16, 20): find σ with `z = Wσ + q` and, at every point `i`,
/// `σ_i = P_K(σ_i − ρ_i y_i(z_i))`. Vectors are flat, point `i` owning entries
/// `D·i .. D·i + D`. The time step of eq. 16 is folded into `W` and `q`: with
/// `h z = Wσ + q` pass `W/h` and `q/h`, or keep them, which only rescales ρ.
#[derive(Debug, Clone)]
pub struct ReducedSystem<const D: usize> {
    pub(crate) operator: Operator<D>,
    pub(crate) q: Vec<f64>,
    pub(crate) rules: Vec<FlowRule<D>>,
}

impl<const D: usize> ReducedSystem<D> {
    /// Checks sizes and finiteness; names the offending field.
    pub fn try_new(
        operator: Operator<D>,
        q: Vec<f64>,
        rules: Vec<FlowRule<D>>,
    ) -> Result<Self, SolveError> {
        operator.validate()?;
        let n = operator.size();
        if n != D * rules.len() {
            return Err(invalid(
                "rules",
                format!(
                    "{} flow rules for an operator of size {n} ({D} components per point)",
                    rules.len()
                ),
            ));
        }
        let mut system = Self {
            operator,
            q: Vec::new(),
            rules,
        };
        system.set_q(q)?;
        Ok(system)
    }

    /// Replaces `q` (a new time step on the same operator).
    pub fn set_q(&mut self, q: Vec<f64>) -> Result<(), SolveError> {
        if q.len() != self.operator.size() {
            return Err(invalid(
                "q",
                format!(
                    "length {} for an operator of size {}",
                    q.len(),
                    self.operator.size()
                ),
            ));
        }
        if let Some(i) = q.iter().position(|v| !v.is_finite()) {
            return Err(invalid(
                "q",
                format!("non-finite entry {} at index {i}", q[i]),
            ));
        }
        self.q = q;
        Ok(())
    }

    /// Replaces the flow rules (a new time step whose yield sets moved, e.g. under a
    /// changing pore pressure): the same number of points and the same symmetry, so that
    /// the Newton system keeps its pattern and factorization kind.
    pub fn set_rules(&mut self, rules: Vec<FlowRule<D>>) -> Result<(), SolveError> {
        if rules.len() != self.rules.len() {
            return Err(invalid(
                "rules",
                format!("{} flow rules for {} points", rules.len(), self.rules.len()),
            ));
        }
        let associative = rules.iter().all(|r| r.is_associative());
        if associative != self.is_associative() {
            return Err(invalid(
                "rules",
                "the new rules change whether the flow is associative (the Newton system's \
                 symmetry): build a new solver"
                    .to_string(),
            ));
        }
        self.rules = rules;
        Ok(())
    }

    pub fn operator(&self) -> &Operator<D> {
        &self.operator
    }

    pub fn q(&self) -> &[f64] {
        &self.q
    }

    pub fn rules(&self) -> &[FlowRule<D>] {
        &self.rules
    }

    pub fn n_points(&self) -> usize {
        self.rules.len()
    }

    /// Whether every point's rule is associative (the Newton system is then symmetric).
    pub fn is_associative(&self) -> bool {
        self.rules.iter().all(|r| r.is_associative())
    }
}
