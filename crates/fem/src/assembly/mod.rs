//! Global operators of eq. 15–16 on a mesh: Gauss points and volumes, the strain
//! operator `B` (free and prescribed columns), the lumped mass `M`, the compliance blocks
//! `S`, and nodal loads. Units: SI, per metre of thickness (plane strain), per radian
//! (axisymmetric, [`Geometry`], `docs/axisymmetry.md`) or per body (3D, `docs/3d.md`).
//! Generic over the Mandel size `D` ([`Dimension`]): 4 on triangles, 6 on tetrahedra.
mod face_loads;
mod gauss;
mod loads;
mod mass;
mod strain_operator;

use faer::sparse::SparseColMat;
use nalgebra::{SMatrix, SVector};

pub use strain_operator::{add_mul, add_mul_transpose, MANDEL};

use crate::dimension::{Dimension, ElementMesh, Mandel};
use crate::dofs::{Dof, DofMap};
use crate::error::FemError;
use crate::geometry::Geometry;
use gauss::GaussData;
use strain_operator::strain_operator;

/// The mass density of an assembly: one value, or one per Gauss point (checked).
#[derive(Clone, Copy)]
enum Density<'a> {
    Uniform(f64),
    PerPoint(&'a [f64]),
}

/// Everything the solver needs from the mesh (feeds `talus_ssn::Structured`:
/// `b = b_free`, `lumped_mass = lumped_mass_free`, `compliance = compliance_blocks(S₀)`).
#[derive(Debug, Clone)]
pub struct Assembly<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    /// Gauss point positions (m).
    pub gauss_points: Vec<<Mandel<D> as Dimension>::Point>,
    /// `V_p = w_p · det J · 1 m` (m³ per metre of thickness; `Σ V_p` = the mesh area), or
    /// `w_p · det J · r_p` (m³ per radian; `2π Σ V_p` = the solid's volume), or
    /// `w_p · det J` (m³, 3D).
    pub gauss_volumes: Vec<f64>,
    /// Element of each Gauss point.
    pub gauss_element: Vec<usize>,
    /// `(D·n_gp) × n_free`: row block p is `V_p · ε̇(x_p)` in Mandel form (xx, yy, zz = 0,
    /// √2 xy; axisymmetric: rr, yy, θθ = v_r/r, √2 ry; 3D: xx, yy, zz, √2 yz, √2 xz,
    /// √2 xy), one column per free velocity dof.
    pub b_free: SparseColMat<usize, f64>,
    /// `(D·n_gp) × n_prescribed`: the same rows for the prescribed dofs.
    pub b_prescribed: SparseColMat<usize, f64>,
    /// Lumped mass per free dof (kg/m in plane strain, kg per radian in axisymmetry, kg
    /// in 3D), all > 0.
    pub lumped_mass_free: Vec<f64>,
    /// Lumped mass per prescribed dof (same units).
    pub lumped_mass_prescribed: Vec<f64>,
    dofs: DofMap,
    gauss: GaussData,
    geometry: Geometry,
}

impl<const D: usize> Assembly<D>
where
    Mandel<D>: Dimension,
{
    /// Checks `mesh` ([`ElementMesh::check`]: [`Mesh::validate`](crate::Mesh::validate),
    /// [`TetrahedralMesh::check_elements`](crate::TetrahedralMesh::check_elements)) and
    /// builds `B`, the Gauss volumes and the lumped mass for mass density `density`
    /// (kg/m³, finite and > 0: `M⁻¹` must exist), in plane strain (triangles) or 3D
    /// (tetrahedra).
    pub fn new<M>(mesh: &M, dofs: &DofMap, density: f64) -> Result<Self, FemError>
    where
        M: ElementMesh<Dim = Mandel<D>>,
    {
        Self::with_geometry(mesh, dofs, density, <Mandel<D> as Dimension>::GEOMETRY)
    }

    /// [`new`](Self::new) in `geometry`. Axisymmetric: refuses a node at `r < 0`, a Gauss
    /// point at `r ≤ 0`, and a node on the axis whose radial velocity is free (prescribe
    /// it, to 0: [`Geometry::axis_nodes`]).
    pub fn with_geometry<M>(
        mesh: &M,
        dofs: &DofMap,
        density: f64,
        geometry: Geometry,
    ) -> Result<Self, FemError>
    where
        M: ElementMesh<Dim = Mandel<D>>,
    {
        if !(density.is_finite() && density > 0.0) {
            return Err(FemError::invalid(
                "density",
                format!("{density} kg/m³ must be finite and > 0 (the lumped mass is inverted)"),
            ));
        }
        Self::build(mesh, dofs, Density::Uniform(density), geometry)
    }

    /// [`with_geometry`](Self::with_geometry) with a mass density per Gauss point (soil
    /// layers, saturated soil below a water table): `densities[p]` (kg/m³, finite and > 0)
    /// belongs to the point `gauss_points[p]`, one per point of the stiffness rule in the
    /// order [`gauss_points`](Self::gauss_points) will have (element by element; P1 one
    /// point per triangle, P2 three). The lumped mass is that of `mass.rs` with the density
    /// inside the integral: P1 `m_a = Σ_p ρ_p V_p N_a(x_p)`; P2 the element mass
    /// `m_e = Σ_p ρ_p V_p` over the element's points, spread by the unchanged HRZ weights.
    /// With every entry equal to `ρ` the result is bit for bit that of `with_geometry(ρ)`.
    /// The points are known only once the mesh is checked, so the mesh's errors come first;
    /// then `densities` must have one entry per point (an error names the expected length)
    /// and each must be finite and > 0 (an error names the first bad index and value).
    pub fn with_point_densities<M>(
        mesh: &M,
        dofs: &DofMap,
        densities: &[f64],
        geometry: Geometry,
    ) -> Result<Self, FemError>
    where
        M: ElementMesh<Dim = Mandel<D>>,
    {
        Self::build(mesh, dofs, Density::PerPoint(densities), geometry)
    }

    /// Where the Gauss points of `mesh` in `geometry` will be, before any assembly: each
    /// point's element and position (m), in the order of `gauss_points`, so that a caller
    /// can give each its density ([`Assembly::with_point_densities`]).
    #[allow(clippy::type_complexity)]
    pub fn gauss_layout<M>(
        mesh: &M,
        geometry: Geometry,
    ) -> Result<(Vec<usize>, Vec<<Mandel<D> as Dimension>::Point>), FemError>
    where
        M: ElementMesh<Dim = Mandel<D>>,
    {
        mesh.check(geometry)?;
        let gauss = GaussData::new(mesh, geometry)?;
        let points = Self::points(&gauss);
        Ok((gauss.elements, points))
    }

    fn points(gauss: &GaussData) -> Vec<<Mandel<D> as Dimension>::Point> {
        gauss
            .positions
            .iter()
            .map(|x| <Mandel<D> as Dimension>::point(*x))
            .collect()
    }

    fn build<M>(
        mesh: &M,
        dofs: &DofMap,
        density: Density<'_>,
        geometry: Geometry,
    ) -> Result<Self, FemError>
    where
        M: ElementMesh<Dim = Mandel<D>>,
    {
        let components = <Mandel<D> as Dimension>::COMPONENTS;
        let n_nodes = mesh.node_positions().len();
        if dofs.n_nodes() != n_nodes || dofs.components() != components {
            return Err(FemError::invalid(
                "dofs",
                format!(
                    "the dof map has {} nodes of {} components, the mesh {n_nodes} of \
                     {components}",
                    dofs.n_nodes(),
                    dofs.components(),
                ),
            ));
        }
        mesh.check(geometry)?;
        if let Some(&n) = mesh
            .axis_nodes(geometry)
            .iter()
            .find(|&&n| dofs.free(n, 0).is_some())
        {
            return Err(FemError::invalid(
                "dofs",
                format!(
                    "node {n} lies on the axis (r = {:e} m) with a free radial velocity; \
                     prescribe u_r = 0 on the axis",
                    mesh.node_positions()[n].as_ref()[0]
                ),
            ));
        }
        let gauss = GaussData::new(mesh, geometry)?;
        if let Density::PerPoint(densities) = density {
            mass::check_densities(densities, gauss.len(), mass::Zero::Refused)?;
        }
        let (b_free, b_prescribed) = strain_operator::<D>(&gauss, dofs)?;
        let nodal = match density {
            Density::Uniform(rho) => mass::nodal_masses(mesh, &gauss, |_| rho)?,
            Density::PerPoint(rho) => mass::nodal_masses(mesh, &gauss, |p| rho[p])?,
        };
        let mut lumped_mass_free = vec![0.0; dofs.n_free()];
        let mut lumped_mass_prescribed = vec![0.0; dofs.n_prescribed()];
        for (node, m) in nodal.iter().enumerate() {
            for comp in 0..components {
                match dofs.dof(node, comp) {
                    Some(Dof::Free(i)) => {
                        if !(m.is_finite() && *m > 0.0) {
                            return Err(FemError::invalid(
                                "mesh",
                                format!("node {node} has mass {m} (does it belong to an element?); its free dofs cannot be inverted"),
                            ));
                        }
                        lumped_mass_free[i] = *m;
                    }
                    Some(Dof::Prescribed(j)) => lumped_mass_prescribed[j] = *m,
                    None => {}
                }
            }
        }
        Ok(Self {
            gauss_points: Self::points(&gauss),
            gauss_volumes: gauss.volumes.clone(),
            gauss_element: gauss.elements.clone(),
            b_free,
            b_prescribed,
            lumped_mass_free,
            lumped_mass_prescribed,
            dofs: dofs.clone(),
            gauss,
            geometry,
        })
    }

    /// Plane strain or axisymmetric.
    pub fn geometry(&self) -> Geometry {
        self.geometry
    }

    /// Number of Gauss points.
    pub fn n_points(&self) -> usize {
        self.gauss_volumes.len()
    }

    /// The dof map the operators were built with.
    pub fn dofs(&self) -> &DofMap {
        &self.dofs
    }

    /// Compliance blocks `S_p = V_p · S₀` (S₀ in 1/Pa, Mandel), the `S` of eq. 15 with the
    /// volume weighting that keeps `W` symmetric.
    pub fn compliance_blocks(&self, s0: &SMatrix<f64, D, D>) -> Vec<SMatrix<f64, D, D>> {
        self.gauss_volumes.iter().map(|v| s0 * *v).collect()
    }

    /// Strain (or strain rate) at each Gauss point, Mandel `(xx, yy, zz, √2 xy)` (zz: the
    /// hoop strain `θθ` in axisymmetry; 3D: `(xx, yy, zz, √2 yz, √2 xz, √2 xy)`), from a
    /// nodal field given as free and prescribed values: `(B_f u_f + B_p u_p)_p / V_p`.
    pub fn strain(
        &self,
        free: &[f64],
        prescribed: &[f64],
    ) -> Result<Vec<SVector<f64, D>>, FemError> {
        self.dofs.check_lengths(free, prescribed)?;
        let mut bu = vec![0.0; D * self.n_points()];
        add_mul(&self.b_free, free, &mut bu);
        add_mul(&self.b_prescribed, prescribed, &mut bu);
        Ok(bu
            .chunks_exact(D)
            .zip(&self.gauss_volumes)
            .map(|(e, v)| SVector::from_column_slice(e) / *v)
            .collect())
    }

    /// Internal force `Bᵀσ` (N/m, N per radian, or N in 3D) on free and prescribed dofs for Mandel stresses `σ`
    /// (Pa, flat, `D` per Gauss point). On prescribed dofs it is the reaction's main part.
    pub fn internal_force(&self, sigma: &[f64]) -> Result<(Vec<f64>, Vec<f64>), FemError> {
        if sigma.len() != D * self.n_points() {
            return Err(FemError::invalid(
                "sigma",
                format!(
                    "{} values for {} Gauss points × {D}",
                    sigma.len(),
                    self.n_points()
                ),
            ));
        }
        let mut free = vec![0.0; self.dofs.n_free()];
        let mut prescribed = vec![0.0; self.dofs.n_prescribed()];
        add_mul_transpose(&self.b_free, sigma, &mut free);
        add_mul_transpose(&self.b_prescribed, sigma, &mut prescribed);
        Ok((free, prescribed))
    }
}
