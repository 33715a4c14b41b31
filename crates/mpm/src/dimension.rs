//! The two dimensions of the material point method (`docs/3d-mpm.md`), as in talus-fem
//! (`crates/fem/src/dimension.rs`): plane strain, whose particles carry 4 Mandel components
//! `(xx, yy, zz, √2 xy)` and move in the xy plane, and 3D, whose particles carry 6
//! `(xx, yy, zz, √2 yz, √2 xz, √2 xy)`. The crate's types are generic over that Mandel size
//! `D` (4 by default, so 2D code reads and computes as before); [`Dimension`] says what each
//! size means. Every per-dimension formula whose 2D rounding must not change (the internal
//! force, the Jacobian, the stress rotation) lives here, once per dimension.
use std::fmt::Debug;
use std::ops::{Index, IndexMut};

/// The Mandel size `D` of a particle's stress, as a type: `Mandel<4>` (2D) or `Mandel<6>`
/// (3D).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mandel<const D: usize>;

/// A position, velocity or force of dimension `D`: `[f64; 2]` or `[f64; 3]`.
pub type Vector<const D: usize> = <Mandel<D> as Dimension>::Point;

/// A velocity gradient `L_ab = ∂v_a/∂x_b`; in 2D only the upper-left 2 × 2 block is used.
pub(crate) type Gradient = [[f64; 3]; 3];

/// What a Mandel size means for the grid, the particles and the transfers.
pub trait Dimension {
    /// Space dimensions: 2 or 3.
    const AXES: usize;
    /// A position or a vector (m, m/s, N): `[f64; 2]` or `[f64; 3]`.
    type Point: Copy
        + Default
        + Debug
        + PartialEq
        + Index<usize, Output = f64>
        + IndexMut<usize>
        + AsRef<[f64]>
        + AsMut<[f64]>
        + serde::Serialize
        + serde::de::DeserializeOwned
        + Send
        + Sync
        + 'static;
    /// Cells per axis: `[usize; 2]` or `[usize; 3]`.
    type Cells: Copy + Debug + PartialEq + Index<usize, Output = usize> + AsRef<[usize]>;
    /// Integer node coordinates: `[i64; 2]` or `[i64; 3]`.
    type NodeCoordinates: Copy
        + Default
        + Debug
        + PartialEq
        + Eq
        + Index<usize, Output = i64>
        + IndexMut<usize>;
    /// Prescribed velocity components, `None` free: `[Option<f64>; 2]` or `[Option<f64>; 3]`.
    type Components: Copy + Debug + PartialEq + AsRef<[Option<f64>]>;
    /// The nodes a particle touches, at most `3^AXES` (quadratic B-splines).
    type StencilArray<T: Copy + Default + Debug>: Copy + Default + Debug + AsRef<[T]> + AsMut<[T]>;

    /// The Mandel rows of `ε̇ = sym ∇v` fed by velocity component `component` of a node
    /// whose shape function has gradient `g` at the particle (eq. 12's `B`; unused entries
    /// carry a zero coefficient).
    fn strain_rows(g: &Self::Point, component: usize) -> [(usize, f64); 3];

    /// `σ ∇N` (per unit volume) for a node of gradient `g` and a particle of Mandel stress
    /// `t`: the node's share of the internal force `Bᵀσ`.
    fn internal_force(g: &Self::Point, t: &[f64]) -> Self::Point;

    /// `det(I + h L)`, the volume ratio over a step.
    fn jacobian(l: &Gradient, h: f64) -> f64;

    /// `t ← R t Rᵀ`, `R = exp(h W)` with `W = (L − Lᵀ)/2` the spin (Mandel, in place).
    fn rotate(t: &mut [f64], l: &Gradient, h: f64);

    /// A position of this dimension from its first `AXES` coordinates.
    fn point(x: [f64; 3]) -> Self::Point;
}

impl Dimension for Mandel<4> {
    const AXES: usize = 2;
    type Point = [f64; 2];
    type Cells = [usize; 2];
    type NodeCoordinates = [i64; 2];
    type Components = [Option<f64>; 2];
    type StencilArray<T: Copy + Default + Debug> = [T; 9];

    fn strain_rows(g: &[f64; 2], component: usize) -> [(usize, f64); 3] {
        let r2 = std::f64::consts::FRAC_1_SQRT_2;
        match component {
            0 => [(0, g[0]), (3, r2 * g[1]), (0, 0.0)],
            _ => [(1, g[1]), (3, r2 * g[0]), (0, 0.0)],
        }
    }

    fn internal_force(g: &[f64; 2], t: &[f64]) -> [f64; 2] {
        let sxy = std::f64::consts::FRAC_1_SQRT_2 * t[3];
        [g[0] * t[0] + g[1] * sxy, g[1] * t[1] + g[0] * sxy]
    }

    fn jacobian(l: &Gradient, h: f64) -> f64 {
        (1.0 + h * l[0][0]) * (1.0 + h * l[1][1]) - h * h * l[0][1] * l[1][0]
    }

    fn rotate(t: &mut [f64], l: &Gradient, h: f64) {
        // A rotation by the angle h ω_z in the xy plane; σzz is unchanged.
        let angle = 0.5 * h * (l[1][0] - l[0][1]);
        let (s, c) = angle.sin_cos();
        let sxy = t[3] * std::f64::consts::FRAC_1_SQRT_2;
        let xx = c * c * t[0] - 2.0 * s * c * sxy + s * s * t[1];
        let yy = s * s * t[0] + 2.0 * s * c * sxy + c * c * t[1];
        let xy = s * c * (t[0] - t[1]) + (c * c - s * s) * sxy;
        t[0] = xx;
        t[1] = yy;
        t[3] = std::f64::consts::SQRT_2 * xy;
    }

    fn point(x: [f64; 3]) -> [f64; 2] {
        [x[0], x[1]]
    }
}

impl Dimension for Mandel<6> {
    const AXES: usize = 3;
    type Point = [f64; 3];
    type Cells = [usize; 3];
    type NodeCoordinates = [i64; 3];
    type Components = [Option<f64>; 3];
    type StencilArray<T: Copy + Default + Debug> = [T; 27];

    fn strain_rows(g: &[f64; 3], component: usize) -> [(usize, f64); 3] {
        // The rows of talus-fem's `mandel_strain_rows` (docs/3d.md).
        let s = std::f64::consts::FRAC_1_SQRT_2;
        match component {
            0 => [(0, g[0]), (4, s * g[2]), (5, s * g[1])],
            1 => [(1, g[1]), (3, s * g[2]), (5, s * g[0])],
            _ => [(2, g[2]), (3, s * g[1]), (4, s * g[0])],
        }
    }

    fn internal_force(g: &[f64; 3], t: &[f64]) -> [f64; 3] {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let (yz, xz, xy) = (s * t[3], s * t[4], s * t[5]);
        [
            g[0] * t[0] + g[1] * xy + g[2] * xz,
            g[0] * xy + g[1] * t[1] + g[2] * yz,
            g[0] * xz + g[1] * yz + g[2] * t[2],
        ]
    }

    fn jacobian(l: &Gradient, h: f64) -> f64 {
        let f = |a: usize, b: usize| (a == b) as u8 as f64 + h * l[a][b];
        f(0, 0) * (f(1, 1) * f(2, 2) - f(1, 2) * f(2, 1))
            - f(0, 1) * (f(1, 0) * f(2, 2) - f(1, 2) * f(2, 0))
            + f(0, 2) * (f(1, 0) * f(2, 1) - f(1, 1) * f(2, 0))
    }

    fn rotate(t: &mut [f64], l: &Gradient, h: f64) {
        // Rodrigues: R = I + sin θ K + (1 − cos θ) K², K = [n]×, θ n = h ω, ω the axial
        // vector of the spin W = (L − Lᵀ)/2 (2D's angle is θ = h ω_z).
        let omega = [
            0.5 * (l[2][1] - l[1][2]),
            0.5 * (l[0][2] - l[2][0]),
            0.5 * (l[1][0] - l[0][1]),
        ];
        let theta = h * omega.iter().map(|w| w * w).sum::<f64>().sqrt();
        if theta == 0.0 {
            return;
        }
        let n = omega.map(|w| h * w / theta);
        let k = [[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]];
        let (s, c) = theta.sin_cos();
        let mut r = [[0.0; 3]; 3];
        for a in 0..3 {
            for b in 0..3 {
                let k2: f64 = (0..3).map(|m| k[a][m] * k[m][b]).sum();
                r[a][b] = (a == b) as u8 as f64 + s * k[a][b] + (1.0 - c) * k2;
            }
        }
        let sigma = mandel6_to_tensor(t);
        let mut out = [[0.0; 3]; 3];
        for a in 0..3 {
            for b in 0..3 {
                let mut v = 0.0;
                for m in 0..3 {
                    for q in 0..3 {
                        v += r[a][m] * sigma[m][q] * r[b][q];
                    }
                }
                out[a][b] = v;
            }
        }
        let r2 = std::f64::consts::SQRT_2;
        t.copy_from_slice(&[
            out[0][0],
            out[1][1],
            out[2][2],
            r2 * 0.5 * (out[1][2] + out[2][1]),
            r2 * 0.5 * (out[0][2] + out[2][0]),
            r2 * 0.5 * (out[0][1] + out[1][0]),
        ]);
    }

    fn point(x: [f64; 3]) -> [f64; 3] {
        x
    }
}

/// The symmetric tensor of a Mandel 6-vector `(xx, yy, zz, √2 yz, √2 xz, √2 xy)`.
pub(crate) fn mandel6_to_tensor(t: &[f64]) -> [[f64; 3]; 3] {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let (yz, xz, xy) = (s * t[3], s * t[4], s * t[5]);
    [[t[0], xy, xz], [xy, t[1], yz], [xz, yz, t[2]]]
}

/// Serde for `Vec<[f64; D]>` (serde implements arrays only of literal sizes): each entry a
/// tuple of `D` numbers, as serde writes `[f64; 4]`, so 2D checkpoints read as before.
pub(crate) mod stress_serde {
    use serde::de::{Error, SeqAccess, Visitor};
    use serde::ser::SerializeTuple;
    use serde::{Deserializer, Serializer};

    struct Row<'a, const D: usize>(&'a [f64; D]);

    impl<const D: usize> serde::Serialize for Row<'_, D> {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            let mut t = s.serialize_tuple(D)?;
            for v in self.0 {
                t.serialize_element(v)?;
            }
            t.end()
        }
    }

    pub fn serialize<S: Serializer, const D: usize>(
        v: &[[f64; D]],
        s: S,
    ) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(Row))
    }

    struct RowVisitor<const D: usize>;

    impl<'de, const D: usize> Visitor<'de> for RowVisitor<D> {
        type Value = [f64; D];
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            write!(f, "{D} stress components")
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[f64; D], A::Error> {
            let mut out = [0.0; D];
            for (k, o) in out.iter_mut().enumerate() {
                *o = seq
                    .next_element()?
                    .ok_or_else(|| A::Error::invalid_length(k, &self))?;
            }
            if seq.next_element::<f64>()?.is_some() {
                return Err(A::Error::invalid_length(D + 1, &self));
            }
            Ok(out)
        }
    }

    struct RowSeed<const D: usize>;

    impl<'de, const D: usize> serde::de::DeserializeSeed<'de> for RowSeed<D> {
        type Value = [f64; D];
        fn deserialize<De: Deserializer<'de>>(self, d: De) -> Result<[f64; D], De::Error> {
            d.deserialize_tuple(D, RowVisitor::<D>)
        }
    }

    struct RowsVisitor<const D: usize>;

    impl<'de, const D: usize> Visitor<'de> for RowsVisitor<D> {
        type Value = Vec<[f64; D]>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            write!(f, "a list of stresses of {D} components")
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
            let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0));
            while let Some(row) = seq.next_element_seed(RowSeed::<D>)? {
                out.push(row);
            }
            Ok(out)
        }
    }

    pub fn deserialize<'de, De: Deserializer<'de>, const D: usize>(
        d: De,
    ) -> Result<Vec<[f64; D]>, De::Error> {
        d.deserialize_seq(RowsVisitor::<D>)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rotation of the frame turns a stress like `R σ Rᵀ`: about z, 3D's Rodrigues
    /// update matches 2D's planar one; any rotation keeps the invariants.
    #[test]
    fn the_3d_rotation_matches_2d_about_z_and_keeps_the_invariants() {
        let mut l = [[0.0; 3]; 3];
        l[1][0] = 0.7;
        l[0][1] = -0.3;
        let mut t2 = [1.0, -2.0, 0.5, 0.8];
        let r2 = std::f64::consts::SQRT_2;
        let mut t3 = [1.0, -2.0, 0.5, 0.0, 0.0, 0.8];
        Mandel::<4>::rotate(&mut t2, &l, 0.3);
        Mandel::<6>::rotate(&mut t3, &l, 0.3);
        for (a, b) in [(0, 0), (1, 1), (2, 2), (3, 5)] {
            assert!((t2[a] - t3[b]).abs() < 1e-14, "{t2:?} vs {t3:?}");
        }
        assert!(t3[3].abs() < 1e-15 && t3[4].abs() < 1e-15);
        let l = [[0.1, -0.4, 0.9], [0.2, -0.3, 0.5], [-0.6, 0.3, 0.2]];
        let mut t = [1.0, -2.0, 0.5, 0.3 * r2, -0.7 * r2, 0.8 * r2];
        let (i1, n0) = (t[0] + t[1] + t[2], t.iter().map(|v| v * v).sum::<f64>());
        Mandel::<6>::rotate(&mut t, &l, 0.5);
        assert!((t[0] + t[1] + t[2] - i1).abs() < 1e-14);
        assert!((t.iter().map(|v| v * v).sum::<f64>() - n0).abs() < 1e-13);
    }

    #[test]
    fn the_3d_jacobian_is_the_determinant() {
        let l = [[0.1, -0.4, 0.9], [0.2, -0.3, 0.5], [-0.6, 0.3, 0.2]];
        let h = 0.1;
        let f = |a: usize, b: usize| (a == b) as u8 as f64 + h * l[a][b];
        let m = nalgebra::Matrix3::from_fn(f);
        assert!((Mandel::<6>::jacobian(&l, h) - m.determinant()).abs() < 1e-15);
    }
}
