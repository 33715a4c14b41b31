//! The sides of the grid, where walls stand: x (left, right), y (bottom, top: y is
//! vertical in both dimensions) and, in 3D, z (back, front; front is the largest z, as in
//! talus-fem's block meshes).

/// A side of the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
    Bottom,
    Top,
    /// z = z₀ (3D only).
    Back,
    /// z = z₀ + nz dx (3D only).
    Front,
}

impl Side {
    /// Axis of the normal, and 0 for the low end, 1 for the high end.
    pub(crate) fn axis_and_end(&self) -> (usize, usize) {
        match self {
            Side::Left => (0, 0),
            Side::Right => (0, 1),
            Side::Bottom => (1, 0),
            Side::Top => (1, 1),
            Side::Back => (2, 0),
            Side::Front => (2, 1),
        }
    }

    /// Axis of the wall normal and the sign of the normal pointing into the domain.
    pub(crate) fn normal(&self) -> (usize, f64) {
        let (axis, end) = self.axis_and_end();
        (axis, if end == 0 { 1.0 } else { -1.0 })
    }
}
