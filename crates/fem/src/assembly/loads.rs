//! Consistent nodal forces `f` of eq. 12 (N per metre of thickness, or per radian in
//! axisymmetry, where every integrand carries `r`: `docs/axisymmetry.md`), split into free
//! and prescribed dofs like the columns of `B`. Forces on prescribed dofs do not move the
//! solution but enter the reaction (`docs/derivations.md`, 'Prescribed velocities and the
//! reaction').
use super::Assembly;
use crate::dofs::Dof;
use crate::element::edge::shape_and_derivative;
use crate::error::FemError;
use crate::mesh::{BoundaryEdge, Mesh};
use crate::quadrature::edge_rule;

fn check_vector(field: &'static str, v: [f64; 2]) -> Result<(), FemError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(FemError::invalid(field, format!("{v:?} must be finite")))
    }
}

impl Assembly {
    /// Body force `f_a = ∫ N_a ρ g dA` (gravity: `g = [0, −9.81]` m/s², y up; axisymmetric:
    /// `∫ N_a ρ g r dA`, through the Gauss volumes), integrated with the Gauss points (exact on affine triangles; on P2 the vertices get 0 and the
    /// mid nodes ρgA/3, as consistency demands). `density` (kg/m³, ≥ 0) may differ from the
    /// inertial one, e.g. 0 for weightless soil.
    pub fn body_force(&self, density: f64, g: [f64; 2]) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        if !(density.is_finite() && density >= 0.0) {
            return Err(FemError::invalid(
                "density",
                format!("{density} kg/m³ must be finite and ≥ 0"),
            ));
        }
        check_vector("gravity", g)?;
        let mut out = self.zero_forces();
        for p in 0..self.gauss.len() {
            let v = self.gauss.volumes[p];
            for (node, n, _) in self.gauss.point(p) {
                for (comp, gc) in g.iter().enumerate() {
                    self.add_force(&mut out, node, comp, density * v * n * gc);
                }
            }
        }
        Ok(out)
    }

    /// Traction `f_a = ∫ N_a t ds` over `edges` (nodes of `mesh`), `t` in Pa (N/m² in
    /// global axes, e.g. `[0, −q]` for a downward pressure q on a top face): the force per
    /// metre of thickness. 3-point Gauss-Legendre per edge: exact on straight edges (P2
    /// weights 1/6, 1/6, 2/3 of `|t|·L` for end, end, mid node). Axisymmetric: `∫ N_a t r ds`
    /// per radian, still exact on straight edges (degree ≤ 3).
    pub fn traction(
        &self,
        mesh: &Mesh,
        edges: &[BoundaryEdge],
        t: [f64; 2],
    ) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        check_vector("traction", t)?;
        self.edge_integral(mesh, edges, |w, n, tangent| {
            let ds = tangent[0].hypot(tangent[1]);
            [w * ds * n * t[0], w * ds * n * t[1]]
        })
    }

    /// Normal pressure `f_a = −p ∫ N_a n ds` over `edges`, `p` in Pa, positive pushing
    /// into the body (`n` the outward normal). Each edge is first oriented by its triangle
    /// ([`Mesh::orient_boundary_edges`]), so one call covers a whole curved boundary drawn
    /// in any direction. With `x(s)` the edge's isoparametric map, `n ds = (y′, −x′) ds`
    /// at each quadrature point: the integrand `N_a x′` has degree ≤ 3, so the 3-point rule
    /// is exact on straight and curved (P2) edges alike, and the forces of an edge from `a`
    /// to `b` sum to `p` times `b − a` turned counter-clockwise, whatever its shape.
    /// Axisymmetric: `−p ∫ N_a n r ds` per radian, degree ≤ 5, still exact.
    pub fn pressure(
        &self,
        mesh: &Mesh,
        edges: &[BoundaryEdge],
        p: f64,
    ) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        if !p.is_finite() {
            return Err(FemError::invalid(
                "pressure",
                format!("{p} Pa must be finite"),
            ));
        }
        let oriented = mesh.orient_boundary_edges(edges)?;
        self.edge_integral(mesh, &oriented, |w, n, tangent| {
            [-w * n * p * tangent[1], w * n * p * tangent[0]]
        })
    }

    /// `Σ_edges Σ_gauss r load(w, N_a, x′(s))` added to every node `a` of each edge (`r`
    /// the geometry's weight at the point, 1 in plane strain), after checking the edges'
    /// node counts against the mesh.
    fn edge_integral(
        &self,
        mesh: &Mesh,
        edges: &[BoundaryEdge],
        load: impl Fn(f64, f64, [f64; 2]) -> [f64; 2],
    ) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        if mesh.nodes.len() != self.dofs.n_nodes() {
            return Err(FemError::invalid(
                "mesh",
                format!(
                    "has {} nodes, the assembly was built for {}",
                    mesh.nodes.len(),
                    self.dofs.n_nodes()
                ),
            ));
        }
        let npe = mesh.order.nodes_per_edge();
        let (points, weights) = edge_rule();
        let mut out = self.zero_forces();
        for edge in edges {
            if edge.nodes.len() != npe || edge.nodes.iter().any(|&n| n >= mesh.nodes.len()) {
                return Err(FemError::invalid(
                    "edges",
                    format!(
                        "edge {:?} must have {npe} nodes below {}",
                        edge.nodes,
                        mesh.nodes.len()
                    ),
                ));
            }
            for (s, w) in points.iter().zip(weights) {
                let (n, dn) = shape_and_derivative(npe, *s);
                let mut tangent = [0.0; 2];
                let mut position = [0.0; 2];
                for (a, &node) in edge.nodes.iter().enumerate() {
                    tangent[0] += dn[a] * mesh.nodes[node][0];
                    tangent[1] += dn[a] * mesh.nodes[node][1];
                    position[0] += n[a] * mesh.nodes[node][0];
                    position[1] += n[a] * mesh.nodes[node][1];
                }
                let weight = self.geometry.weight(position);
                for (a, &node) in edge.nodes.iter().enumerate() {
                    let f = load(*w, n[a], tangent);
                    for (comp, fc) in f.into_iter().enumerate() {
                        self.add_force(&mut out, node, comp, fc * weight);
                    }
                }
            }
        }
        Ok(out)
    }

    fn zero_forces(&self) -> (Vec<f64>, Vec<f64>) {
        (
            vec![0.0; self.dofs.n_free()],
            vec![0.0; self.dofs.n_prescribed()],
        )
    }

    fn add_force(&self, out: &mut (Vec<f64>, Vec<f64>), node: usize, comp: usize, f: f64) {
        match self.dofs.dof(node, comp) {
            Some(Dof::Free(i)) => out.0[i] += f,
            Some(Dof::Prescribed(j)) => out.1[j] += f,
            None => {}
        }
    }
}
