/// The state between steps.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct State {
    pub time: f64,
    /// Mandel stress per Gauss point, flat (Pa).
    pub sigma: Vec<f64>,
    /// `∫‖ε̇ᵖ‖ dt` per Gauss point.
    pub plastic_strain: Vec<f64>,
    /// Velocities of the free and prescribed dofs (m/s).
    pub velocity_free: Vec<f64>,
    pub velocity_prescribed: Vec<f64>,
    /// Nodal displacement (m).
    pub displacement: Vec<[f64; 2]>,
}

impl State {
    /// At rest, stress free.
    pub fn at_rest(n_points: usize, n_free: usize, n_prescribed: usize, n_nodes: usize) -> Self {
        Self {
            time: 0.0,
            sigma: vec![0.0; 4 * n_points],
            plastic_strain: vec![0.0; n_points],
            velocity_free: vec![0.0; n_free],
            velocity_prescribed: vec![0.0; n_prescribed],
            displacement: vec![[0.0; 2]; n_nodes],
        }
    }
}
