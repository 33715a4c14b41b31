//! The size of a run before anything is allocated (`docs/scenes.md`, 'Size'): memory from
//! the count of stress points (Gauss points or particles) against the memory available,
//! and work (steps × points) against a cap; `talus run --allow-large` overrides both.
use talus_fem::quadrature::stiffness_rule;
use talus_fem::{ElementOrder, Mesh};

use crate::scene::{MeshSpec, MpmSceneSpec, Order, Scene, SceneDocument, SceneError, SceneVector};

/// Bytes per stress point: `(8 + 0.8 log₂ N)` KiB for N points (the Schur factor's fill
/// grows as N log N in 2D). Fitted on the measured peaks (`VmHWM`) of
/// `docs/performance.md` (P2 footing: 32 MiB, 429 MiB, 5.3 GiB at 2 688, 29 952, 299 520
/// Gauss points; estimated 45 MiB, 0.56 GiB, 6.6 GiB) and `docs/mpm-performance.md`
/// (167 MiB and 2.1 GiB at 9 800 and 100 352 particles; estimated 178 MiB, 2.0 GiB).
const KIB_PER_POINT: f64 = 8.0;
const KIB_PER_POINT_PER_LOG2: f64 = 0.8;
/// An MPM grid node, allocated whether material reaches it or not (bytes).
const BYTES_PER_GRID_NODE: f64 = 64.0;
/// Steps × stress points above which a run is refused without `--allow-large`: the paper
/// footing is 8e5 (300 × 2 688); 1e11 is days of computing on this machine.
pub const MAX_WORK: f64 = 1e11;

/// What a scene will hold.
#[derive(Debug, Clone, PartialEq)]
pub struct SizeEstimate {
    /// Gauss points or particles.
    pub points: f64,
    /// Other allocations counted (MPM grid nodes).
    pub grid_nodes: f64,
    pub bytes: f64,
    pub steps: usize,
}

/// Why a run is refused before it starts.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TooLarge {
    #[error(
        "the run would need about {} ({:.3e} stress points) but {} is available; \
         make the mesh or grid coarser, or pass --allow-large to run anyway",
        bytes(.estimate.bytes), .estimate.points, bytes(*.available as f64)
    )]
    Memory {
        estimate: SizeEstimate,
        available: u64,
    },
    #[error(
        "{} steps × {:.3e} stress points = {:.3e} point-steps, more than {MAX_WORK:e}; \
         take fewer steps or a coarser mesh, or pass --allow-large to run anyway",
        .estimate.steps, .estimate.points, .estimate.steps as f64 * .estimate.points
    )]
    Work { estimate: SizeEstimate },
}

fn bytes(b: f64) -> String {
    if b >= 1024f64.powi(4) {
        format!("{:.3e} GiB", b / 1024f64.powi(3))
    } else if b >= 1024.0 * 1024.0 * 1024.0 {
        format!("{:.3} GiB", b / (1024.0 * 1024.0 * 1024.0))
    } else {
        format!("{:.1} MiB", b / (1024.0 * 1024.0))
    }
}

impl SizeEstimate {
    fn new(points: f64, grid_nodes: f64, steps: usize) -> Self {
        let per_point = 1024.0 * (KIB_PER_POINT + KIB_PER_POINT_PER_LOG2 * points.max(2.0).log2());
        Self {
            points,
            grid_nodes,
            bytes: points * per_point + grid_nodes * BYTES_PER_GRID_NODE,
            steps,
        }
    }

    /// A FEM scene: its Gauss points from the rectangle's cells (in floating point, so
    /// that `cells = [1e9, 1e9]` cannot overflow) or from the Gmsh file's triangles.
    pub fn of_fem(scene: &Scene) -> Result<Self, SceneError> {
        let (triangles, order) = match &scene.spec.mesh {
            MeshSpec::Rectangle { cells, order, .. } => {
                let order = match order {
                    Order::P1 => ElementOrder::P1,
                    Order::P2 => ElementOrder::P2,
                };
                (2.0 * cells[0] as f64 * cells[1] as f64, order)
            }
            MeshSpec::Box { .. } => {
                return Err(crate::scene::dimension::three_d_key(
                    scene,
                    "mesh.box",
                    "a box of tetrahedra",
                ))
            }
            MeshSpec::Gmsh { path, order, .. } => {
                let mesh = Mesh::from_msh(&scene.resolve(path))
                    .map_err(|e| scene.error("mesh.gmsh.path", e.to_string()))?;
                let order = match order {
                    Some(Order::P2) => ElementOrder::P2,
                    _ => mesh.order,
                };
                (mesh.triangles.len() as f64, order)
            }
        };
        let points = triangles * stiffness_rule(order).points.len() as f64;
        Ok(Self::new(points, 0.0, scene.spec.total_steps()))
    }

    /// An MPM scene: its particles from the bodies' areas (3D: volumes, a cylinder's
    /// `π R² H`), and the grid's nodes. In 3D the bytes per particle are 2D's: a lower
    /// bound (a 3D node couples to 125 nodes, not 25, `docs/3d-mpm.md`, 'Cost').
    pub fn of_mpm<V: SceneVector>(scene: &SceneDocument<MpmSceneSpec<V>>) -> Self {
        let spec = &scene.spec;
        let dx = spec.grid.spacing;
        let points = spec
            .body
            .iter()
            .filter_map(|b| {
                let n = b.particles_per_cell as f64;
                let along = |lo: f64, hi: f64| ((hi - lo) / dx * n).ceil().max(0.0);
                if let Some([lo, hi]) = b.rectangle.or(b.cuboid) {
                    let (lo, hi) = (lo.as_ref(), hi.as_ref());
                    return Some((0..V::DIM).map(|a| along(lo[a], hi[a])).product::<f64>());
                }
                let c = b.cylinder?;
                let share = if c.quarter { 0.25 } else { 1.0 };
                let r = along(0.0, c.radius);
                Some(share * std::f64::consts::PI * r * r * along(0.0, c.height))
            })
            .filter(|p| p.is_finite())
            .sum();
        let grid_nodes = (spec.grid.cells.as_ref().iter())
            .map(|&c| c as f64 + 1.0)
            .product();
        Self::new(points, grid_nodes, spec.time.steps)
    }

    /// Refused when the memory exceeds `available` bytes (unknown: not checked) or the
    /// work exceeds [`MAX_WORK`].
    pub fn check(&self, available: Option<u64>) -> Result<(), TooLarge> {
        if let Some(available) = available {
            if self.bytes > available as f64 {
                return Err(TooLarge::Memory {
                    estimate: self.clone(),
                    available,
                });
            }
        }
        if self.steps as f64 * self.points > MAX_WORK {
            return Err(TooLarge::Work {
                estimate: self.clone(),
            });
        }
        Ok(())
    }
}

/// `MemAvailable` of `/proc/meminfo` (bytes); `None` where there is no such file (not
/// Linux): the memory is then not checked.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_meminfo(&text)
}

fn parse_meminfo(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let mut words = line.split_whitespace().skip(1);
    let kib: u64 = words.next()?.parse().ok()?;
    (words.next() == Some("kB")).then_some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_estimate_brackets_the_measured_peaks() {
        // (points, measured peak MiB) from docs/performance.md and docs/mpm-performance.md.
        for (points, mib) in [
            (2_688.0, 32.0),
            (29_952.0, 429.0),
            (299_520.0, 5.3 * 1024.0),
            (9_800.0, 167.0),
            (100_352.0, 2_132.0),
        ] {
            let e = SizeEstimate::new(points, 0.0, 1).bytes / (1024.0 * 1024.0);
            assert!(
                e >= 0.9 * mib && e <= 1.5 * mib,
                "{points}: {e} MiB against {mib}"
            );
        }
    }

    #[test]
    fn meminfo_is_read_in_kib() {
        let text = "MemTotal:  8000000 kB\nMemFree: 100 kB\nMemAvailable:    2048 kB\n";
        assert_eq!(parse_meminfo(text), Some(2048 * 1024));
        assert_eq!(parse_meminfo("MemTotal: 1 kB\n"), None);
        assert_eq!(parse_meminfo("MemAvailable: x kB\n"), None);
    }

    #[test]
    fn too_much_memory_or_work_is_refused() {
        let e = SizeEstimate::new(1e6, 0.0, 10);
        assert!(matches!(
            e.check(Some(1 << 20)),
            Err(TooLarge::Memory { .. })
        ));
        assert!(e.check(Some(1 << 40)).is_ok());
        assert!(e.check(None).is_ok());
        let long = SizeEstimate::new(1e6, 0.0, 1_000_000);
        assert!(matches!(long.check(None), Err(TooLarge::Work { .. })));
    }
}
