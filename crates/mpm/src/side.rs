//! The sides of the grid, where walls stand.

/// A side of the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
    Bottom,
    Top,
}

impl Side {
    /// Axis of the normal, and 0 for the low end, 1 for the high end.
    pub(crate) fn axis_and_end(&self) -> (usize, usize) {
        match self {
            Side::Left => (0, 0),
            Side::Right => (0, 1),
            Side::Bottom => (1, 0),
            Side::Top => (1, 1),
        }
    }

    /// Axis of the wall normal and the sign of the normal pointing into the domain.
    pub(crate) fn normal(&self) -> (usize, f64) {
        match self {
            Side::Left => (0, 1.0),
            Side::Right => (0, -1.0),
            Side::Bottom => (1, 1.0),
            Side::Top => (1, -1.0),
        }
    }
}
