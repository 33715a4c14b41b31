//! Property tests of the projections onto the translated second-order cone and the von Mises
//! cylinder, in D = 3, 4 and 6. Every property is written once as a generic function over
//! `const D: usize` and run for each D by [`check`].
//!
//! Tolerances are relative to the scale `S` of the data (the largest norm among the points,
//! the apex and the radius involved). A correct implementation computes each result with
//! O(D) roundings of quantities no larger than `S`, so it is within a few ulps of `S`: over
//! many runs the tests pass with `ROUND = 6` and fail with `ROUND = 2`; `ROUND * EPS * S`
//! with `ROUND = 16` leaves a margin of about 3 over the largest errors observed.

use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt::Debug;

use nalgebra::{vector, DMatrix, SMatrix, SVector};
use proptest::prelude::*;
use proptest::test_runner::{TestCaseError, TestRunner};
use talus_cone::{
    project_batch, ConeError, Parallelism, Projection, Projector, Region, SecondOrderCone,
    VonMisesCylinder,
};

type V<const D: usize> = SVector<f64, D>;
type M<const D: usize> = SMatrix<f64, D, D>;

const EPS: f64 = f64::EPSILON;
/// Allowed rounding error in units of `EPS * S` (see the module comment).
const ROUND: f64 = 16.0;
/// Proptest cases per property and per dimension (each case takes microseconds in release;
/// the whole file runs in about a second).
const CASES: u32 = 8192;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: CASES,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Runs one property for one dimension; panics with the (shrunk) counter-example.
fn check<S>(name: &str, strategy: S, test: impl Fn(S::Value) -> Result<(), TestCaseError>)
where
    S: Strategy,
    S::Value: Debug,
{
    let mut runner = TestRunner::new(config());
    if let Err(e) = runner.run(&strategy, test) {
        panic!("{name}: {e}");
    }
}

/// Runs a generic property for D = 3, 4 and 6.
macro_rules! for_dims {
    ($name:literal, $strategy:ident, $prop:ident) => {
        check(concat!($name, ", D = 3"), $strategy::<3>(), |v| {
            $prop::<3>(v)
        });
        check(concat!($name, ", D = 4"), $strategy::<4>(), |v| {
            $prop::<4>(v)
        });
        check(concat!($name, ", D = 6"), $strategy::<6>(), |v| {
            $prop::<6>(v)
        });
    };
}

// ---------------------------------------------------------------------------------------------
// Strategies and geometry helpers
// ---------------------------------------------------------------------------------------------

fn pow10(e: f64) -> f64 {
    10f64.powf(e)
}

fn unit_box<const D: usize>() -> impl Strategy<Value = [f64; D]> + Clone {
    proptest::array::uniform(-1.0f64..1.0)
}

/// An axis as handed to the constructors (not normalised, length 1e-3..1e3): axis-aligned
/// (either sign) a quarter of the time, otherwise a random direction.
fn raw_axis<const D: usize>() -> impl Strategy<Value = V<D>> {
    let aligned = (0..D, any::<bool>(), -3.0f64..=3.0).prop_map(|(k, neg, e)| {
        let mut v = V::<D>::zeros();
        v[k] = if neg { -pow10(e) } else { pow10(e) };
        v
    });
    let random = (unit_box::<D>(), -3.0f64..=3.0)
        .prop_filter("axis away from zero", |(v, _)| {
            V::<D>::from(*v).norm() > 0.1
        })
        .prop_map(|(v, e)| V::<D>::from(v) * pow10(e));
    prop_oneof![1 => aligned, 3 => random]
}

/// A unit vector orthogonal to the unit vector `n`, from a raw direction.
fn transverse<const D: usize>(n: &V<D>, raw: &[f64; D]) -> V<D> {
    let v = V::<D>::from(*raw);
    let mut e = v - n * n.dot(&v);
    if e.norm() < 1e-3 {
        // Fall back on the basis vector least aligned with n.
        let k = (0..D)
            .min_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs()))
            .unwrap();
        e = -n * n[k];
        e[k] += 1.0;
    }
    e.normalize()
}

fn max_abs<const D: usize>(m: &M<D>) -> f64 {
    m.iter().fold(0.0f64, |acc, v| acc.max(v.abs()))
}

fn same_bits<const D: usize>(a: &V<D>, b: &V<D>) -> bool {
    a.iter()
        .zip(b.iter())
        .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Checks that a projection Jacobian is symmetric with eigenvalues in [0, 1].
fn check_symmetric_contraction<const D: usize>(j: &M<D>) -> Result<(), TestCaseError> {
    // Entries are O(1) and J is built from symmetric products, so symmetry holds to an ulp;
    // the eigen-solver adds its own O(D EPS) rounding (observed up to 10 EPS): allow 64 EPS.
    prop_assert!(
        max_abs(&(j - j.transpose())) <= 4.0 * EPS,
        "not symmetric: {j}"
    );
    let eig = DMatrix::from_iterator(D, D, j.iter().copied()).symmetric_eigenvalues();
    for l in eig.iter() {
        prop_assert!(
            (-64.0 * EPS..=1.0 + 64.0 * EPS).contains(l),
            "eigenvalue {l} outside [0, 1] in {j}"
        );
    }
    Ok(())
}

/// Central finite differences of `p.project` with step `h`; also returns whether every stencil
/// point stayed in the region of `x` (the tests sample `x` so that it does).
fn fd_jacobian<const D: usize, P: Projector<D>>(p: &P, x: &V<D>, h: f64) -> (M<D>, bool) {
    let region = p.project(x).region;
    let mut same = true;
    let mut j = M::<D>::zeros();
    for k in 0..D {
        let (mut xp, mut xm) = (*x, *x);
        xp[k] += h;
        xm[k] -= h;
        let (pp, pm) = (p.project(&xp), p.project(&xm));
        same &= pp.region == region && pm.region == region;
        // Divide by the step actually taken after rounding x ± h.
        j.set_column(k, &((pp.point - pm.point) / (xp[k] - xm[k])));
    }
    (j, same)
}

/// FD step and tolerance at a point whose region boundaries (and, for the lateral surface,
/// the axis, where u = x_t/r is singular) are at least `rho` away, in data of scale `s`.
/// Central differences err by ~(h/rho)² (third derivatives scale as 1/rho²) plus
/// ~EPS S/h (rounding of P, itself ~EPS S); h = rho (EPS S/rho)^(1/3) balances the two, both
/// then being q = (EPS S/rho)^(2/3). Observed errors stay below q (the tests fail at q/4);
/// the tolerance allows 8 q, plus a floor for q → 0.
fn fd_step_and_tol(rho: f64, s: f64) -> (f64, f64) {
    let c = (EPS * s / rho).cbrt();
    (rho * c, 8.0 * c * c + 1e-12)
}

#[derive(Debug, Clone)]
struct ConeCase<const D: usize> {
    cone: SecondOrderCone<D>,
    /// Unit axis, as normalised by the constructor.
    n: V<D>,
    a: V<D>,
    eta: f64,
    /// Scale of the data: the apex is `s` times a vector of the unit box, points are at
    /// `s * 10^mag` from the apex.
    s: f64,
}

/// Random cone: η log-uniform in [1e-3, 1e3], scale log-uniform in [1e-9, 1e9], apex at the
/// origin half of the time and otherwise a random point at that scale.
fn cone_case<const D: usize>() -> impl Strategy<Value = ConeCase<D>> {
    (
        raw_axis::<D>(),
        unit_box::<D>(),
        any::<bool>(),
        -3.0f64..=3.0,
        -9.0f64..=9.0,
    )
        .prop_map(|(axis, apex, has_apex, eta_exp, s_exp)| {
            let (eta, s) = (pow10(eta_exp), pow10(s_exp));
            let a = if has_apex {
                V::<D>::from(apex) * s
            } else {
                V::<D>::zeros()
            };
            let cone = SecondOrderCone::try_new(axis, a, eta).unwrap();
            ConeCase {
                n: *cone.axis(),
                a,
                eta,
                s,
                cone,
            }
        })
}

/// Where to put a point relative to a cone, in the meridian half-plane spanned by `n` and a
/// transverse direction `e`: at angle θ from the axis and distance `s * 10^mag` from the apex.
#[derive(Debug, Clone, Copy)]
struct Spot<const D: usize> {
    /// 0: interior, 1: lateral-surface region, 2: polar region, 3: any angle, 4: the apex.
    kind: u8,
    /// Position of θ within the angular interval of `kind`.
    frac: f64,
    dir: [f64; D],
    mag: f64,
}

fn spot_with<const D: usize>(
    kinds: impl Strategy<Value = u8>,
    mag_lo: f64,
    mag_hi: f64,
) -> impl Strategy<Value = Spot<D>> {
    (kinds, 0.0f64..=1.0, unit_box::<D>(), mag_lo..=mag_hi).prop_map(|(kind, frac, dir, mag)| {
        Spot {
            kind,
            frac,
            dir,
            mag,
        }
    })
}

/// Any spot, down to 1e-8 of the data scale from the apex (points near the apex).
fn spot<const D: usize>() -> impl Strategy<Value = Spot<D>> {
    let kinds =
        prop_oneof![4 => Just(0u8), 4 => Just(1u8), 4 => Just(2u8), 3 => Just(3u8), 1 => Just(4u8)];
    spot_with(kinds, -8.0, 1.0)
}

/// A spot in region 0, 1 or 2, at least 1e-2 of the data scale from the apex (so that finite
/// differences or side points can resolve it).
fn region_spot<const D: usize>() -> impl Strategy<Value = Spot<D>> {
    spot_with(0u8..3, -2.0, 1.0)
}

impl<const D: usize> ConeCase<D> {
    /// Half-opening angle of the cone.
    fn alpha(&self) -> f64 {
        self.eta.atan()
    }

    /// Angular interval (from the axis) of a region: the polar cone has half-opening
    /// atan(1/η) = π/2 − α around −n.
    fn interval(&self, kind: u8) -> (f64, f64) {
        let alpha = self.alpha();
        match kind {
            0 => (0.0, alpha),
            1 => (alpha, alpha + FRAC_PI_2),
            2 => (alpha + FRAC_PI_2, PI),
            _ => (0.0, PI),
        }
    }

    /// The point of `spot`, θ kept a fraction `margin` of the interval away from its ends.
    fn point(&self, spot: &Spot<D>, margin: f64) -> V<D> {
        if spot.kind == 4 {
            return self.a;
        }
        let (lo, hi) = self.interval(spot.kind);
        let theta = lo + (hi - lo) * (margin + (1.0 - 2.0 * margin) * spot.frac);
        self.at(
            theta,
            self.s * pow10(spot.mag),
            &transverse(&self.n, &spot.dir),
        )
    }

    fn at(&self, theta: f64, m: f64, e: &V<D>) -> V<D> {
        self.a + (self.n * theta.cos() + e * theta.sin()) * m
    }

    /// (z_n, ‖z_t‖) of z = y − apex.
    fn meridian(&self, y: &V<D>) -> (f64, f64) {
        let z = y - self.a;
        let zn = z.dot(&self.n);
        (zn, (z - self.n * zn).norm())
    }

    /// (‖z_t‖ − η z_n)₊ / √(1+η²): the distance to the cone of a point off the polar region
    /// and a lower bound of it otherwise; zero exactly in the cone.
    fn excess(&self, y: &V<D>) -> f64 {
        let (zn, r) = self.meridian(y);
        (r - self.eta * zn).max(0.0) / (1.0 + self.eta * self.eta).sqrt()
    }

    fn scale(&self, ys: &[&V<D>]) -> f64 {
        ys.iter()
            .fold(self.a.norm(), |acc, y| acc.max(y.norm()))
            .max(f64::MIN_POSITIVE)
    }
}

fn region_of(kind: u8) -> Region {
    match kind {
        0 => Region::Interior,
        1 => Region::Boundary,
        _ => Region::Polar,
    }
}

// ---------------------------------------------------------------------------------------------
// Second-order cone
// ---------------------------------------------------------------------------------------------

fn cone_and_spot<const D: usize>() -> impl Strategy<Value = (ConeCase<D>, Spot<D>)> {
    (cone_case::<D>(), spot::<D>())
}

fn prop_cone_feasible_idempotent<const D: usize>(
    (c, sp): (ConeCase<D>, Spot<D>),
) -> Result<(), TestCaseError> {
    let x = c.point(&sp, 0.0);
    let p = c.cone.project(&x);
    let s = c.scale(&[&x]);
    let tol = ROUND * EPS * s;
    prop_assert!(c.excess(&p.point) <= tol, "P(x) = {} outside", p.point);
    // `contains(y, tol)` compares ‖z_t‖ − η z_n, √(1+η²) times the distance to the cone, with
    // tol · max(‖y‖, ‖apex‖); P(x) carries errors ~EPS S, S the scale of x, which may be far
    // larger than ‖P(x)‖ (x near the polar region): the tolerance is rescaled accordingly.
    let own_scale = c.scale(&[&p.point]);
    // (Capped at 1 so that it stays finite when P(x) rounds to 0.)
    let rel_tol = (ROUND * EPS * (1.0 + c.eta * c.eta).sqrt() * (s / own_scale)).min(1.0);
    prop_assert!(c.cone.contains(&p.point, rel_tol));
    let pp = c.cone.project(&p.point);
    prop_assert!(
        (pp.point - p.point).norm() <= tol,
        "P(P(x)) = {} ≠ {}",
        pp.point,
        p.point
    );
    // The Jacobian variant classifies identically and projects to the same point up to rounding.
    let (pj, _) = c.cone.project_with_jacobian(&x);
    prop_assert_eq!(pj.region, p.region);
    prop_assert!((pj.point - p.point).norm() <= tol);
    Ok(())
}

/// x and y either independent or y a small perturbation of x (relative 1e-12..1).
fn cone_pair<const D: usize>(
) -> impl Strategy<Value = (ConeCase<D>, Spot<D>, Spot<D>, Option<(f64, [f64; D])>)> {
    (
        cone_case::<D>(),
        spot::<D>(),
        spot::<D>(),
        proptest::option::of((-12.0f64..=0.0, unit_box::<D>())),
    )
}

fn prop_cone_non_expansive<const D: usize>(
    (c, sx, sy, pert): (ConeCase<D>, Spot<D>, Spot<D>, Option<(f64, [f64; D])>),
) -> Result<(), TestCaseError> {
    let x = c.point(&sx, 0.0);
    let y = match pert {
        None => c.point(&sy, 0.0),
        Some((e, dir)) => x + V::<D>::from(dir).normalize() * (c.s * pow10(sx.mag) * pow10(e)),
    };
    let (px, py) = (c.cone.project(&x).point, c.cone.project(&y).point);
    let s = c.scale(&[&x, &y]);
    prop_assert!(
        (px - py).norm() <= (x - y).norm() + ROUND * EPS * s,
        "‖P(x) − P(y)‖ = {} > ‖x − y‖ = {}",
        (px - py).norm(),
        (x - y).norm()
    );
    Ok(())
}

/// y = apex + t (n + γ η e') with t ≥ 0, γ ∈ [0, 1]: a point of the cone by construction.
fn cone_vi_case<const D: usize>(
) -> impl Strategy<Value = (ConeCase<D>, Spot<D>, (f64, f64, [f64; D]))> {
    (
        cone_case::<D>(),
        spot::<D>(),
        (-8.0f64..=1.0, 0.0f64..=1.0, unit_box::<D>()),
    )
}

fn prop_cone_variational_inequality<const D: usize>(
    (c, sp, (t_exp, gamma, dir)): (ConeCase<D>, Spot<D>, (f64, f64, [f64; D])),
) -> Result<(), TestCaseError> {
    let x = c.point(&sp, 0.0);
    let e = transverse(&c.n, &dir);
    let y = c.a + (c.n + e * (gamma * c.eta)) * (c.s * pow10(t_exp));
    let p = c.cone.project(&x).point;
    // P and y carry errors ~EPS S (y may sit that far outside), each moving the product by
    // at most that times the other factor.
    let err = ROUND * EPS * c.scale(&[&x, &y]);
    let (dx, dy) = (x - p, y - p);
    prop_assert!(
        dx.dot(&dy) <= err * (dx.norm() + dy.norm()) + err * err,
        "(x − P)·(y − P) = {} > 0",
        dx.dot(&dy)
    );
    Ok(())
}

fn prop_cone_moreau<const D: usize>((c, sp): (ConeCase<D>, Spot<D>)) -> Result<(), TestCaseError> {
    let x = c.point(&sp, 0.0);
    let z = x - c.a;
    let k0 = SecondOrderCone::try_new(c.n, V::<D>::zeros(), c.eta).unwrap();
    let polar = SecondOrderCone::try_new(-c.n, V::<D>::zeros(), 1.0 / c.eta).unwrap();
    let (p, q) = (k0.project(&z), polar.project(&z));
    // Both parts are computed from z with O(D) roundings: errors ~EPS ‖z‖.
    let zn = z.norm();
    let tol = ROUND * EPS * zn;
    prop_assert!(
        (z - p.point - q.point).norm() <= tol,
        "z ≠ P_K(z) + P_K°(z)"
    );
    prop_assert!(
        p.point.dot(&q.point).abs() <= tol * zn,
        "parts not orthogonal"
    );
    // The regions mirror each other (away from the region boundaries).
    if sp.kind < 3 {
        let xm = c.point(&sp, 0.05);
        let zm = xm - c.a;
        let (pm, qm) = (k0.project(&zm).region, polar.project(&zm).region);
        let mirrored = match pm {
            Region::Interior => Region::Polar,
            Region::Boundary => Region::Boundary,
            Region::Polar => Region::Interior,
        };
        prop_assert_eq!(qm, mirrored);
    }
    // Translation: P_K(x) = apex + P_K0(x − apex).
    let px = c.cone.project(&x).point;
    prop_assert!((px - (c.a + p.point)).norm() <= ROUND * EPS * c.scale(&[&x]));
    Ok(())
}

fn prop_cone_regions<const D: usize>((c, sp): (ConeCase<D>, Spot<D>)) -> Result<(), TestCaseError> {
    // Any point: the region is consistent with the returned point.
    let x = c.point(&sp, 0.0);
    let p = c.cone.project(&x);
    match p.region {
        Region::Interior => {
            prop_assert!(same_bits(&p.point, &x), "Interior but P(x) ≠ x");
            prop_assert_eq!(c.excess(&x), 0.0);
        }
        Region::Polar => {
            prop_assert!(same_bits(&p.point, &c.a), "Polar but P(x) ≠ apex");
            prop_assert!(x != c.a, "the apex itself reported Polar");
        }
        Region::Boundary => prop_assert!(c.excess(&x) > 0.0, "Boundary but x in the cone"),
    }
    if x == c.a {
        prop_assert_eq!(p.region, Region::Interior);
    }
    // A point 5 % of its region's angular width inside the region: the region is the
    // geometric one, and P(x) = apex iff Polar.
    if sp.kind < 3 {
        let x = c.point(&sp, 0.05);
        let p = c.cone.project(&x);
        prop_assert_eq!(p.region, region_of(sp.kind));
        prop_assert_eq!(c.excess(&x) == 0.0, sp.kind == 0);
        prop_assert_eq!(p.point == c.a, sp.kind == 2);
    }
    Ok(())
}

fn cone_and_region_spot<const D: usize>() -> impl Strategy<Value = (ConeCase<D>, Spot<D>)> {
    (cone_case::<D>(), region_spot::<D>())
}

fn prop_cone_jacobian_fd<const D: usize>(
    (c, sp): (ConeCase<D>, Spot<D>),
) -> Result<(), TestCaseError> {
    // θ 10 % of the region's angular width away from its ends.
    let x = c.point(&sp, 0.1);
    let (p, j) = c.cone.project_with_jacobian(&x);
    prop_assert_eq!(p.region, region_of(sp.kind));
    check_symmetric_contraction(&j)?;
    // Distances to the two region boundaries (lines through the apex at angles α and
    // α + π/2 in the meridian plane) and, on the lateral region, to the axis.
    let (zn, r) = c.meridian(&x);
    let hyp = (1.0 + c.eta * c.eta).sqrt();
    let to_cone = (r - c.eta * zn).abs() / hyp;
    let to_polar = (c.eta * r + zn).abs() / hyp;
    let rho = match p.region {
        Region::Interior => to_cone,
        Region::Boundary => to_cone.min(to_polar).min(r),
        Region::Polar => to_polar,
    };
    let (h, tol) = fd_step_and_tol(rho, c.scale(&[&x]));
    let (fd, same) = fd_jacobian(&c.cone, &x, h);
    prop_assert!(same, "FD stencil left the region (test bug)");
    let err = max_abs(&(j - fd));
    prop_assert!(
        err <= tol,
        "‖J − J_FD‖ = {err:e} > {tol:e}\nJ = {j}J_FD = {fd}"
    );
    Ok(())
}

/// A point on the interior/lateral boundary (0), on the lateral/polar boundary (1) or the
/// apex (2).
fn cone_edge_case<const D: usize>() -> impl Strategy<Value = (ConeCase<D>, u8, [f64; D], f64)> {
    (cone_case::<D>(), 0u8..3, unit_box::<D>(), -2.0f64..=1.0)
}

fn prop_cone_clarke_on_edges<const D: usize>(
    (c, edge, dir, mag): (ConeCase<D>, u8, [f64; D], f64),
) -> Result<(), TestCaseError> {
    if edge == 2 {
        // At the apex all three regions meet: I or 0 (or a lateral limit) are in the hull;
        // the implementation reports Interior.
        let (p, j) = c.cone.project_with_jacobian(&c.a);
        prop_assert_eq!(p.region, Region::Interior);
        prop_assert_eq!(j, M::<D>::identity());
        return Ok(());
    }
    let e = transverse(&c.n, &dir);
    let theta = c.alpha() + if edge == 0 { 0.0 } else { FRAC_PI_2 };
    let m = c.s * pow10(mag);
    let x = c.at(theta, m, &e);
    let (below, above) = if edge == 0 {
        (Region::Interior, Region::Boundary)
    } else {
        (Region::Boundary, Region::Polar)
    };
    // Side points at ±δ along the direction of increasing θ; δ is 1e-7 of the distance to
    // the axis (Jacobians vary by O(δ/r) within a region), far above the rounding of x.
    let nu = -c.n * theta.sin() + e * theta.cos();
    let delta = 1e-7 * m * theta.sin();
    let (pm, jm) = c.cone.project_with_jacobian(&(x - nu * delta));
    let (pp, jp) = c.cone.project_with_jacobian(&(x + nu * delta));
    prop_assert_eq!(
        (pm.region, pp.region),
        (below, above),
        "side points misplaced (test bug)"
    );
    let (p, j) = c.cone.project_with_jacobian(&x);
    prop_assert!(p.region == below || p.region == above);
    let neighbour = if p.region == below { jm } else { jp };
    let err = max_abs(&(j - neighbour));
    prop_assert!(
        err <= 1e-5,
        "J on the edge is not the {:?} limit: {err:e}",
        p.region
    );
    Ok(())
}

#[test]
fn cone_feasibility_and_idempotence() {
    for_dims!(
        "feasibility/idempotence",
        cone_and_spot,
        prop_cone_feasible_idempotent
    );
}

#[test]
fn cone_non_expansive() {
    for_dims!("non-expansiveness", cone_pair, prop_cone_non_expansive);
}

#[test]
fn cone_variational_inequality() {
    for_dims!(
        "variational inequality",
        cone_vi_case,
        prop_cone_variational_inequality
    );
}

#[test]
fn cone_moreau_decomposition() {
    for_dims!("Moreau decomposition", cone_and_spot, prop_cone_moreau);
}

#[test]
fn cone_region_classification() {
    for_dims!("regions", cone_and_spot, prop_cone_regions);
}

#[test]
fn cone_jacobian_matches_finite_differences() {
    for_dims!(
        "Jacobian vs FD",
        cone_and_region_spot,
        prop_cone_jacobian_fd
    );
}

#[test]
fn cone_jacobian_on_region_boundaries_is_a_neighbour_limit() {
    for_dims!("Clarke on edges", cone_edge_case, prop_cone_clarke_on_edges);
}

// ---------------------------------------------------------------------------------------------
// Von Mises cylinder
// ---------------------------------------------------------------------------------------------

#[derive(Debug, Clone)]
struct CylCase<const D: usize> {
    cyl: VonMisesCylinder<D>,
    n: V<D>,
    radius: f64,
}

/// R = 0 a fifth of the time, otherwise log-uniform in [1e-9, 1e9].
fn cyl_case<const D: usize>() -> impl Strategy<Value = CylCase<D>> {
    let radius = prop_oneof![1 => Just(0.0), 4 => (-9.0f64..=9.0).prop_map(pow10)];
    (raw_axis::<D>(), radius).prop_map(|(axis, radius)| {
        let cyl = VonMisesCylinder::try_new(axis, radius).unwrap();
        CylCase {
            n: *cyl.axis(),
            radius,
            cyl,
        }
    })
}

/// x = x_n n + r e.
#[derive(Debug, Clone, Copy)]
struct CylSpot<const D: usize> {
    /// 0: inside (r = frac R), 1: outside (r = R + 10^r_exp), 2: r = 10^r_exp, 3: on the axis.
    kind: u8,
    frac: f64,
    dir: [f64; D],
    r_exp: f64,
    /// x_n = ±10^xn_exp.
    xn_exp: f64,
    neg: bool,
}

fn cyl_spot<const D: usize>() -> impl Strategy<Value = CylSpot<D>> {
    (
        0u8..4,
        0.0f64..=1.0,
        unit_box::<D>(),
        -9.0f64..=9.0,
        -9.0f64..=9.0,
        any::<bool>(),
    )
        .prop_map(|(kind, frac, dir, r_exp, xn_exp, neg)| CylSpot {
            kind,
            frac,
            dir,
            r_exp,
            xn_exp,
            neg,
        })
}

impl<const D: usize> CylCase<D> {
    /// Returns the point and its distance r to the axis. With `margin`, r stays a fraction
    /// `margin` of R away from R and |x_n| is within 1e-3..1e3 of max(r, R), so that finite
    /// differences resolve the boundary (kinds 0 and 1 only).
    fn point(&self, sp: &CylSpot<D>, margin: f64) -> (V<D>, f64) {
        let rr = self.radius;
        let r = match sp.kind {
            0 => rr * (margin + (1.0 - 2.0 * margin) * sp.frac),
            1 => rr * (1.0 + margin) + pow10(sp.r_exp),
            2 => pow10(sp.r_exp),
            _ => 0.0,
        };
        let mut xn = if margin > 0.0 {
            r.max(rr) * pow10(sp.xn_exp / 3.0)
        } else {
            pow10(sp.xn_exp)
        };
        if sp.neg {
            xn = -xn;
        }
        (self.n * xn + transverse(&self.n, &sp.dir) * r, r)
    }

    fn excess(&self, y: &V<D>) -> f64 {
        let yn = y.dot(&self.n);
        ((y - self.n * yn).norm() - self.radius).max(0.0)
    }

    fn scale(&self, ys: &[&V<D>]) -> f64 {
        ys.iter()
            .fold(self.radius, |acc, y| acc.max(y.norm()))
            .max(f64::MIN_POSITIVE)
    }
}

fn cyl_and_spot<const D: usize>() -> impl Strategy<Value = (CylCase<D>, CylSpot<D>)> {
    (cyl_case::<D>(), cyl_spot::<D>())
}

fn prop_cyl_feasible_idempotent<const D: usize>(
    (c, sp): (CylCase<D>, CylSpot<D>),
) -> Result<(), TestCaseError> {
    let (x, _) = c.point(&sp, 0.0);
    let p = c.cyl.project(&x);
    let tol = ROUND * EPS * c.scale(&[&x]);
    prop_assert!(c.excess(&p.point) <= tol, "P(x) = {} outside", p.point);
    // `contains` scales tol by max(‖P(x)‖, R), possibly far below the scale of x (see the cone).
    let own_scale = c.scale(&[&p.point]);
    let s = c.scale(&[&x]);
    prop_assert!(c
        .cyl
        .contains(&p.point, (ROUND * EPS * (s / own_scale)).min(1.0)));
    let pp = c.cyl.project(&p.point);
    prop_assert!((pp.point - p.point).norm() <= tol, "P(P(x)) ≠ P(x)");
    let (pj, _) = c.cyl.project_with_jacobian(&x);
    prop_assert_eq!(pj.region, p.region);
    prop_assert!((pj.point - p.point).norm() <= tol);
    // No polar region; Interior exactly when R > 0 and x is in the cylinder, where P(x) = x.
    prop_assert!(p.region != Region::Polar);
    prop_assert_eq!(
        p.region == Region::Interior,
        c.radius > 0.0 && c.excess(&x) == 0.0
    );
    if p.region == Region::Interior {
        prop_assert!(same_bits(&p.point, &x));
    }
    Ok(())
}

fn cyl_pair<const D: usize>(
) -> impl Strategy<Value = (CylCase<D>, CylSpot<D>, CylSpot<D>, Option<(f64, [f64; D])>)> {
    (
        cyl_case::<D>(),
        cyl_spot::<D>(),
        cyl_spot::<D>(),
        proptest::option::of((-12.0f64..=0.0, unit_box::<D>())),
    )
}

fn prop_cyl_non_expansive<const D: usize>(
    (c, sx, sy, pert): (CylCase<D>, CylSpot<D>, CylSpot<D>, Option<(f64, [f64; D])>),
) -> Result<(), TestCaseError> {
    let (x, _) = c.point(&sx, 0.0);
    let y = match pert {
        None => c.point(&sy, 0.0).0,
        Some((e, dir)) => x + V::<D>::from(dir).normalize() * (x.norm() * pow10(e)),
    };
    let (px, py) = (c.cyl.project(&x).point, c.cyl.project(&y).point);
    prop_assert!(
        (px - py).norm() <= (x - y).norm() + ROUND * EPS * c.scale(&[&x, &y]),
        "‖P(x) − P(y)‖ = {} > ‖x − y‖ = {}",
        (px - py).norm(),
        (x - y).norm()
    );
    Ok(())
}

/// y = t n + γ R e' with γ ∈ [0, 1]: a point of the cylinder by construction.
fn cyl_vi_case<const D: usize>(
) -> impl Strategy<Value = (CylCase<D>, CylSpot<D>, (f64, bool, f64, [f64; D]))> {
    (
        cyl_case::<D>(),
        cyl_spot::<D>(),
        (-9.0f64..=9.0, any::<bool>(), 0.0f64..=1.0, unit_box::<D>()),
    )
}

fn prop_cyl_variational_inequality<const D: usize>(
    (c, sp, (t_exp, neg, gamma, dir)): (CylCase<D>, CylSpot<D>, (f64, bool, f64, [f64; D])),
) -> Result<(), TestCaseError> {
    let (x, _) = c.point(&sp, 0.0);
    let t = if neg { -pow10(t_exp) } else { pow10(t_exp) };
    let y = c.n * t + transverse(&c.n, &dir) * (gamma * c.radius);
    let p = c.cyl.project(&x).point;
    // As for the cone: errors ~EPS S in P and in y.
    let err = ROUND * EPS * c.scale(&[&x, &y]);
    let (dx, dy) = (x - p, y - p);
    prop_assert!(
        dx.dot(&dy) <= err * (dx.norm() + dy.norm()) + err * err,
        "(x − P)·(y − P) = {} > 0",
        dx.dot(&dy)
    );
    Ok(())
}

fn cyl_and_region_spot<const D: usize>() -> impl Strategy<Value = (CylCase<D>, CylSpot<D>)> {
    (cyl_case::<D>(), cyl_spot::<D>()).prop_filter(
        "inside spots need R > 0; FD runs on inside/outside spots",
        |(c, sp)| sp.kind == 1 || (sp.kind == 0 && c.radius > 0.0),
    )
}

fn prop_cyl_jacobian_fd<const D: usize>(
    (c, sp): (CylCase<D>, CylSpot<D>),
) -> Result<(), TestCaseError> {
    // r at least 10 % of R away from R.
    let (x, r) = c.point(&sp, 0.1);
    let (p, j) = c.cyl.project_with_jacobian(&x);
    prop_assert_eq!(p.region, region_of(sp.kind));
    check_symmetric_contraction(&j)?;
    let rho = match p.region {
        Region::Interior => c.radius - r,
        _ => (r - c.radius).min(r),
    };
    let (h, tol) = fd_step_and_tol(rho, c.scale(&[&x]));
    let (fd, same) = fd_jacobian(&c.cyl, &x, h);
    prop_assert!(same, "FD stencil left the region (test bug)");
    let err = max_abs(&(j - fd));
    prop_assert!(
        err <= tol,
        "‖J − J_FD‖ = {err:e} > {tol:e}\nJ = {j}J_FD = {fd}"
    );
    Ok(())
}

/// A point on the lateral surface r = R (or on the axis when R = 0), x_n within 1e-3..1e3 of
/// max(R, |x_n|).
fn cyl_edge_case<const D: usize>() -> impl Strategy<Value = (CylCase<D>, [f64; D], f64, f64)> {
    (
        cyl_case::<D>(),
        unit_box::<D>(),
        -3.0f64..=3.0,
        -9.0f64..=9.0,
    )
}

fn prop_cyl_clarke_on_edge<const D: usize>(
    (c, dir, xn_rel, xn_abs): (CylCase<D>, [f64; D], f64, f64),
) -> Result<(), TestCaseError> {
    let e = transverse(&c.n, &dir);
    let xn = if c.radius > 0.0 {
        c.radius * pow10(xn_rel)
    } else {
        pow10(xn_abs)
    };
    let x = c.n * xn + e * c.radius;
    // J varies on the scale R (R/r): δ = 1e-7 R, far above the rounding of x (≤ 1e3 R EPS).
    // For R = 0 the Jacobian is n nᵀ on both sides; δ is then relative to x_n.
    let delta = 1e-7 * if c.radius > 0.0 { c.radius } else { xn.abs() };
    let (pm, jm) = c.cyl.project_with_jacobian(&(x - e * delta));
    let (pp, jp) = c.cyl.project_with_jacobian(&(x + e * delta));
    let (p, j) = c.cyl.project_with_jacobian(&x);
    prop_assert_eq!(
        pp.region,
        Region::Boundary,
        "outer side point misplaced (test bug)"
    );
    let neighbour = if p.region == pm.region { jm } else { jp };
    prop_assert!(p.region == pm.region || p.region == pp.region);
    let err = max_abs(&(j - neighbour));
    prop_assert!(
        err <= 1e-5,
        "J on the edge is not the {:?} limit: {err:e}",
        p.region
    );
    Ok(())
}

#[test]
fn cylinder_feasibility_idempotence_and_regions() {
    for_dims!(
        "cylinder feasibility/idempotence",
        cyl_and_spot,
        prop_cyl_feasible_idempotent
    );
}

#[test]
fn cylinder_non_expansive() {
    for_dims!(
        "cylinder non-expansiveness",
        cyl_pair,
        prop_cyl_non_expansive
    );
}

#[test]
fn cylinder_variational_inequality() {
    for_dims!("cylinder VI", cyl_vi_case, prop_cyl_variational_inequality);
}

#[test]
fn cylinder_jacobian_matches_finite_differences() {
    for_dims!(
        "cylinder Jacobian vs FD",
        cyl_and_region_spot,
        prop_cyl_jacobian_fd
    );
}

#[test]
fn cylinder_jacobian_on_boundary_is_a_neighbour_limit() {
    for_dims!(
        "cylinder Clarke on edge",
        cyl_edge_case,
        prop_cyl_clarke_on_edge
    );
}

// ---------------------------------------------------------------------------------------------
// project_batch: bitwise reproducibility
// ---------------------------------------------------------------------------------------------

/// SplitMix64: deterministic data without new dependencies.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
    fn vector<const D: usize>(&mut self) -> V<D> {
        V::<D>::from_fn(|_, _| self.range(-1.0, 1.0))
    }
}

const BATCH: usize = 12_345;

fn same_projection<const D: usize>(a: &Projection<D>, b: &Projection<D>) -> bool {
    a.region == b.region && same_bits(&a.point, &b.point)
}

/// Runs `project_batch` Sequential outside any pool (the reference, itself checked against
/// one-point calls), then Sequential and Rayon inside pools of 1, 2 and 4 threads, with and
/// without Jacobians; every result must be bitwise identical to the reference.
fn check_batch<S: Projector<D> + Sync, const D: usize>(label: &str, sets: &[S], points: &[V<D>]) {
    let n = points.len();
    let blank = Projection {
        point: V::<D>::zeros(),
        region: Region::Interior,
    };
    let set = |i: usize| if sets.len() == 1 { &sets[0] } else { &sets[i] };

    let mut reference = vec![blank; n];
    project_batch(sets, points, &mut reference, None, Parallelism::Sequential);
    let mut reference_j = vec![blank; n];
    let mut jacobians = vec![M::<D>::zeros(); n];
    project_batch(
        sets,
        points,
        &mut reference_j,
        Some(&mut jacobians),
        Parallelism::Sequential,
    );
    let mut regions = [0usize; 3];
    for i in 0..n {
        assert!(same_projection(&reference[i], &set(i).project(&points[i])));
        let (p, j) = set(i).project_with_jacobian(&points[i]);
        assert!(same_projection(&reference_j[i], &p));
        assert!(j
            .iter()
            .zip(jacobians[i].iter())
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        regions[reference[i].region as usize] += 1;
    }
    assert!(
        regions.iter().filter(|&&k| k > n / 20).count() >= 2,
        "{label}: poor region mix {regions:?}"
    );

    for threads in [1, 2, 4] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            for par in [Parallelism::Sequential, Parallelism::Rayon] {
                let what = format!("{label}, {par:?}, {threads} threads");
                let mut out = vec![blank; n];
                project_batch(sets, points, &mut out, None, par);
                assert!(
                    out.iter()
                        .zip(&reference)
                        .all(|(a, b)| same_projection(a, b)),
                    "{what}: points differ"
                );
                let mut out = vec![blank; n];
                let mut jac = vec![M::<D>::from_element(f64::NAN); n];
                project_batch(sets, points, &mut out, Some(&mut jac), par);
                assert!(
                    out.iter()
                        .zip(&reference_j)
                        .all(|(a, b)| same_projection(a, b)),
                    "{what}: points (with Jacobian) differ"
                );
                assert!(
                    jac.iter().zip(&jacobians).all(|(a, b)| a
                        .iter()
                        .zip(b.iter())
                        .all(|(u, v)| u.to_bits() == v.to_bits())),
                    "{what}: Jacobians differ"
                );
            }
        });
    }
}

fn batch_for_dim<const D: usize>() {
    let mut rng = Rng(0x7A15_0000 ^ D as u64);
    let random_axis = |rng: &mut Rng| loop {
        let v = rng.vector::<D>();
        if v.norm() > 0.1 {
            break v;
        }
    };
    // Per-point cones, and points spread over all angles around each apex.
    let cones: Vec<SecondOrderCone<D>> = (0..BATCH)
        .map(|_| {
            let s = pow10(rng.range(-6.0, 6.0));
            let apex = rng.vector::<D>() * s;
            let axis = random_axis(&mut rng);
            SecondOrderCone::try_new(axis, apex, pow10(rng.range(-1.0, 1.0))).unwrap()
        })
        .collect();
    let around = |rng: &mut Rng, cone: &SecondOrderCone<D>| {
        let s = cone.apex().norm().max(1.0);
        cone.apex() + rng.vector::<D>() * (s * pow10(rng.range(-3.0, 1.0)))
    };
    let points: Vec<V<D>> = cones.iter().map(|c| around(&mut rng, c)).collect();
    check_batch("cones, per point", &cones, &points);
    let shared: Vec<V<D>> = (0..BATCH).map(|_| around(&mut rng, &cones[0])).collect();
    check_batch("cones, broadcast", &cones[..1], &shared);

    let cylinders: Vec<VonMisesCylinder<D>> = (0..BATCH)
        .map(|_| {
            let axis = random_axis(&mut rng);
            VonMisesCylinder::try_new(axis, pow10(rng.range(-6.0, 6.0))).unwrap()
        })
        .collect();
    let near = |rng: &mut Rng, cyl: &VonMisesCylinder<D>| {
        rng.vector::<D>() * (cyl.radius() * pow10(rng.range(-1.0, 1.0)))
    };
    let points: Vec<V<D>> = cylinders.iter().map(|c| near(&mut rng, c)).collect();
    check_batch("cylinders, per point", &cylinders, &points);
    let shared: Vec<V<D>> = (0..BATCH).map(|_| near(&mut rng, &cylinders[0])).collect();
    check_batch("cylinders, broadcast", &cylinders[..1], &shared);
}

#[test]
fn batch_is_bitwise_identical_across_parallelism_and_thread_counts() {
    batch_for_dim::<3>();
    batch_for_dim::<4>();
    batch_for_dim::<6>();
}

// ---------------------------------------------------------------------------------------------
// Constructors and closed-form examples
// ---------------------------------------------------------------------------------------------

fn assert_names(result: Result<impl Debug, ConeError>, name: &str) {
    let msg = result.expect_err("invalid parameter accepted").to_string();
    assert!(msg.contains(name), "error {msg:?} does not name {name:?}");
}

#[test]
fn constructors_reject_invalid_parameters() {
    let (inf, nan) = (f64::INFINITY, f64::NAN);
    let axis = vector![0.0, 0.0, 1.0];
    let apex = vector![1.0, 2.0, 3.0];
    for eta in [0.0, -0.0, -1.0, -f64::MIN_POSITIVE, nan, inf, -inf] {
        assert_names(SecondOrderCone::try_new(axis, apex, eta), "eta");
    }
    for bad in [
        vector![0.0, 0.0, 0.0],
        vector![nan, 0.0, 1.0],
        vector![0.0, inf, 1.0],
        vector![0.0, 0.0, -inf],
    ] {
        assert_names(SecondOrderCone::try_new(bad, apex, 1.0), "axis");
        assert_names(VonMisesCylinder::try_new(bad, 1.0), "axis");
    }
    for bad in [
        vector![nan, 0.0, 0.0],
        vector![0.0, inf, 0.0],
        vector![0.0, 0.0, -inf],
    ] {
        assert_names(SecondOrderCone::try_new(axis, bad, 1.0), "apex");
    }
    for radius in [-1.0, -f64::MIN_POSITIVE, nan, inf, -inf] {
        assert_names(VonMisesCylinder::try_new(axis, radius), "radius");
    }
    // Valid edge values are accepted.
    assert!(SecondOrderCone::try_new(axis, apex, 1e-300).is_ok());
    assert!(SecondOrderCone::try_new(axis, apex, 1e300).is_ok());
    assert!(VonMisesCylinder::try_new(axis, 0.0).is_ok());
    let cone = SecondOrderCone::try_new(vector![0.0, 0.0, 2.0], apex, 1.0).unwrap();
    assert_eq!(*cone.axis(), axis, "axis is normalised");
}

#[test]
fn cone_closed_form_d3() {
    // n = e3 (given as 2 e3), apex a = (1, −1, 2), η = 1 (45° half-opening).
    let a = vector![1.0, -1.0, 2.0];
    let cone = SecondOrderCone::try_new(vector![0.0, 0.0, 2.0], a, 1.0).unwrap();
    // x − a = (3, 0, 1): z_n = 1, z_t = (3, 0, 0), r = 3; outside (3 > 1), not polar (3 > −1).
    // s = (z_n + η r)/(1 + η²) = 2, w = n + η u = (1, 0, 1): P = a + (2, 0, 2) = (3, −1, 4).
    // J = w wᵀ/2 + (η s/r)(I − n nᵀ − u uᵀ) = [[½, 0, ½], [0, ⅔, 0], [½, 0, ½]].
    let (p, j) = cone.project_with_jacobian(&(a + vector![3.0, 0.0, 1.0]));
    assert_eq!(p.region, Region::Boundary);
    approx::assert_relative_eq!(p.point, vector![3.0, -1.0, 4.0], max_relative = 4.0 * EPS);
    let expected = SMatrix::<f64, 3, 3>::new(0.5, 0.0, 0.5, 0.0, 2.0 / 3.0, 0.0, 0.5, 0.0, 0.5);
    approx::assert_relative_eq!(j, expected, epsilon = 4.0 * EPS);
    let q = cone.project(&(a + vector![3.0, 0.0, 1.0])).point;
    approx::assert_relative_eq!(q, p.point, max_relative = 4.0 * EPS);

    // Inside: x − a = (1, 0, 2). Polar: x − a = (1, 0, −2) (η r = 1 ≤ 2).
    let x = a + vector![1.0, 0.0, 2.0];
    let (p, j) = cone.project_with_jacobian(&x);
    assert_eq!(
        (p.region, p.point, j),
        (Region::Interior, x, SMatrix::identity())
    );
    let (p, j) = cone.project_with_jacobian(&(a + vector![1.0, 0.0, -2.0]));
    assert_eq!((p.region, p.point, j), (Region::Polar, a, SMatrix::zeros()));

    // Exactly on the region boundaries (exact in binary), n = e1, apex 0, η = 2:
    // (1, 2, 0) has r = η x_n: Interior with J = I, the interior-side limit;
    // (−4, 2, 0) has η r = −x_n: Polar with J = 0, the polar-side limit.
    let cone =
        SecondOrderCone::try_new(vector![1.0, 0.0, 0.0], vector![0.0, 0.0, 0.0], 2.0).unwrap();
    let x = vector![1.0, 2.0, 0.0];
    let (p, j) = cone.project_with_jacobian(&x);
    assert_eq!(
        (p.region, p.point, j),
        (Region::Interior, x, SMatrix::identity())
    );
    let (p, j) = cone.project_with_jacobian(&vector![-4.0, 2.0, 0.0]);
    assert_eq!(
        (p.region, p.point, j),
        (Region::Polar, vector![0.0, 0.0, 0.0], SMatrix::zeros())
    );
    // The apex itself: Interior, J = I.
    let (p, j) = cone.project_with_jacobian(&vector![0.0, 0.0, 0.0]);
    assert_eq!((p.region, j), (Region::Interior, SMatrix::identity()));
}

#[test]
fn cylinder_closed_form_d3() {
    // n = e3, R = 2, x = (3, 4, 7): r = 5, u = (0.6, 0.8, 0), P = (1.2, 1.6, 7),
    // J = n nᵀ + (R/r)(I − n nᵀ − u uᵀ) = [[0.256, −0.192, 0], [−0.192, 0.144, 0], [0, 0, 1]].
    let cyl = VonMisesCylinder::try_new(vector![0.0, 0.0, 1.0], 2.0).unwrap();
    let (p, j) = cyl.project_with_jacobian(&vector![3.0, 4.0, 7.0]);
    assert_eq!(p.region, Region::Boundary);
    approx::assert_relative_eq!(p.point, vector![1.2, 1.6, 7.0], max_relative = 4.0 * EPS);
    let expected = SMatrix::<f64, 3, 3>::new(0.256, -0.192, 0.0, -0.192, 0.144, 0.0, 0.0, 0.0, 1.0);
    approx::assert_relative_eq!(j, expected, epsilon = 4.0 * EPS);
    // On the surface (r = 2 exactly): Interior, J = I; inside likewise.
    let x = vector![0.0, 2.0, -5.0];
    assert_eq!(
        cyl.project_with_jacobian(&x),
        (
            Projection {
                point: x,
                region: Region::Interior
            },
            SMatrix::identity()
        )
    );
    // R = 0: the axis line; J = n nᵀ everywhere, on the axis included.
    let line = VonMisesCylinder::try_new(vector![0.0, 0.0, 1.0], 0.0).unwrap();
    let nn = SMatrix::<f64, 3, 3>::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0);
    for x in [vector![3.0, 4.0, 7.0], vector![0.0, 0.0, 7.0]] {
        let (p, j) = line.project_with_jacobian(&x);
        assert_eq!(
            (p.region, p.point, j),
            (Region::Boundary, vector![0.0, 0.0, 7.0], nn)
        );
    }
}
