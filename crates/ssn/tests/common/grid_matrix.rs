//! A 2-dof-per-node grid matrix with unsymmetric values: the pattern of a P1/Q1 stiffness,
//! for the no-pivot LU's tests and its thread benchmark.
use talus_ssn::faer::sparse::{SparseColMat, Triplet};

/// Deterministic numbers in [-1, 1) (SplitMix64).
pub struct Numbers(u64);
impl Numbers {
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// A 2-dof-per-node 9-point stencil on an `nx × ny` grid (the pattern of a P1/Q1
/// stiffness), unsymmetric values, diagonally dominant by `dominance`.
pub fn grid_matrix(nx: usize, ny: usize, dominance: f64, seed: u64) -> SparseColMat<usize, f64> {
    let mut rng = Numbers(seed);
    let node = |i: usize, j: usize| i + nx * j;
    let n = 2 * nx * ny;
    let mut triplets = Vec::new();
    let mut row_sum = vec![0.0; n];
    for j in 0..ny {
        for i in 0..nx {
            for dj in -1i64..=1 {
                for di in -1i64..=1 {
                    let (ii, jj) = (i as i64 + di, j as i64 + dj);
                    if ii < 0 || jj < 0 || ii >= nx as i64 || jj >= ny as i64 {
                        continue;
                    }
                    for a in 0..2 {
                        for b in 0..2 {
                            let r = 2 * node(i, j) + a;
                            let c = 2 * node(ii as usize, jj as usize) + b;
                            if r != c {
                                let v = rng.next();
                                row_sum[r] += v.abs();
                                triplets.push(Triplet::new(r, c, v));
                            }
                        }
                    }
                }
            }
        }
    }
    for (r, s) in row_sum.iter().enumerate() {
        triplets.push(Triplet::new(r, r, dominance * s + 1e-3));
    }
    SparseColMat::try_new_from_triplets(n, n, &triplets).expect("valid triplets")
}
