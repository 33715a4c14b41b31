//! Consistent nodal forces `f` of eq. 12 (N per metre of thickness, or per radian in
//! axisymmetry, where every integrand carries `r`: `docs/axisymmetry.md`; N in 3D), split
//! into free and prescribed dofs like the columns of `B`. Body and point forces serve both
//! dimensions; edge loads are 2D's, face loads 3D's (`face_loads.rs`). Forces on prescribed dofs do not move the
//! solution but enter the reaction (`docs/derivations.md`, 'Prescribed velocities and the
//! reaction').
use super::mass::{check_densities, Zero};
use super::Assembly;
use crate::dimension::{Dimension, Mandel};
use crate::dofs::Dof;
use crate::element::edge::shape_and_derivative;
use crate::error::FemError;
use crate::mesh::{BoundaryEdge, Mesh};
use crate::quadrature::edge_rule;

// 4-point Gauss-Legendre on [0, 1] (degree 7), for a pressure varying along the edge:
// `p(x(s)) N_a(s) x′(s) r(s)` has degree 7 for a linear p on a curved P2 edge in
// axisymmetry. Points 1/2 ∓ √(3/7 ± 2/7 √(6/5))/2, weights (18 ∓ √30)/72.
const GL4_POINTS: [f64; 4] = [
    0.5 - 0.430_568_155_797_026_3,
    0.5 - 0.169_990_521_792_428_13,
    0.5 + 0.169_990_521_792_428_13,
    0.5 + 0.430_568_155_797_026_3,
];
const GL4_WEIGHTS: [f64; 4] = [
    0.173_927_422_568_726_93,
    0.326_072_577_431_273_07,
    0.326_072_577_431_273_07,
    0.173_927_422_568_726_93,
];

/// A varying pressure's value `p` (Pa) at quadrature point `q` (at `x`) of facet `k`
/// (`kind` "edge" or "face", its nodes given), refused unless finite.
pub(super) fn finite_pressure(
    p: f64,
    q: usize,
    x: &[f64],
    (kind, k, nodes): (&str, usize, &[usize]),
) -> Result<f64, FemError> {
    if p.is_finite() {
        Ok(p)
    } else {
        Err(FemError::invalid(
            "pressure",
            format!(
                "p = {p} Pa at quadrature point {q} ({x:?}) of {kind} {k} (nodes {nodes:?}) \
                 must be finite"
            ),
        ))
    }
}

pub(super) fn check_vector(field: &'static str, v: &[f64]) -> Result<(), FemError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(FemError::invalid(field, format!("{v:?} must be finite")))
    }
}

impl<const D: usize> Assembly<D>
where
    Mandel<D>: Dimension,
{
    /// Body force `f_a = ∫ N_a ρ g dA` (gravity: `g = [0, −9.81]` m/s², y up; axisymmetric:
    /// `∫ N_a ρ g r dA`, through the Gauss volumes), integrated with the Gauss points (exact on affine triangles; on P2 the vertices get 0 and the
    /// mid nodes ρgA/3, as consistency demands). `density` (kg/m³, ≥ 0) may differ from the
    /// inertial one, e.g. 0 for weightless soil.
    pub fn body_force(
        &self,
        density: f64,
        g: <Mandel<D> as Dimension>::Point,
    ) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        if !(density.is_finite() && density >= 0.0) {
            return Err(FemError::invalid(
                "density",
                format!("{density} kg/m³ must be finite and ≥ 0"),
            ));
        }
        check_vector("gravity", g.as_ref())?;
        Ok(self.weight(|_| density, g.as_ref()))
    }

    /// [`body_force`](Self::body_force) with a density per Gauss point (soil layers,
    /// saturated soil below a water table): `f_a = Σ_p ρ_p V_p N_a(x_p) g`, `densities[p]`
    /// (kg/m³) the density at `gauss_points[p]`, one per point. As in `body_force`, a
    /// density may be 0 (a weightless layer; unlike the inertial densities of
    /// [`with_point_densities`](Self::with_point_densities)), and with every entry equal to
    /// `ρ` the forces are bit for bit those of `body_force(ρ, g)`. Errors name `densities`
    /// (its expected length, or the first entry not finite and ≥ 0 with its index) or
    /// `gravity`.
    pub fn body_force_at_points(
        &self,
        densities: &[f64],
        g: <Mandel<D> as Dimension>::Point,
    ) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        check_densities(densities, self.gauss.len(), Zero::Accepted)?;
        check_vector("gravity", g.as_ref())?;
        Ok(self.weight(|p| densities[p], g.as_ref()))
    }

    /// `Σ_p density(p) V_p N_a(x_p) g` on every node `a` of point `p`'s element.
    fn weight(&self, density: impl Fn(usize) -> f64, g: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut out = self.zero_forces();
        for p in 0..self.gauss.len() {
            let rho = density(p);
            let v = self.gauss.volumes[p];
            for (node, n, _) in self.gauss.point(p) {
                for (comp, gc) in g.iter().enumerate() {
                    self.add_force(&mut out, node, comp, rho * v * n * gc);
                }
            }
        }
        out
    }

    /// A force `[fx, fy]` (3D: `[fx, fy, fz]`, N) on one node, split into free and prescribed dofs like the
    /// other loads (a component on a prescribed dof enters only the reaction). Plane
    /// strain: N per metre of thickness (a line load along the out-of-plane direction).
    /// Axisymmetric: N per radian, like every load there (`[F_r, F_y]`): a ring load of
    /// `q` N per metre of circumference at radius `r` is `q r` per radian, and a total axial
    /// force `P` on an axis node is `P / 2π` per radian (its radial component falls on the
    /// prescribed `u_r = 0`). Errors name `node` (out of range) or `force` (not finite).
    pub fn point_force(
        &self,
        node: usize,
        force: <Mandel<D> as Dimension>::Point,
    ) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        if node >= self.dofs.n_nodes() {
            return Err(FemError::invalid(
                "node",
                format!(
                    "node {node} is out of range: the mesh has {} nodes",
                    self.dofs.n_nodes()
                ),
            ));
        }
        check_vector("force", force.as_ref())?;
        let mut out = self.zero_forces();
        for (comp, fc) in force.as_ref().iter().enumerate() {
            self.add_force(&mut out, node, comp, *fc);
        }
        Ok(out)
    }

    pub(super) fn zero_forces(&self) -> (Vec<f64>, Vec<f64>) {
        (
            vec![0.0; self.dofs.n_free()],
            vec![0.0; self.dofs.n_prescribed()],
        )
    }

    pub(super) fn add_force(
        &self,
        out: &mut (Vec<f64>, Vec<f64>),
        node: usize,
        comp: usize,
        f: f64,
    ) {
        match self.dofs.dof(node, comp) {
            Some(Dof::Free(i)) => out.0[i] += f,
            Some(Dof::Prescribed(j)) => out.1[j] += f,
            None => {}
        }
    }
}

/// Edge loads of a triangle mesh (2D).
impl Assembly<4> {
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
        check_vector("traction", &t)?;
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

    /// Normal pressure varying in space, `f_a = −∫ p(x) N_a n ds` over `edges` (Pa,
    /// positive pushing into the body, `n` the outward normal: the convention of
    /// [`pressure`](Self::pressure), whose edge orientation it shares), e.g. water on a
    /// wall, `p = γ_w (h − y)` below the free surface `y = h` (and `max(0, ·)` above it).
    /// `p` is called at each quadrature point `x(s)` of each edge. A 4-point Gauss-Legendre
    /// rule (degree 7) per edge makes it exact for a linear `p` on straight and curved (P2)
    /// edges in both geometries (axisymmetric, per radian: `−∫ p N_a n r ds`, the integrand
    /// one degree higher), and on straight edges for `p` of degree ≤ 4; a `p` with a kink
    /// inside an edge (a water table crossing it) is integrated approximately, so put a node
    /// there. With a constant `p` the forces equal those of `pressure` to rounding (not bit
    /// for bit: the rules differ). A non-finite `p` is an error naming the edge (its index
    /// in `edges` and its nodes) and the quadrature point.
    pub fn pressure_with(
        &self,
        mesh: &Mesh,
        edges: &[BoundaryEdge],
        p: impl Fn([f64; 2]) -> f64,
    ) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        let oriented = mesh.orient_boundary_edges(edges)?;
        self.edge_integral_at(
            mesh,
            &oriented,
            (&GL4_POINTS, &GL4_WEIGHTS),
            |k, q, x| finite_pressure(p(x), q, &x, ("edge", k, &edges[k].nodes)),
            |w, n, tangent, &pk| [-w * n * pk * tangent[1], w * n * pk * tangent[0]],
        )
    }

    /// `Σ_edges Σ_gauss r load(w, N_a, x′(s))` added to every node `a` of each edge (`r`
    /// the geometry's weight at the point, 1 in plane strain), after checking the edges'
    /// node counts against the mesh; the 3-point rule.
    fn edge_integral(
        &self,
        mesh: &Mesh,
        edges: &[BoundaryEdge],
        load: impl Fn(f64, f64, [f64; 2]) -> [f64; 2],
    ) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        self.edge_integral_at(
            mesh,
            edges,
            edge_rule(),
            |_, _, _| Ok(()),
            |w, n, tangent, _| load(w, n, tangent),
        )
    }

    /// [`edge_integral`](Self::edge_integral) with the rule `(points, weights)` on
    /// `[0, 1]` and a value `at(edge index, point index, x(s))` computed once per
    /// quadrature point (before the nodes' loads, which receive it), whose error stops the
    /// integral.
    fn edge_integral_at<T>(
        &self,
        mesh: &Mesh,
        edges: &[BoundaryEdge],
        (points, weights): (&[f64], &[f64]),
        at: impl Fn(usize, usize, [f64; 2]) -> Result<T, FemError>,
        load: impl Fn(f64, f64, [f64; 2], &T) -> [f64; 2],
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
        let mut out = self.zero_forces();
        for (k, edge) in edges.iter().enumerate() {
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
            for (q, (s, w)) in points.iter().zip(weights).enumerate() {
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
                let value = at(k, q, position)?;
                for (a, &node) in edge.nodes.iter().enumerate() {
                    let f = load(*w, n[a], tangent, &value);
                    for (comp, fc) in f.into_iter().enumerate() {
                        self.add_force(&mut out, node, comp, fc * weight);
                    }
                }
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_point_rule_is_exact_to_degree_seven() {
        for k in 0..=7 {
            let q: f64 = GL4_POINTS
                .iter()
                .zip(GL4_WEIGHTS)
                .map(|(s, w)| w * s.powi(k))
                .sum();
            let exact = 1.0 / f64::from(k as u32 + 1);
            assert!((q - exact).abs() < 1e-15, "s^{k}: {q} vs {exact}");
        }
        // and not beyond
        let q: f64 = GL4_POINTS
            .iter()
            .zip(GL4_WEIGHTS)
            .map(|(s, w)| w * s.powi(8))
            .sum();
        assert!((q - 1.0 / 9.0).abs() > 1e-6);
    }
}
