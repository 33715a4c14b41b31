//! Loads on the faces of a tetrahedral mesh (3D, N): tractions and normal pressures over
//! [`BoundaryFace`]s, the 3D counterparts of `loads.rs`' edge loads. Each face is first
//! checked to be on the boundary and turned outward
//! ([`TetrahedralMesh::orient_boundary_faces`]), as 2D edges are. A face is a P1 or P2
//! triangle `x(ξ, η)` in Gmsh order, counter-clockwise seen from outside, so
//! `∂x/∂ξ × ∂x/∂η dξ dη = n dA` with `n` the outward normal. Radon's 7-point rule
//! (degree 5) integrates `p N_a n dA` exactly for a `p` linear in space on flat and
//! curved (P2) faces: `N_a` has degree 2, `∂x/∂ξ × ∂x/∂η` degree 2 on a P2 face.
use super::loads::{check_vector, finite_pressure};
use super::Assembly;
use crate::error::FemError;
use crate::mesh3::{BoundaryFace, TetrahedralMesh};
use crate::quadrature::mass_rule;

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl Assembly<6> {
    /// Traction `f_a = ∫ N_a t dA` over `faces` of `mesh`, `t` in Pa (N/m² in global
    /// axes, e.g. `[0, −q, 0]` for a downward load q on a top face). Exact on flat faces.
    pub fn traction(
        &self,
        mesh: &TetrahedralMesh,
        faces: &[BoundaryFace],
        t: [f64; 3],
    ) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        check_vector("traction", &t)?;
        self.face_integral(
            mesh,
            faces,
            |_, _, _| Ok(()),
            |w, n, normal, _| {
                let da = normal.iter().map(|c| c * c).sum::<f64>().sqrt();
                t.map(|tc| w * n * da * tc)
            },
        )
    }

    /// Normal pressure `f_a = −p ∫ N_a n dA` over `faces`, `p` in Pa, positive pushing
    /// into the body (`n` outward). Exact on flat and curved (P2) faces; the forces of a
    /// closed surface sum to 0.
    pub fn pressure(
        &self,
        mesh: &TetrahedralMesh,
        faces: &[BoundaryFace],
        p: f64,
    ) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        if !p.is_finite() {
            return Err(FemError::invalid(
                "pressure",
                format!("{p} Pa must be finite"),
            ));
        }
        self.face_integral(
            mesh,
            faces,
            |_, _, _| Ok(()),
            |w, n, normal, _| normal.map(|c| -w * n * p * c),
        )
    }

    /// A pressure varying in space, `f_a = −∫ p(x) N_a n dA` (Pa, positive pushing into
    /// the body), e.g. water on a wall, `p = γ_w (h − y)` below the water level `y = h`:
    /// exact for a linear `p`. A non-finite `p` is an error naming the face (its index in
    /// `faces` and its nodes) and the quadrature point.
    pub fn pressure_with(
        &self,
        mesh: &TetrahedralMesh,
        faces: &[BoundaryFace],
        p: impl Fn([f64; 3]) -> f64,
    ) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        self.face_integral(
            mesh,
            faces,
            |k, q, x| finite_pressure(p(x), q, &x, ("face", k, &faces[k].nodes)),
            |w, n, normal, &pk| normal.map(|c| -w * n * pk * c),
        )
    }

    /// `Σ_faces Σ_points load(w, N_a, ∂x/∂ξ × ∂x/∂η, at(x))` added to every node `a` of
    /// each face, after checking the faces' node counts against the mesh.
    fn face_integral<T>(
        &self,
        mesh: &TetrahedralMesh,
        faces: &[BoundaryFace],
        at: impl Fn(usize, usize, [f64; 3]) -> Result<T, FemError>,
        load: impl Fn(f64, f64, [f64; 3], &T) -> [f64; 3],
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
        let faces = mesh.orient_boundary_faces(faces)?;
        let rule = mass_rule();
        let mut out = self.zero_forces();
        for (k, face) in faces.iter().enumerate() {
            for (q, (xi, w)) in rule.points.iter().zip(rule.weights).enumerate() {
                let n = mesh.order.shape_functions(*xi);
                let dn = mesh.order.reference_gradients(*xi);
                let (mut position, mut a, mut b) = ([0.0; 3], [0.0; 3], [0.0; 3]);
                for (i, &node) in face.nodes.iter().enumerate() {
                    let x = mesh.nodes[node];
                    for c in 0..3 {
                        position[c] += n[i] * x[c];
                        a[c] += dn[i][0] * x[c];
                        b[c] += dn[i][1] * x[c];
                    }
                }
                let value = at(k, q, position)?;
                let normal = cross(a, b);
                for (i, &node) in face.nodes.iter().enumerate() {
                    let f = load(*w, n[i], normal, &value);
                    for (comp, fc) in f.into_iter().enumerate() {
                        self.add_force(&mut out, node, comp, fc);
                    }
                }
            }
        }
        Ok(out)
    }
}
