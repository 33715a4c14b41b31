//! The two dimensions of the operators (`docs/3d.md`): plane strain and axisymmetry, whose
//! stress points carry 4 Mandel components `(xx, yy, zz, √2 xy)` on triangle meshes, and
//! 3D, whose points carry 6 `(xx, yy, zz, √2 yz, √2 xz, √2 xy)` on tetrahedral meshes.
//! [`Assembly`](crate::Assembly), [`Model`](crate::Model) and [`State`](crate::State) are
//! generic over that Mandel size `D` (4 by default); [`Dimension`] says what each size
//! means, [`ElementMesh`] what the operators read from its meshes.
use crate::element::tetrahedron::{mandel_strain_rows, map_tetrahedron_point};
use crate::element::{map_point, ElementOrder};
use crate::error::MeshError;
use crate::geometry::Geometry;
use crate::mesh::Mesh;
use crate::mesh3::TetrahedralMesh;
use crate::quadrature::{self, tetrahedron};

/// The Mandel size `D` of a stress point, as a type: `Mandel<4>` (2D) or `Mandel<6>` (3D).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mandel<const D: usize>;

/// What a Mandel size means for the operators.
pub trait Dimension {
    /// Velocity components per node: 2 or 3.
    const COMPONENTS: usize;
    /// A position or a vector (m, N, m/s): `[f64; 2]` or `[f64; 3]`.
    type Point: Copy
        + Default
        + std::fmt::Debug
        + PartialEq
        + AsRef<[f64]>
        + AsMut<[f64]>
        + serde::Serialize
        + serde::de::DeserializeOwned
        + Send
        + Sync
        + 'static;
    /// The mesh: triangles (2D) or tetrahedra (3D).
    type Mesh: ElementMesh<Dim = Self, Point = Self::Point>;
    /// The geometry of an assembly that names none: plane strain, or 3D.
    const GEOMETRY: Geometry;

    /// The Mandel rows fed by velocity component `component` of a node whose shape
    /// function at a stress point at `position` has value `n` and physical gradient `g`:
    /// `ε̇_row += coefficient · v_component` (`ε̇ = sym ∇v`, eq. 12's `B`).
    fn strain_rows(
        geometry: Geometry,
        n: f64,
        g: [f64; 3],
        position: [f64; 3],
        component: usize,
    ) -> [Option<(usize, f64)>; 3];

    /// The first [`COMPONENTS`](Self::COMPONENTS) entries of `x`.
    fn point(x: [f64; 3]) -> Self::Point;
}

impl Dimension for Mandel<4> {
    const COMPONENTS: usize = 2;
    type Point = [f64; 2];
    type Mesh = Mesh;
    const GEOMETRY: Geometry = Geometry::PlaneStrain;

    fn strain_rows(
        geometry: Geometry,
        n: f64,
        g: [f64; 3],
        position: [f64; 3],
        component: usize,
    ) -> [Option<(usize, f64)>; 3] {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        // ε̇xx = ∂vx/∂x, ε̇yy = ∂vy/∂y, √2 ε̇xy = (∂vx/∂y + ∂vy/∂x)/√2; axisymmetric: the
        // hoop rate ε̇θθ = v_r / r (r > 0 at every stress point, `ElementMesh::check`).
        match component {
            0 => [
                Some((0, g[0])),
                Some((3, s * g[1])),
                (geometry == Geometry::Axisymmetric).then(|| (2, n / position[0])),
            ],
            _ => [Some((1, g[1])), Some((3, s * g[0])), None],
        }
    }

    fn point(x: [f64; 3]) -> [f64; 2] {
        [x[0], x[1]]
    }
}

impl Dimension for Mandel<6> {
    const COMPONENTS: usize = 3;
    type Point = [f64; 3];
    type Mesh = TetrahedralMesh;
    const GEOMETRY: Geometry = Geometry::ThreeDimensional;

    fn strain_rows(
        _: Geometry,
        _: f64,
        g: [f64; 3],
        _: [f64; 3],
        component: usize,
    ) -> [Option<(usize, f64)>; 3] {
        mandel_strain_rows(g, component).map(Some)
    }

    fn point(x: [f64; 3]) -> [f64; 3] {
        x
    }
}

/// One stiffness quadrature point of an element, mapped: where stresses live.
#[derive(Debug, Clone, PartialEq)]
pub struct StressPoint {
    /// Position (m; the third coordinate 0 in 2D).
    pub position: [f64; 3],
    /// `w · det J` (m² in 2D, m³ in 3D), before the geometry's weight.
    pub measure: f64,
    /// `N_a` of the element's nodes.
    pub shape: Vec<f64>,
    /// `∂N_a/∂x` (1/m; the third 0 in 2D).
    pub gradients: Vec<[f64; 3]>,
}

/// What the operators read from a mesh ([`Mesh`], [`TetrahedralMesh`]).
pub trait ElementMesh: Clone + std::fmt::Debug + Send + Sync {
    /// The Mandel size of its stress points.
    type Dim;
    /// A node's position (m).
    type Point: AsRef<[f64]>;

    fn order(&self) -> ElementOrder;
    fn node_positions(&self) -> &[Self::Point];
    /// Node indices of each element.
    fn elements(&self) -> &[Vec<usize>];
    /// Refuses a mesh the operators cannot use in `geometry`: bad elements, or a mesh of
    /// the other dimension (a triangle mesh in 3D, tetrahedra in plane strain or
    /// axisymmetry); axisymmetric: a node at `r < 0`.
    fn check(&self, geometry: Geometry) -> Result<(), MeshError>;
    /// Nodes on the axis of an axisymmetric mesh, whose radial velocity must be 0.
    fn axis_nodes(&self, geometry: Geometry) -> Vec<usize>;
    /// The stiffness rule's points of element `e` (mesh checked); an error names the
    /// element where `det J ≤ 0`.
    fn stress_points(&self, e: usize) -> Result<Vec<StressPoint>, MeshError>;
    /// `∫ N_a² w dV` over element `e` for each of its nodes, `w` the geometry's weight: the
    /// diagonal that HRZ lumping scales (`assembly/mass.rs`).
    fn mass_diagonal(&self, e: usize, geometry: Geometry) -> Result<Vec<f64>, MeshError>;
}

fn det_error(kind: &str, e: usize, rule: &str, xi: &[f64]) -> MeshError {
    MeshError::element(
        format!("{kind} {e}"),
        format!("det J ≤ 0 at {rule} quadrature point {xi:?}"),
    )
}

impl ElementMesh for Mesh {
    type Dim = Mandel<4>;
    type Point = [f64; 2];

    fn order(&self) -> ElementOrder {
        self.order
    }
    fn node_positions(&self) -> &[[f64; 2]] {
        &self.nodes
    }
    fn elements(&self) -> &[Vec<usize>] {
        &self.triangles
    }
    fn check(&self, geometry: Geometry) -> Result<(), MeshError> {
        if geometry == Geometry::ThreeDimensional {
            return Err(MeshError::invalid(
                "mesh",
                "a triangle mesh cannot be used in a 3D analysis (geometry = \"3d\" needs \
                 tetrahedra)"
                    .to_string(),
            ));
        }
        self.validate()?;
        geometry.check_mesh(self)
    }
    fn axis_nodes(&self, geometry: Geometry) -> Vec<usize> {
        geometry.axis_nodes(self)
    }
    fn stress_points(&self, e: usize) -> Result<Vec<StressPoint>, MeshError> {
        let coords = self.triangle_coordinates(e);
        let rule = quadrature::stiffness_rule(self.order);
        rule.points
            .iter()
            .zip(rule.weights)
            .map(|(xi, w)| {
                let m = map_point(self.order, &coords, *xi)
                    .ok_or_else(|| det_error("triangle", e, "stiffness", xi))?;
                Ok(StressPoint {
                    position: [m.position[0], m.position[1], 0.0],
                    measure: w * m.det_j,
                    shape: m.shape,
                    gradients: m.gradients.iter().map(|g| [g[0], g[1], 0.0]).collect(),
                })
            })
            .collect()
    }
    fn mass_diagonal(&self, e: usize, geometry: Geometry) -> Result<Vec<f64>, MeshError> {
        let coords = self.triangle_coordinates(e);
        let rule = quadrature::mass_rule();
        let mut diag = vec![0.0; coords.len()];
        for (xi, w) in rule.points.iter().zip(rule.weights) {
            let m = map_point(self.order, &coords, *xi)
                .ok_or_else(|| det_error("triangle", e, "mass", xi))?;
            let weight = geometry.weight(m.position);
            for (d, n) in diag.iter_mut().zip(&m.shape) {
                *d += w * m.det_j * n * n * weight;
            }
        }
        Ok(diag)
    }
}

impl ElementMesh for TetrahedralMesh {
    type Dim = Mandel<6>;
    type Point = [f64; 3];

    fn order(&self) -> ElementOrder {
        self.order
    }
    fn node_positions(&self) -> &[[f64; 3]] {
        &self.nodes
    }
    fn elements(&self) -> &[Vec<usize>] {
        &self.tetrahedra
    }
    fn check(&self, geometry: Geometry) -> Result<(), MeshError> {
        if geometry != Geometry::ThreeDimensional {
            return Err(MeshError::invalid(
                "mesh",
                format!(
                    "a tetrahedral mesh cannot be used in a {geometry:?} analysis (tetrahedra \
                     need geometry = \"3d\")"
                ),
            ));
        }
        if let Some((n, p)) = self
            .nodes
            .iter()
            .enumerate()
            .find(|(_, p)| !p.iter().all(|x| x.is_finite()))
        {
            return Err(MeshError::invalid(
                "mesh",
                format!("node {n} has coordinates {p:?}: they must be finite"),
            ));
        }
        self.check_elements()
    }
    fn axis_nodes(&self, _: Geometry) -> Vec<usize> {
        Vec::new()
    }
    fn stress_points(&self, e: usize) -> Result<Vec<StressPoint>, MeshError> {
        let coords = self.tetrahedron_coordinates(e);
        let rule = tetrahedron::stiffness_rule(self.order);
        rule.points
            .iter()
            .zip(rule.weights)
            .map(|(xi, w)| {
                let m = map_tetrahedron_point(self.order, &coords, *xi)
                    .ok_or_else(|| det_error("tetrahedron", e, "stiffness", xi))?;
                Ok(StressPoint {
                    position: m.position,
                    measure: w * m.det_j,
                    shape: m.shape,
                    gradients: m.gradients,
                })
            })
            .collect()
    }
    fn mass_diagonal(&self, e: usize, _: Geometry) -> Result<Vec<f64>, MeshError> {
        let coords = self.tetrahedron_coordinates(e);
        let rule = tetrahedron::mass_rule();
        let mut diag = vec![0.0; coords.len()];
        for (xi, w) in rule.points.iter().zip(rule.weights) {
            let m = map_tetrahedron_point(self.order, &coords, *xi)
                .ok_or_else(|| det_error("tetrahedron", e, "mass", xi))?;
            for (d, n) in diag.iter_mut().zip(&m.shape) {
                *d += w * m.det_j * n * n;
            }
        }
        Ok(diag)
    }
}
