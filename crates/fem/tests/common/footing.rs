//! The strip footing of Guillet et al. (2024), Fig. 3 (`scenes/footing.toml`), built with
//! talus-fem's API alone: a rough rigid footing of width 0.5 m pushed at 1 mm/s into a
//! non-associative Drucker-Prager soil (φ = 27°, c = 2 kPa, tan ψ = tan φ / 2) under
//! gravity and a 20 kPa surcharge beside it, from a K₀ = 0.546 state at rest; h = 0.01 s.
//!
//! ```text
//!   20 kPa ↓↓↓↓↓ |footing ↓ 1 mm/s| ↓↓↓↓↓ 20 kPa        y = 0
//!   |  ←x fixed                      x fixed→  |
//!   |            soil, ρ = 2000 kg/m³          |        y = −1 m
//!   ▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲ bottom fixed ▲▲▲▲▲▲▲▲▲▲▲▲▲▲▲
//!  x = −1 m                                  x = 1 m
//! ```
#![allow(dead_code)] // each test binary uses part of it
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_fem::{
    graded_coordinates, Assembly, Constraint, DofMap, ElementOrder, Mesh, Model, State,
};

/// The paper's step (s).
pub const H: f64 = 1e-2;

pub fn soil(dilatancy_angle: f64) -> DruckerPrager {
    DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e9,
        poisson_ratio: 0.3,
        friction_angle: 27.0,
        cohesion: 2e3,
        dilatancy_angle,
        cone_fit: ConeFit::PlaneStrain,
    })
    .expect("the paper's soil")
}

/// The footing on `cells` P2 cells, graded toward the surface by 1.1, with `soil`; and its
/// K₀ state at rest.
pub fn footing(cells: [usize; 2], soil: DruckerPrager) -> (Model, State) {
    let xs = graded_coordinates(-1.0, 1.0, cells[0], 0.0, 1.0).unwrap();
    let ys = graded_coordinates(-1.0, 0.0, cells[1], 0.0, 1.1).unwrap();
    let mesh = Mesh::rectangle(&xs, &ys, ElementOrder::P2).unwrap();
    let footing = mesh.nodes_in_box([-0.25, -1e-9], [0.25, 1e-9]).unwrap();
    let constraints = [
        (mesh.node_sets["bottom"].clone(), Constraint::Fixed),
        (mesh.node_sets["left"].clone(), Constraint::FixX),
        (mesh.node_sets["right"].clone(), Constraint::FixX),
        (footing.clone(), Constraint::Fixed),
    ];
    let dofs = DofMap::new(mesh.nodes.len(), &constraints).unwrap();
    let density = 2e3;
    let assembly = Assembly::new(&mesh, &dofs, density).unwrap();
    let weight = assembly.body_force(density, [0.0, -9.81]).unwrap();
    let surcharge: Vec<_> = [[-1.0, -0.25], [0.25, 1.0]]
        .iter()
        .map(|&[x0, x1]| {
            let edges = mesh.boundary_edges_in_box([x0, -1e-9], [x1, 1e-9]).unwrap();
            assembly.traction(&mesh, &edges, [0.0, -20e3]).unwrap()
        })
        .collect();
    let points = assembly.gauss_points.clone();
    let mut model = Model::new(mesh, assembly, soil);
    model.add_load(weight, None);
    for load in surcharge {
        model.add_load(load, None);
    }
    // The footing's reaction: both components of its nodes, the vertical one reported.
    for &n in &footing {
        for comp in 0..2 {
            let j = model.assembly.dofs().prescribed(n, comp).unwrap();
            model.reaction_dofs.push((j, comp));
        }
        let j = model.assembly.dofs().prescribed(n, 1).unwrap();
        model.prescribed_velocity[j] = -1e-3;
    }
    let dofs = model.assembly.dofs();
    let mut state = State::at_rest(
        model.n_points(),
        dofs.n_free(),
        dofs.n_prescribed(),
        model.mesh.nodes.len(),
    );
    // K₀ (Jaky, 1 − sin 27°): σ_yy = −(20 kPa + γ depth), σ_xx = σ_zz = K₀ σ_yy.
    for (p, x) in points.iter().enumerate() {
        let vertical = -(20e3 + density * 9.81 * (0.0 - x[1]));
        let s = [0.546 * vertical, vertical, 0.546 * vertical, 0.0];
        state.sigma[4 * p..4 * p + 4].copy_from_slice(&s);
    }
    (model, state)
}

/// The paper's soil: tan ψ = tan φ / 2.
pub fn paper_footing(cells: [usize; 2]) -> (Model, State) {
    footing(cells, soil(14.2906))
}
