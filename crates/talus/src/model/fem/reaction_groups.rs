//! Per-boundary reactions. A prescribed velocity component shared by two `[[boundary]]`
//! conditions (a corner of a fixed base and a symmetry side) is counted once: it belongs
//! to the condition whose velocity it follows, the last one in file order that prescribes
//! it (`Model::dof_owner`), and so does the force enforcing it. The MPM walls and boxes
//! follow the same rule (`docs/scenes.md`, 'Reactions').
use super::Model;

/// The named conditions, one group per distinct name (conditions sharing a name add up),
/// with the prescribed dofs each owns.
#[derive(Debug, Clone, PartialEq)]
pub struct ReactionGroups {
    /// `(field of the first condition with the name, name)`, in file order.
    pub names: Vec<(String, String)>,
    /// Per group, its prescribed dofs `j` and their component.
    pub dofs: Vec<Vec<(usize, usize)>>,
    /// From the prescribed forces' unit to the reported one: 1, or `2π` in axisymmetry
    /// (forces per radian, reported for the whole circumference: `docs/axisymmetry.md`).
    pub scale: f64,
}

impl ReactionGroups {
    /// `names[k]`: the name of condition `k`; `dof_owner[j]`: the condition prescribed dof
    /// `j` belongs to; `prescribed_dofs[j]`: its `(node, component)`.
    pub fn new(
        names: &[Option<String>],
        dof_owner: &[usize],
        prescribed_dofs: &[(usize, usize)],
    ) -> Self {
        let mut groups = Self {
            names: Vec::new(),
            dofs: Vec::new(),
            scale: 1.0,
        };
        let mut group_of = vec![None; names.len()];
        for (k, name) in names.iter().enumerate() {
            let Some(name) = name else { continue };
            let g = match groups.names.iter().position(|(_, n)| n == name) {
                Some(g) => g,
                None => {
                    groups
                        .names
                        .push((format!("boundary[{k}].name"), name.clone()));
                    groups.dofs.push(Vec::new());
                    groups.names.len() - 1
                }
            };
            group_of[k] = Some(g);
        }
        for (j, &k) in dof_owner.iter().enumerate() {
            if let Some(g) = group_of.get(k).copied().flatten() {
                groups.dofs[g].push((j, prescribed_dofs[j].1));
            }
        }
        groups
    }

    /// `[fx, fy]` per group, from the force on every prescribed dof, times `scale`.
    pub fn sums(&self, forces: &[f64]) -> Vec<[f64; 2]> {
        self.sums_of(forces)
    }

    /// The `C` force components per group (`[fx, fy]`, 3D `[fx, fy, fz]`), from the force
    /// on every prescribed dof, times `scale`.
    pub fn sums_of<const C: usize>(&self, forces: &[f64]) -> Vec<[f64; C]> {
        self.dofs
            .iter()
            .map(|dofs| {
                let mut f = [0.0; C];
                for &(j, comp) in dofs {
                    if let Some(f) = f.get_mut(comp) {
                        *f += forces.get(j).copied().unwrap_or(0.0);
                    }
                }
                f.map(|x| x * self.scale)
            })
            .collect()
    }

    /// The groups of a FEM model, reported per metre (plane strain) or for the whole
    /// circumference (axisymmetric).
    pub fn of_model<const D: usize>(model: &Model<D>, names: &[Option<String>]) -> Self
    where
        talus_fem::Mandel<D>: talus_fem::Dimension,
    {
        Self {
            scale: model.assembly.geometry().whole_body_factor(),
            ..Self::new(
                names,
                &model.dof_owner,
                model.assembly.dofs().prescribed_dofs(),
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A corner node 0 fixed in x and y by a base (condition 0) and in x by a symmetry side
    /// (condition 1, later): its x belongs to the side, its y to the base.
    #[test]
    fn a_shared_corner_component_goes_to_exactly_one_group() {
        // Prescribed dofs: node 0 x, node 0 y, node 1 x, node 1 y (base), node 2 x (side).
        let prescribed = [(0, 0), (0, 1), (1, 0), (1, 1), (2, 0)];
        let owner = [1, 0, 0, 0, 1];
        let names = [Some("base".to_string()), Some("side".to_string())];
        let g = ReactionGroups::new(&names, &owner, &prescribed);
        assert_eq!(g.dofs[0], vec![(1, 1), (2, 0), (3, 1)]);
        assert_eq!(g.dofs[1], vec![(0, 0), (4, 0)]);
        let forces = [1.0, 10.0, 100.0, 1000.0, 10000.0];
        assert_eq!(g.sums(&forces), vec![[100.0, 1010.0], [10001.0, 0.0]]);
        // Every dof in exactly one group: the groups add up to the total.
        let total: f64 = g.sums(&forces).iter().flatten().sum();
        assert_eq!(total, forces.iter().sum::<f64>());
    }

    #[test]
    fn conditions_sharing_a_name_add_up_and_unnamed_ones_report_nothing() {
        let prescribed = [(0, 1), (1, 1), (2, 1)];
        let owner = [0, 1, 2];
        let names = [
            Some("footing".to_string()),
            None,
            Some("footing".to_string()),
        ];
        let g = ReactionGroups::new(&names, &owner, &prescribed);
        assert_eq!(
            g.names,
            vec![("boundary[0].name".to_string(), "footing".to_string())]
        );
        assert_eq!(g.sums(&[1.0, 2.0, 4.0]), vec![[0.0, 5.0]]);
    }
}
