//! Lamé's thick hollow sphere under internal pressure (Timoshenko & Goodier, *Theory of
//! Elasticity*, 3rd ed., §141), the first 3D check of `Assembly<6>`: its strain rows,
//! Gauss volumes, compliance blocks and face pressures together, on curved (P2) and
//! faceted (P1) tetrahedra.
//!
//! The shell `a ≤ r ≤ b` (a = 0.5 m, b = 1 m; E = 20 MPa, ν = 0.3) carries the pressure
//! `p` on `r = a` and none on `r = b`. The displacement is radial, `u = u_r(r) e_r` with
//! `u_r = A r + B / r²` (the general radially symmetric solution of Navier's equation), so
//! `ε_rr = A − 2B/r³`, `ε_θθ = ε_φφ = A + B/r³`, and Hooke's law gives
//! `σ_rr = E A/(1 − 2ν) − 2E B/((1 + ν) r³)`, `σ_θθ = E A/(1 − 2ν) + E B/((1 + ν) r³)`.
//! The boundary conditions `σ_rr(a) = −p`, `σ_rr(b) = 0` (tension positive) give
//! - `σ_rr = −p a³ (b³ − r³) / (r³ (b³ − a³))`,
//! - `σ_θθ = σ_φφ = p a³ (2r³ + b³) / (2r³ (b³ − a³))`,
//! - `u_r = p a³ / (E (b³ − a³)) · ((1 − 2ν) r + (1 + ν) b³ / (2r²))`.
//!
//! The model is one octant `x, y, z ≥ 0` with rollers on its three symmetry planes (the
//! normal component fixed on each), meshed as a cube sphere: three blocks `(ρ, s, t) ∈
//! [a, b] × [0, 1]²`, one per axis, each mapped by `x = ρ c/|c|` with the point `c` of the
//! unit cube's face (`c = (1, tan(πs/4), tan(πt/4))` for the x patch, cyclically for the
//! others), so that no cell is degenerate (no pole); the three meet on the planes `x = y`,
//! `y = z`, `x = z`, where Kuhn's face diagonals agree and the nodes coincide bit for bit.
//! Every node, P2 mid-edge nodes included, goes through the same smooth map: P2 faces on
//! `r = a` interpolate the sphere quadratically. `n` cells per patch side and radially
//! (`3 n³` cells, `18 n³` tetrahedra).
//!
//! The static problem `K u = f`, `K = B_fᵀ blockdiag((V_p S₀)⁻¹) B_f` (`solid3d::stiffness`)
//! and `f` = `asm.pressure` on the inner faces, is solved by faer's sparse Cholesky.
//! Measured (release, 2 cores, both orders running in parallel; `e_u` the largest nodal
//! error of `u_r` relative to `u_r(a)`, `e_t` the largest tangential nodal displacement
//! relative to `u_r(a)`, `e_σ` the `L²` error of the stress at the Gauss points relative to
//! `p √V`, `e_V` the relative error of the discrete volume `Σ V_p` against `π (b³ − a³)/6`;
//! orders between successive meshes):
//!
//! | order | n  | free dofs | e_u     | e_t     | e_σ     | e_V     | orders u, σ, V   |
//! |-------|----|-----------|---------|---------|---------|---------|------------------|
//! | P1    | 4  | 780       | 1.64e-1 | 1.47e-2 | 1.56e-1 | 1.57e-2 |                  |
//! | P1    | 8  | 5 400     | 6.29e-2 | 4.59e-3 | 9.16e-2 | 3.95e-3 | 1.38, 0.77, 1.99 |
//! | P1    | 16 | 39 984    | 2.08e-2 | 1.24e-3 | 4.85e-2 | 9.88e-4 | 1.60, 0.92, 2.00 |
//! | P2    | 2  | 780       | 3.12e-2 | 7.88e-3 | 3.40e-2 | 3.41e-4 |                  |
//! | P2    | 4  | 5 400     | 6.29e-3 | 1.69e-3 | 1.22e-2 | 2.16e-5 | 2.31, 1.48, 3.98 |
//! | P2    | 8  | 39 984    | 1.01e-3 | 2.37e-4 | 3.54e-3 | 1.35e-6 | 2.64, 1.78, 4.00 |
//!
//! The orders still climb towards 2 and 1 (P1 nodal `u`, `σ`) and 3 and 2 (P2) on the finest
//! meshes. Each finest solve takes 3–5 s, most of it in the sparse Cholesky, whose factor
//! holds 44 M (P1) and 49 M (P2) entries with AMD: the two tests running in parallel peak at
//! 1.2 GB, and the file takes 5–8 s in all, which is why no finer mesh is run. The volume
//! converges at the rates of the faceted (2) and quadratic (4) spheres. The assertions bound
//! the finest errors by about 1.5 times the measured figures (P1: `e_u < 0.03`,
//! `e_t < 2.5e-3`, `e_σ < 0.07`; P2: `e_u < 1.5e-3`, `e_t < 4e-4`, `e_σ < 5e-3`) and the last
//! orders from below (P1: u > 1.45, σ > 0.8, V > 1.9; P2: u > 2.45, σ > 1.6, V > 3.8), and
//! the lumped mass must total `ρ Σ V_p` to 1e-12. A wrong pressure (sign, size or normal),
//! strain row, Gauss volume or compliance block leaves an `O(1)` error that no refinement
//! removes, which both kinds of bound catch.
use crate::solid3d;

use std::collections::HashMap;
use std::time::Instant;

use nalgebra::SVector;
use solid3d::{nodal, solve_spd, stiffness};
use talus_bipotential::mandel::isotropic_compliance;
use talus_fem::{Assembly, BoundaryFace, Constraint, DofMap, ElementOrder, TetrahedralMesh};

const A: f64 = 0.5;
const B: f64 = 1.0;
const YOUNG: f64 = 2.0e7;
const POISSON: f64 = 0.3;
const PRESSURE: f64 = 1.0e5;
const DENSITY: f64 = 2000.0;

/// `u_r(r)` (m).
fn radial_displacement(r: f64) -> f64 {
    let (a3, b3) = (A.powi(3), B.powi(3));
    PRESSURE * a3 / (YOUNG * (b3 - a3))
        * ((1.0 - 2.0 * POISSON) * r + (1.0 + POISSON) * b3 / (2.0 * r * r))
}

/// `(σ_rr, σ_θθ)` (Pa, tension positive).
fn stresses(r: f64) -> (f64, f64) {
    let (a3, b3, r3) = (A.powi(3), B.powi(3), r.powi(3));
    (
        -PRESSURE * a3 * (b3 - r3) / (r3 * (b3 - a3)),
        PRESSURE * a3 * (2.0 * r3 + b3) / (2.0 * r3 * (b3 - a3)),
    )
}

/// The exact stress at `x` in Mandel form `(xx, yy, zz, √2 yz, √2 xz, √2 xy)`:
/// `σ = σ_θθ 1 + (σ_rr − σ_θθ) e_r ⊗ e_r`.
fn exact_stress(x: [f64; 3]) -> SVector<f64, 6> {
    let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
    let e = [x[0] / r, x[1] / r, x[2] / r];
    let (rr, tt) = stresses(r);
    let t = |i: usize, j: usize| tt * f64::from(u8::from(i == j)) + (rr - tt) * e[i] * e[j];
    let s = std::f64::consts::SQRT_2;
    SVector::from([
        t(0, 0),
        t(1, 1),
        t(2, 2),
        s * t(1, 2),
        s * t(0, 2),
        s * t(0, 1),
    ])
}

/// `tan(πs/4)`, exactly 1 at `s = 1`, so that the patches' shared nodes coincide.
fn ratio(s: f64) -> f64 {
    if s == 1.0 {
        1.0
    } else {
        (std::f64::consts::FRAC_PI_4 * s).tan()
    }
}

/// The octant of the shell, `n` cells per patch side and radially, with its inner faces.
fn shell_octant(order: ElementOrder, n: usize) -> (TetrahedralMesh, Vec<BoundaryFace>) {
    let rho: Vec<f64> = (0..=n).map(|i| A + (B - A) * i as f64 / n as f64).collect();
    let s: Vec<f64> = (0..=n).map(|i| i as f64 / n as f64).collect();
    let block = TetrahedralMesh::block(&rho, &s, &s, order).unwrap();
    // The cube point of each patch, cyclic in (x, y, z) so that every map keeps the
    // orientation: det(c, ∂c/∂s, ∂c/∂t) = 1 > 0.
    let patches: [fn(f64, f64) -> [f64; 3]; 3] = [
        |s, t| [1.0, ratio(s), ratio(t)],
        |s, t| [ratio(t), 1.0, ratio(s)],
        |s, t| [ratio(s), ratio(t), 1.0],
    ];
    let mut nodes: Vec<[f64; 3]> = Vec::new();
    let mut index: HashMap<[u64; 3], usize> = HashMap::new();
    let mut tetrahedra = Vec::new();
    let mut inner = Vec::new();
    for cube in patches {
        let global: Vec<usize> = block
            .nodes
            .iter()
            .map(|&[r, s, t]| {
                let c = cube(s, t);
                let norm = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
                let x = c.map(|ci| r * ci / norm);
                *index.entry(x.map(f64::to_bits)).or_insert_with(|| {
                    nodes.push(x);
                    nodes.len() - 1
                })
            })
            .collect();
        for t in &block.tetrahedra {
            tetrahedra.push(t.iter().map(|&k| global[k]).collect());
        }
        for f in &block.face_sets["left"] {
            inner.push(BoundaryFace {
                nodes: f.nodes.iter().map(|&k| global[k]).collect(),
            });
        }
    }
    let mut node_sets = std::collections::BTreeMap::new();
    for (c, name) in ["x0", "y0", "z0"].iter().enumerate() {
        let set = (0..nodes.len()).filter(|&k| nodes[k][c] == 0.0).collect();
        node_sets.insert(name.to_string(), set);
    }
    let mesh = TetrahedralMesh {
        order,
        nodes,
        tetrahedra,
        node_sets,
        face_sets: Default::default(),
        element_sets: Default::default(),
    };
    mesh.check_elements().unwrap();
    (mesh, inner)
}

/// Errors of one solve (see the module's table).
#[derive(Debug)]
struct Errors {
    dofs: usize,
    radial: f64,
    tangential: f64,
    stress: f64,
    volume: f64,
    seconds: f64,
}

fn solve(order: ElementOrder, n: usize) -> Errors {
    let start = Instant::now();
    let (mesh, inner) = shell_octant(order, n);
    let dofs = DofMap::with_components(
        mesh.nodes.len(),
        3,
        &[
            (mesh.node_sets["x0"].clone(), Constraint::FixX),
            (mesh.node_sets["y0"].clone(), Constraint::FixY),
            (mesh.node_sets["z0"].clone(), Constraint::FixZ),
        ],
    )
    .unwrap();
    let asm = Assembly::new(&mesh, &dofs, DENSITY).unwrap();
    let s0 = isotropic_compliance::<6>(YOUNG, POISSON);
    let (k_ff, _) = stiffness(&asm, &s0);
    let (f, _) = asm.pressure(&mesh, &inner, PRESSURE).unwrap();
    let u_f = solve_spd(&k_ff, &f);
    // Rollers are prescribed to 0.
    let u_p = vec![0.0; dofs.n_prescribed()];
    let u = nodal(&dofs, &(u_f.clone(), u_p.clone()));

    let scale = radial_displacement(A);
    let (mut radial, mut tangential) = (0.0f64, 0.0f64);
    for (x, ux) in mesh.nodes.iter().zip(&u) {
        let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
        let ur = (x[0] * ux[0] + x[1] * ux[1] + x[2] * ux[2]) / r;
        let ut: f64 = (0..3)
            .map(|c| (ux[c] - ur * x[c] / r).powi(2))
            .sum::<f64>()
            .sqrt();
        radial = radial.max((ur - radial_displacement(r)).abs() / scale);
        tangential = tangential.max(ut / scale);
    }

    let c = s0.try_inverse().unwrap();
    let strains = asm.strain(&u_f, &u_p).unwrap();
    let (mut squared, mut volume) = (0.0, 0.0);
    for ((eps, x), v) in strains
        .iter()
        .zip(&asm.gauss_points)
        .zip(&asm.gauss_volumes)
    {
        let e = c * eps - exact_stress(*x);
        squared += v * e.norm_squared();
        volume += v;
    }
    let stress = squared.sqrt() / (PRESSURE * volume.sqrt());

    // The lumped mass carries ρ times the discrete volume, whatever the elements' shapes.
    let mass: f64 = (0..mesh.nodes.len())
        .map(|k| match dofs.dof(k, 0).unwrap() {
            talus_fem::Dof::Free(i) => asm.lumped_mass_free[i],
            talus_fem::Dof::Prescribed(j) => asm.lumped_mass_prescribed[j],
        })
        .sum();
    assert!(
        (mass - DENSITY * volume).abs() < 1e-12 * DENSITY * volume,
        "{order:?}, n = {n}: mass {mass} vs ρV = {}",
        DENSITY * volume
    );
    let exact_volume = std::f64::consts::PI * (B.powi(3) - A.powi(3)) / 6.0;
    Errors {
        dofs: dofs.n_free(),
        radial,
        tangential,
        stress,
        volume: (volume - exact_volume).abs() / exact_volume,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// `log(e_coarse / e_fine) / log(n_fine / n_coarse)` between successive meshes.
fn orders(errors: &[Errors], field: impl Fn(&Errors) -> f64, ns: &[usize]) -> Vec<f64> {
    errors
        .windows(2)
        .zip(ns.windows(2))
        .map(|(e, n)| (field(&e[0]) / field(&e[1])).ln() / (n[1] as f64 / n[0] as f64).ln())
        .collect()
}

/// Bounds on the finest mesh's errors and on the last orders (see the module's table).
struct Expected {
    radial: f64,
    tangential: f64,
    stress: f64,
    radial_order: f64,
    stress_order: f64,
    volume_order: f64,
}

fn check_convergence(order: ElementOrder, ns: &[usize], want: Expected) {
    let errors: Vec<Errors> = ns.iter().map(|&n| solve(order, n)).collect();
    for (n, e) in ns.iter().zip(&errors) {
        eprintln!(
            "{order:?} n = {n}: {} free dofs, e_u {:.2e}, e_t {:.2e}, e_σ {:.2e}, e_V {:.2e}, \
             {:.2} s",
            e.dofs, e.radial, e.tangential, e.stress, e.volume, e.seconds
        );
    }
    let u = orders(&errors, |e| e.radial, ns);
    let s = orders(&errors, |e| e.stress, ns);
    let v = orders(&errors, |e| e.volume, ns);
    eprintln!("{order:?}: orders u {u:?}, σ {s:?}, volume {v:?}");
    // every refinement helps, the asymptotic orders are reached on the last one
    for w in errors.windows(2) {
        assert!(
            w[1].radial < w[0].radial && w[1].stress < w[0].stress,
            "{order:?}: no convergence: {w:?}"
        );
    }
    let last = errors.last().unwrap();
    assert!(last.radial < want.radial, "{order:?}: {last:?}");
    assert!(last.tangential < want.tangential, "{order:?}: {last:?}");
    assert!(last.stress < want.stress, "{order:?}: {last:?}");
    assert!(
        u[u.len() - 1] > want.radial_order,
        "{order:?}: u orders {u:?}"
    );
    assert!(
        s[s.len() - 1] > want.stress_order,
        "{order:?}: σ orders {s:?}"
    );
    assert!(
        v[v.len() - 1] > want.volume_order,
        "{order:?}: volume orders {v:?}"
    );
}

/// Faceted tetrahedra: nodal displacements tend to second order, stresses to first.
#[test]
fn lame_sphere_p1_octant_converges() {
    check_convergence(
        ElementOrder::P1,
        &[4, 8, 16],
        Expected {
            radial: 0.03,
            tangential: 2.5e-3,
            stress: 0.07,
            radial_order: 1.45,
            stress_order: 0.8,
            volume_order: 1.9,
        },
    );
}

/// Curved tetrahedra: nodal displacements tend to third order, stresses to second, the
/// volume of the shell to fourth.
#[test]
fn lame_sphere_p2_octant_converges() {
    check_convergence(
        ElementOrder::P2,
        &[2, 4, 8],
        Expected {
            radial: 1.5e-3,
            tangential: 4e-4,
            stress: 5e-3,
            radial_order: 2.45,
            stress_order: 1.6,
            volume_order: 3.8,
        },
    );
}

/// Guards the closed forms themselves: `u_r` gives the stresses through Hooke's law
/// (`ε_rr = du_r/dr` by central differences, `ε_θθ = u_r/r`), which satisfy the radial
/// equilibrium `dσ_rr/dr + 2(σ_rr − σ_θθ)/r = 0` and the boundary conditions
/// `σ_rr(a) = −p`, `σ_rr(b) = 0`.
#[test]
fn lame_closed_forms_are_consistent() {
    let lambda = YOUNG * POISSON / ((1.0 + POISSON) * (1.0 - 2.0 * POISSON));
    let mu = YOUNG / (2.0 * (1.0 + POISSON));
    let h = 1e-5;
    for k in 0..=10 {
        let r = A + (B - A) * f64::from(k) / 10.0;
        let err = (radial_displacement(r + h) - radial_displacement(r - h)) / (2.0 * h);
        let ett = radial_displacement(r) / r;
        let trace = err + 2.0 * ett;
        let (rr, tt) = stresses(r);
        assert!(
            (lambda * trace + 2.0 * mu * err - rr).abs() < 1e-6 * PRESSURE,
            "σ_rr at {r}"
        );
        assert!(
            (lambda * trace + 2.0 * mu * ett - tt).abs() < 1e-6 * PRESSURE,
            "σ_θθ at {r}"
        );
        let drr = (stresses(r + h).0 - stresses(r - h).0) / (2.0 * h);
        assert!(
            (drr + 2.0 * (rr - tt) / r).abs() < 1e-4 * PRESSURE,
            "equilibrium at {r}"
        );
    }
    assert!((stresses(A).0 + PRESSURE).abs() < 1e-9 * PRESSURE);
    assert!(stresses(B).0.abs() < 1e-9 * PRESSURE);
}

/// The cube-sphere octant is one conforming mesh: the patches share their seam nodes
/// (`3m³ − 3m² + m` nodes, `m` = nodes per patch side, by inclusion–exclusion over the
/// three patches, their three seams and the diagonal `x = y = z`) and their seam faces
/// (every face met once or twice; once only on the `6n²` inner, `6n²` outer and `4n²`
/// per symmetry plane triangles); every node lies in the shell, inner faces on `r = a`.
#[test]
fn cube_sphere_octant_is_conforming() {
    for order in [ElementOrder::P1, ElementOrder::P2] {
        for n in [1, 3] {
            let (mesh, inner) = shell_octant(order, n);
            let m = match order {
                ElementOrder::P1 => n + 1,
                ElementOrder::P2 => 2 * n + 1,
            };
            assert_eq!(
                mesh.nodes.len(),
                3 * m * m * m - 3 * m * m + m,
                "{order:?} {n}"
            );
            assert_eq!(mesh.tetrahedra.len(), 18 * n * n * n);
            let mut count: HashMap<[usize; 3], usize> = HashMap::new();
            for t in &mesh.tetrahedra {
                for f in talus_fem::mesh3::TETRAHEDRON_FACES {
                    let mut k = f.map(|v| t[v]);
                    k.sort_unstable();
                    *count.entry(k).or_default() += 1;
                }
            }
            assert!(count.values().all(|&c| c == 1 || c == 2));
            let boundary = count.values().filter(|&&c| c == 1).count();
            assert_eq!(boundary, (6 + 6 + 3 * 4) * n * n, "{order:?} {n}");
            assert_eq!(inner.len(), 6 * n * n);
            for f in &inner {
                for &k in &f.nodes {
                    let x = mesh.nodes[k];
                    let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
                    assert!((r - A).abs() < 1e-15, "{order:?}: inner node at r = {r}");
                }
            }
            for x in &mesh.nodes {
                let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
                assert!(r > A - 1e-15 && r < B + 1e-15 && x.iter().all(|c| *c >= 0.0));
            }
        }
    }
}
