use crate::dimension::{Dimension, Mandel};

/// The state between steps (`D` Mandel components per point: 4 in 2D, 6 in 3D).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct State<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub time: f64,
    /// Mandel stress per Gauss point, flat (Pa).
    pub sigma: Vec<f64>,
    /// `∫‖ε̇ᵖ‖ dt` per Gauss point.
    pub plastic_strain: Vec<f64>,
    /// Velocities of the free and prescribed dofs (m/s).
    pub velocity_free: Vec<f64>,
    pub velocity_prescribed: Vec<f64>,
    /// Nodal displacement (m).
    pub displacement: Vec<<Mandel<D> as Dimension>::Point>,
}

impl<const D: usize> State<D>
where
    Mandel<D>: Dimension,
{
    /// At rest, stress free.
    pub fn at_rest(n_points: usize, n_free: usize, n_prescribed: usize, n_nodes: usize) -> Self {
        Self {
            time: 0.0,
            sigma: vec![0.0; D * n_points],
            plastic_strain: vec![0.0; n_points],
            velocity_free: vec![0.0; n_free],
            velocity_prescribed: vec![0.0; n_prescribed],
            displacement: vec![Default::default(); n_nodes],
        }
    }
}
