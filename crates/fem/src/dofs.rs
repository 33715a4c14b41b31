//! Degrees of freedom: two velocity (or displacement) components per node, each either
//! free (an unknown of the solver, a column of `B_free`) or prescribed (Dirichlet, a
//! column of `B_prescribed`; its value enters `q` of eq. 16 through `B`, see
//! `docs/derivations.md`, 'The reduced system'). Components: 0 = x, 1 = y.
use crate::error::FemError;

/// Which components of a node set are prescribed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Constraint {
    /// Both components.
    Fixed,
    /// `x` only: a roller that slides along `y` (e.g. the sides of a soil box).
    FixX,
    /// `y` only: a roller that slides along `x` (e.g. a smooth base).
    FixY,
}

impl Constraint {
    fn fixes(self, comp: usize) -> bool {
        match self {
            Constraint::Fixed => true,
            Constraint::FixX => comp == 0,
            Constraint::FixY => comp == 1,
        }
    }
}

/// Status of one component of one node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dof {
    /// Index among the free dofs (column of `B_free`, entry of the free mass).
    Free(usize),
    /// Index among the prescribed dofs (column of `B_prescribed`).
    Prescribed(usize),
}

/// Numbering of free and prescribed dofs, node-major (node 0 x, node 0 y, node 1 x, …)
/// within each kind, so that neighbouring nodes get neighbouring columns.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DofMap {
    dofs: Vec<[Dof; 2]>,
    n_free: usize,
    prescribed: Vec<(usize, usize)>,
}

impl DofMap {
    /// Prescribes the components named by each constraint on its nodes; a node in several
    /// sets gets the union of their constraints. Errors on a node index `≥ n_nodes`.
    pub fn new(n_nodes: usize, constraints: &[(Vec<usize>, Constraint)]) -> Result<Self, FemError> {
        let mut fixed = vec![[false; 2]; n_nodes];
        for (k, (nodes, c)) in constraints.iter().enumerate() {
            for &n in nodes {
                let f = fixed.get_mut(n).ok_or_else(|| {
                    FemError::invalid(
                        "constraints",
                        format!(
                            "constraint {k} ({c:?}) names node {n}, the mesh has {n_nodes} nodes"
                        ),
                    )
                })?;
                for (comp, fc) in f.iter_mut().enumerate() {
                    *fc |= c.fixes(comp);
                }
            }
        }
        let mut n_free = 0;
        let mut prescribed = Vec::new();
        let dofs = fixed
            .iter()
            .enumerate()
            .map(|(node, f)| {
                [0, 1].map(|comp| {
                    if f[comp] {
                        prescribed.push((node, comp));
                        Dof::Prescribed(prescribed.len() - 1)
                    } else {
                        n_free += 1;
                        Dof::Free(n_free - 1)
                    }
                })
            })
            .collect();
        Ok(Self {
            dofs,
            n_free,
            prescribed,
        })
    }

    pub fn n_nodes(&self) -> usize {
        self.dofs.len()
    }

    pub fn n_free(&self) -> usize {
        self.n_free
    }

    pub fn n_prescribed(&self) -> usize {
        self.prescribed.len()
    }

    /// Status of component `comp` (0 = x, 1 = y) of `node`; `None` if out of range.
    pub fn dof(&self, node: usize, comp: usize) -> Option<Dof> {
        self.dofs.get(node).and_then(|d| d.get(comp)).copied()
    }

    /// Free index of `(node, comp)`, if that dof is free.
    pub fn free(&self, node: usize, comp: usize) -> Option<usize> {
        match self.dof(node, comp)? {
            Dof::Free(i) => Some(i),
            Dof::Prescribed(_) => None,
        }
    }

    /// Prescribed index of `(node, comp)`, if that dof is prescribed.
    pub fn prescribed(&self, node: usize, comp: usize) -> Option<usize> {
        match self.dof(node, comp)? {
            Dof::Prescribed(j) => Some(j),
            Dof::Free(_) => None,
        }
    }

    /// `(node, comp)` of every prescribed dof, in prescribed order (to fill the vector of
    /// prescribed velocities).
    pub fn prescribed_dofs(&self) -> &[(usize, usize)] {
        &self.prescribed
    }

    /// Nodal vectors `[x, y]` from free and prescribed values (e.g. for output).
    pub fn scatter(&self, free: &[f64], prescribed: &[f64]) -> Result<Vec<[f64; 2]>, FemError> {
        self.check_lengths(free, prescribed)?;
        Ok(self
            .dofs
            .iter()
            .map(|d| {
                d.map(|dof| match dof {
                    Dof::Free(i) => free[i],
                    Dof::Prescribed(j) => prescribed[j],
                })
            })
            .collect())
    }

    pub(crate) fn check_lengths(&self, free: &[f64], prescribed: &[f64]) -> Result<(), FemError> {
        if free.len() != self.n_free || prescribed.len() != self.n_prescribed() {
            return Err(FemError::invalid(
                "field",
                format!(
                    "{} free and {} prescribed values for {} free and {} prescribed dofs",
                    free.len(),
                    prescribed.len(),
                    self.n_free,
                    self.n_prescribed()
                ),
            ));
        }
        Ok(())
    }
}
