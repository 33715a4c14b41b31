use nalgebra::{SMatrix, SVector};
use talus_cone::{Projection, Projector, Region, SecondOrderCone, VonMisesCylinder};

use crate::Relaxation;

/// The elastic domain of one point: a Drucker-Prager cone or, at φ = 0, a von Mises
/// cylinder; the whole space for a material that never yields.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum YieldSet<const D: usize> {
    Cone(SecondOrderCone<D>),
    Cylinder(VonMisesCylinder<D>),
    /// No yield surface (an elastic material): the projection is the identity, so the
    /// natural map `σ − P(σ − ρ y)` is `ρ z` and its root `z = 0`, no plastic flow.
    Everywhere,
}

impl<const D: usize> YieldSet<D> {
    /// The axis `n` of the set (pointing into compression for Drucker-Prager); `None` for
    /// the whole space.
    pub fn axis(&self) -> Option<&SVector<f64, D>> {
        match self {
            YieldSet::Cone(c) => Some(c.axis()),
            YieldSet::Cylinder(c) => Some(c.axis()),
            YieldSet::Everywhere => None,
        }
    }
}

impl<const D: usize> Projector<D> for YieldSet<D> {
    #[inline]
    fn project(&self, x: &SVector<f64, D>) -> Projection<D> {
        match self {
            YieldSet::Cone(c) => c.project(x),
            YieldSet::Cylinder(c) => c.project(x),
            YieldSet::Everywhere => Projection {
                point: *x,
                region: Region::Interior,
            },
        }
    }

    #[inline]
    fn project_with_jacobian(&self, x: &SVector<f64, D>) -> (Projection<D>, SMatrix<f64, D, D>) {
        match self {
            YieldSet::Cone(c) => c.project_with_jacobian(x),
            YieldSet::Cylinder(c) => c.project_with_jacobian(x),
            YieldSet::Everywhere => (self.project(x), SMatrix::identity()),
        }
    }

    fn contains(&self, x: &SVector<f64, D>, tol: f64) -> bool {
        match self {
            YieldSet::Cone(c) => c.contains(x, tol),
            YieldSet::Cylinder(c) => c.contains(x, tol),
            YieldSet::Everywhere => x.iter().all(|v| v.is_finite()),
        }
    }
}

/// The flow rule of one point in natural-map form (eq. 20, signs of `docs/conventions.md`,
/// 'Flow rule'):
/// `σ = P_K(σ − ρ y(z))` with `y(z) = z + κ ‖z_t‖ n`, `z = −ε̇ᵖ`, `z_t = z − (z·n) n`.
///
/// `κ = k_d (tan φ − tan θ) / √3` for Drucker-Prager in Mandel notation; `κ = 0` is
/// associative. In a cone's own axis coordinates (the Siconos files) `κ` is eq. 20's `α`.
///
/// With a [`Relaxation`] `N` (Duvaut–Lions, `docs/derivations.md`, 'Duvaut–Lions
/// relaxation') the rule holds at the shifted stress `p = σ + N z`:
/// `F = p − P_K(p − ρ y(z))`; without one, the rate-independent map above, untouched.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlowRule<const D: usize> {
    set: YieldSet<D>,
    kappa: f64,
    relaxation: Option<Relaxation>,
}

/// `F(σ) = σ − P_K(σ − ρ y(z))` at one point and the blocks of its generalized Jacobian:
/// `dF = (I − D) dσ + ρ G dz` with `D ∈ ∂P_K`, `G = D J_y`, `J_y = I + κ n uᵀ`; with a
/// relaxation `N`, `G = D J_y + (I − D) N / ρ` (`docs/derivations.md`, 'Duvaut–Lions
/// relaxation').
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NaturalMapLinearization<const D: usize> {
    pub residual: SVector<f64, D>,
    /// `D`, the Clarke Jacobian of the projection at `σ − ρ y(z)` (`p − ρ y(z)` relaxed).
    pub projection_jacobian: SMatrix<f64, D, D>,
    /// `G = D J_y` (`+ (I − D) N / ρ` relaxed); equals `D` when the rule is associative
    /// and not relaxed.
    pub coupling: SMatrix<f64, D, D>,
    pub region: Region,
}

impl<const D: usize> FlowRule<D> {
    /// A rule on a second-order cone with non-associative shift `kappa ≥ 0`.
    pub fn cone(cone: SecondOrderCone<D>, kappa: f64) -> Self {
        Self {
            set: YieldSet::Cone(cone),
            kappa,
            relaxation: None,
        }
    }

    /// An elastic point: no yield set, no plastic flow (`z = 0` at the root).
    pub fn elastic() -> Self {
        Self {
            set: YieldSet::Everywhere,
            kappa: 0.0,
            relaxation: None,
        }
    }

    /// The von Mises rule: associative, plastically incompressible.
    pub fn cylinder(cylinder: VonMisesCylinder<D>) -> Self {
        Self {
            set: YieldSet::Cylinder(cylinder),
            kappa: 0.0,
            relaxation: None,
        }
    }

    /// This rule with Duvaut–Lions relaxation `N` (`None`: rate-independent). An elastic
    /// point has no overstress and keeps `None`.
    pub fn with_relaxation(self, relaxation: Option<Relaxation>) -> Self {
        Self {
            relaxation: relaxation.filter(|_| !matches!(self.set, YieldSet::Everywhere)),
            ..self
        }
    }

    pub fn relaxation(&self) -> Option<&Relaxation> {
        self.relaxation.as_ref()
    }

    pub fn yield_set(&self) -> &YieldSet<D> {
        &self.set
    }

    pub fn kappa(&self) -> f64 {
        self.kappa
    }

    pub fn is_associative(&self) -> bool {
        self.kappa == 0.0
    }

    /// `y(z) = z + κ ‖z_t‖ n` (eq. 20's `(z^h + α‖dev z‖, dev z)` in axis coordinates).
    #[inline]
    pub fn shifted(&self, z: &SVector<f64, D>) -> SVector<f64, D> {
        let Some(n) = self.set.axis().filter(|_| self.kappa != 0.0) else {
            return *z;
        };
        let zt = z - n * z.dot(n);
        z + n * (self.kappa * zt.norm())
    }

    /// `F(σ) = σ − P_K(σ − ρ y(z))`; zero exactly when (σ, −z) satisfy the flow rule. With
    /// a relaxation `N`, `σ` is read as `p = σ + N z` (`docs/derivations.md`, 'Duvaut–Lions
    /// relaxation', eq. DL4).
    #[inline]
    pub fn natural_map_residual(
        &self,
        sigma: &SVector<f64, D>,
        z: &SVector<f64, D>,
        rho: f64,
    ) -> SVector<f64, D> {
        let p = self.relaxed(sigma, z);
        p - self.set.project(&(p - self.shifted(z) * rho)).point
    }

    /// `p = σ + N z`, or `σ` without relaxation.
    #[inline]
    fn relaxed(&self, sigma: &SVector<f64, D>, z: &SVector<f64, D>) -> SVector<f64, D> {
        match &self.relaxation {
            Some(n) => sigma + n.apply(z),
            None => *sigma,
        }
    }

    /// The residual and its Jacobian blocks. At `z_t = 0` the gradient of `‖z_t‖` is taken
    /// as 0, an element of its Clarke subdifferential (`docs/derivations.md`, 'Clarke elements
    /// at the kinks'). With a relaxation, `dF = (I − D) dσ + [(I − D) N + ρ D J_y] dz`
    /// (eq. DL4).
    #[inline]
    pub fn natural_map_linearization(
        &self,
        sigma: &SVector<f64, D>,
        z: &SVector<f64, D>,
        rho: f64,
    ) -> NaturalMapLinearization<D> {
        let (y, jy) = match self.set.axis().filter(|_| self.kappa != 0.0) {
            None => (*z, None),
            Some(&n) => {
                let zt = z - n * z.dot(&n);
                let r = zt.norm();
                let y = z + n * (self.kappa * r);
                let jy = (r > 0.0).then(|| n * (zt / r).transpose() * self.kappa);
                (y, jy)
            }
        };
        let p = self.relaxed(sigma, z);
        let (proj, d) = self.set.project_with_jacobian(&(p - y * rho));
        // G = D (I + κ n uᵀ) = D + (D n)(κ u)ᵀ.
        let mut coupling = match jy {
            Some(extra) => d + d * extra,
            None => d,
        };
        if let Some(n) = &self.relaxation {
            coupling += (SMatrix::<f64, D, D>::identity() - d) * n.matrix::<D>() / rho;
        }
        NaturalMapLinearization {
            residual: p - proj.point,
            projection_jacobian: d,
            coupling,
            region: proj.region,
        }
    }
}
