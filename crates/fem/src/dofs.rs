//! Degrees of freedom: two (2D) or three (3D) velocity (or displacement) components per
//! node, each either free (an unknown of the solver, a column of `B_free`) or prescribed
//! (Dirichlet, a column of `B_prescribed`; its value enters `q` of eq. 16 through `B`, see
//! `docs/derivations.md`, 'The reduced system'). Components: 0 = x, 1 = y, 2 = z.
use crate::error::FemError;

/// Which components of a node set are prescribed (`fix = "xy"`, `"x"`, … of a scene).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Constraint {
    /// Every component.
    Fixed,
    /// `x` only: a roller that slides along `y` (and `z`), e.g. the sides of a soil box.
    FixX,
    /// `y` only: a roller that slides along `x` (and `z`), e.g. a smooth base.
    FixY,
    /// `z` only (3D): e.g. the faces of a slab in plane strain.
    FixZ,
    /// `x` and `y` (3D; in 2D the same as `Fixed`).
    FixXY,
    /// `x` and `z` (3D).
    FixXZ,
    /// `y` and `z` (3D).
    FixYZ,
}

impl Constraint {
    fn fixes(self, comp: usize) -> bool {
        let axes: &[usize] = match self {
            Constraint::Fixed => return true,
            Constraint::FixX => &[0],
            Constraint::FixY => &[1],
            Constraint::FixZ => &[2],
            Constraint::FixXY => &[0, 1],
            Constraint::FixXZ => &[0, 2],
            Constraint::FixYZ => &[1, 2],
        };
        axes.contains(&comp)
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
    /// `components` entries per node.
    dofs: Vec<Dof>,
    components: usize,
    n_free: usize,
    prescribed: Vec<(usize, usize)>,
}

impl DofMap {
    /// A 2D map (x, y): see [`with_components`](Self::with_components).
    pub fn new(n_nodes: usize, constraints: &[(Vec<usize>, Constraint)]) -> Result<Self, FemError> {
        Self::with_components(n_nodes, 2, constraints)
    }

    /// `components` (2 or 3) per node; prescribes the components named by each constraint
    /// on its nodes, a node in several sets getting the union of their constraints. Errors
    /// name the constraint: a node index `≥ n_nodes`, or a 2D map asked to fix z.
    pub fn with_components(
        n_nodes: usize,
        components: usize,
        constraints: &[(Vec<usize>, Constraint)],
    ) -> Result<Self, FemError> {
        if !(components == 2 || components == 3) {
            return Err(FemError::invalid(
                "components",
                format!("{components}: a dof map has 2 (2D) or 3 (3D) components per node"),
            ));
        }
        let mut fixed = vec![false; components * n_nodes];
        for (k, (nodes, c)) in constraints.iter().enumerate() {
            let names_z = matches!(c, Constraint::FixZ | Constraint::FixXZ | Constraint::FixYZ);
            if components == 2 && names_z {
                return Err(FemError::invalid(
                    "constraints",
                    format!("constraint {k} ({c:?}) fixes z, which a 2D map does not have"),
                ));
            }
            for &n in nodes {
                if n >= n_nodes {
                    return Err(FemError::invalid(
                        "constraints",
                        format!(
                            "constraint {k} ({c:?}) names node {n}, the mesh has {n_nodes} nodes"
                        ),
                    ));
                }
                for comp in 0..components {
                    fixed[components * n + comp] |= c.fixes(comp);
                }
            }
        }
        let mut n_free = 0;
        let mut prescribed = Vec::new();
        let dofs = fixed
            .iter()
            .enumerate()
            .map(|(k, &f)| {
                if f {
                    prescribed.push((k / components, k % components));
                    Dof::Prescribed(prescribed.len() - 1)
                } else {
                    n_free += 1;
                    Dof::Free(n_free - 1)
                }
            })
            .collect();
        Ok(Self {
            dofs,
            components,
            n_free,
            prescribed,
        })
    }

    pub fn n_nodes(&self) -> usize {
        self.dofs.len() / self.components
    }

    /// Components per node: 2 or 3.
    pub fn components(&self) -> usize {
        self.components
    }

    pub fn n_free(&self) -> usize {
        self.n_free
    }

    pub fn n_prescribed(&self) -> usize {
        self.prescribed.len()
    }

    /// Status of component `comp` (0 = x, 1 = y, 2 = z) of `node`; `None` if out of range.
    pub fn dof(&self, node: usize, comp: usize) -> Option<Dof> {
        if comp >= self.components {
            return None;
        }
        self.dofs.get(self.components * node + comp).copied()
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

    /// Nodal vectors `[x, y]` of a 2D map from free and prescribed values (e.g. for
    /// output).
    pub fn scatter(&self, free: &[f64], prescribed: &[f64]) -> Result<Vec<[f64; 2]>, FemError> {
        self.nodal_vectors(free, prescribed)
    }

    /// Nodal vectors (`[x, y]` with `N = 2`, `[x, y, z]` with `N = 3`: the map's
    /// components) from free and prescribed values.
    pub fn nodal_vectors<const N: usize>(
        &self,
        free: &[f64],
        prescribed: &[f64],
    ) -> Result<Vec<[f64; N]>, FemError> {
        if N != self.components {
            return Err(FemError::invalid(
                "field",
                format!("{N} components asked of a map with {}", self.components),
            ));
        }
        self.check_lengths(free, prescribed)?;
        Ok(self
            .dofs
            .chunks_exact(N)
            .map(|d| {
                std::array::from_fn(|c| match d[c] {
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
