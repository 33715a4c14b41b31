//! The memory a 3D scene's Newton solves will need, estimated before anything is
//! allocated, so that a mesh too large for the machine is refused with the estimate
//! instead of failing (or swapping) minutes into its first factorization. The estimate
//! interpolates the peaks measured by `cargo bench -p talus-fem --bench newton_3d`
//! (`docs/3d.md`, 'Memory and speed in 3D').
use crate::scene::{MaterialModel, MaterialSpec};

/// (free dofs, peak MiB of a non-associative step (LU), of an associative one (LLᵀ)):
/// a quarter footing of P2 tetrahedra on a graded box, AMD ordering (`docs/3d.md`).
const MEASURED: [(f64, f64, f64); 4] = [
    (1_635.0, 39.0, 29.0),
    (12_719.0, 382.0, 242.0),
    (49_567.0, 1_981.0, 1_188.0),
    (204_577.0, 13_731.0, 7_393.0),
];

/// Past the largest measured size: the last measured slope of log(peak) over log(dofs)
/// is 1.37 (LU) and 1.29 (LLᵀ), and the factor of a 3D mesh fills at least as
/// `n^{4/3}` under nested dissection; 1.4 keeps the estimate on the safe side.
const SLOPE_BEYOND: f64 = 1.4;

/// The estimated peak memory (MiB) of a 3D run with `free_dofs` unknowns; `associative`
/// when every material is (the symmetric Cholesky path, about 0.55–0.65 of LU's).
pub fn peak_mib(free_dofs: f64, associative: bool) -> f64 {
    let at = |k: usize| {
        let (n, lu, llt) = MEASURED[k];
        (n, if associative { llt } else { lu })
    };
    let (n0, m0) = at(0);
    if free_dofs <= n0 {
        return m0 * free_dofs.max(0.0) / n0;
    }
    for k in 1..MEASURED.len() {
        let ((na, ma), (nb, mb)) = (at(k - 1), at(k));
        if free_dofs <= nb {
            let s = (mb / ma).ln() / (nb / na).ln();
            return ma * (free_dofs / na).powf(s);
        }
    }
    let (n, m) = at(MEASURED.len() - 1);
    m * (free_dofs / n).powf(SLOPE_BEYOND)
}

/// Whether every material's flow is associative (θ = φ, Davis' equivalent, or elastic).
pub fn associative(materials: &[MaterialSpec]) -> bool {
    materials.iter().all(|m| {
        m.model == MaterialModel::Elastic
            || m.flow.as_deref() == Some("davis")
            || m.dilatancy_angle
                .is_none_or(|t| Some(t) == m.friction_angle)
    })
}

/// Where the machine's memory cannot be read: 1 TiB, so that only a mesh no machine
/// could factor is refused (a fuzzed `cells = [1e9, 1e9, 1e9]` aborted in allocation).
pub const UNKNOWN_MACHINE_MIB: f64 = 1024.0 * 1024.0;

/// This machine's memory (MiB): `MemTotal` of `/proc/meminfo`; `None` where it cannot be
/// read.
pub fn machine_mib() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_the_measured_peaks_and_grows() {
        for (n, lu, llt) in MEASURED {
            assert!((peak_mib(n, false) / lu - 1.0).abs() < 1e-12, "{n}");
            assert!((peak_mib(n, true) / llt - 1.0).abs() < 1e-12, "{n}");
        }
        let mut last = 0.0;
        for k in 1..60 {
            let p = peak_mib(1e3 * 1.3f64.powi(k), false);
            assert!(p > last, "{k}: {p} after {last}");
            last = p;
        }
        // Twice the largest measured size: 2^1.4 times its peak.
        assert!((peak_mib(409_154.0, false) / (13_731.0 * 2f64.powf(1.4)) - 1.0).abs() < 1e-12);
    }
}
