//! Construction in stages: the finite-element primitives of an excavation. When a region
//! `R` of the body is dug out, the kept part `K` is modelled on its own mesh
//! ([`Mesh::submesh`](crate::Mesh::submesh)), starts from the state of the full body
//! restricted to it ([`restrict_state`], [`kept_points`]), and carries, as a load, the
//! force `F` the removed part exerted on it ([`element_forces`], [`restrict_forces`]); a
//! stage then ramps `F` to zero (`Model::add_load` with a `Ramp` from 1 to 0), and the
//! kept body answers to the excavation.
//!
//! # The force of the removed part
//!
//! Eq. 15 of Guillet et al. (2024) is the discrete momentum balance the stepper enforces,
//! `M (v − vₙ)/h + Bᵀσ = f` on the free dofs (`docs/derivations.md`, 'The reduced system
//! (eqs. 15–16)', item 1), and on a prescribed dof it defines the support's reaction `Rᵢ`,
//! `M_D a_D + B_Dᵀσ = f_D + R` ('Prescribed velocities and the reaction'). In a state at
//! rest (`M a = 0`) both read, at every dof `i`,
//!
//! `(Bᵀσ)ᵢ = fᵢ + Rᵢ`  (`Rᵢ = 0` on a free dof).
//!
//! `B` is a stack of row blocks, one per Gauss point, and each point belongs to one
//! triangle; the weight `fᵢ = Σ_p ρ_p V_p Nᵢ(x_p) g` is a sum over the same points. So
//! both split triangle by triangle, `(Bᵀσ)ᵢ = Σ_e (B_eᵀσ_e)ᵢ` and `fᵢ = Σ_e f_{e,i}`, and
//! with the triangles split into the kept `K` and the removed `R`:
//!
//! `Σ_{e∈K} (B_eᵀσ_e)ᵢ − Σ_{e∈K} f_{e,i} − Rᵢ = Σ_{e∈R} (f_{e,i} − (B_eᵀσ_e)ᵢ) =: Fᵢ`.
//!
//! The left side is the balance of `K` alone: cut free from `R`, `K` is at rest under its
//! own weight, its supports and the nodal force `Fᵢ`, the force `R` exerts on `K`. The
//! right side computes `F` from `R` alone, its weight minus its internal force, which is
//! [`element_forces`]. Consequences:
//!
//! - `Fᵢ = 0` at the nodes `R` does not touch, and at the free dofs of the nodes only `R`
//!   uses (there the right side is the whole balance): `F` lives on the interface (and on
//!   `R`'s supports), and the nodes that go with `R` take nothing with them.
//! - `Σᵢ Fᵢ` is the weight of `R`: a rigid translation strains nothing, so `Σᵢ (Bᵀσ)ᵢ`
//!   vanishes per component (axisymmetric: for `y` only, a radial motion strains the hoop).
//! - On a prescribed dof of `K` the support's reaction takes part of the balance, and `F`
//!   there, a load on a prescribed dof, changes only the kept model's reaction.
//! - The identity holds for any `σ` at rest; for a state stepped by the engine, to its
//!   Newton tolerance and inertia (`M (v − vₙ)/h`, which `F` then carries `R`'s share of).
//! - Other loads that `R` carried (a traction on its edges, a point force on a node only
//!   it holds) reach `K` through it: add their nodal forces (the `Assembly`'s load
//!   methods, spread over nodes by `DofMap::scatter`) to `F`.
use crate::dimension::{Dimension, ElementMesh, Mandel};
use crate::dofs::{Dof, DofMap};
use crate::error::FemError;
use crate::model::Model;
use crate::state::State;

/// Whether each triangle of a mesh of `n_triangles` is in `elements` (each once, in range).
fn selection(n_triangles: usize, elements: &[usize]) -> Result<Vec<bool>, FemError> {
    let mut selected = vec![false; n_triangles];
    for (k, &e) in elements.iter().enumerate() {
        if e >= n_triangles {
            return Err(FemError::invalid(
                "elements",
                format!("entry {k} is triangle {e}, the mesh has {n_triangles} triangles"),
            ));
        }
        if selected[e] {
            return Err(FemError::invalid(
                "elements",
                format!("entry {k} names triangle {e} a second time"),
            ));
        }
        selected[e] = true;
    }
    Ok(selected)
}

/// The force the triangles `elements` (indices into the model's mesh, any order, each
/// once) exert on their nodes in `state`, per node of the full mesh (N/m, or N per radian
/// in axisymmetry): their weight minus their internal force,
/// `Fᵢ = Σ_{e∈elements} (∫ Nᵢ ρ g − Bᵀσ)_{e,i}`, integrated with the model's Gauss points
/// (`ρ_p = densities[p]`, one per point of the model, kg/m³, `≥ 0`; `gravity` in m/s²).
/// For a state at rest, and `elements` the part dug out, it is the force that part exerted
/// on the rest (the module's documentation derives it): the load a stage ramps to zero.
/// Pass the densities the model's weight was built with (`Assembly::body_force_at_points`,
/// or one value repeated for `Assembly::body_force`), so that `F` matches the weight the
/// stress carries.
///
/// Errors name `elements` (empty, out of range or repeated), `densities` (length, or an
/// entry of a selected point not finite and `≥ 0`), `gravity` (not finite) or `sigma`
/// (the state's length).
pub fn element_forces(
    model: &Model,
    state: &State,
    elements: &[usize],
    gravity: [f64; 2],
    densities: &[f64],
) -> Result<Vec<[f64; 2]>, FemError> {
    let asm = &model.assembly;
    if elements.is_empty() {
        return Err(FemError::invalid("elements", "selects no triangle"));
    }
    let selected = selection(model.mesh.triangles.len(), elements)?;
    let n = asm.n_points();
    if densities.len() != n {
        return Err(FemError::invalid(
            "densities",
            format!("has {} entries for {n} Gauss points", densities.len()),
        ));
    }
    if state.sigma.len() != 4 * n {
        return Err(FemError::invalid(
            "sigma",
            format!("{} values for {n} Gauss points × 4", state.sigma.len()),
        ));
    }
    // The selected points' densities and stresses; the others' 0, so that the assembly's
    // own sums over all points give the selected triangles' share.
    let mut rho = vec![0.0; n];
    let mut sigma = vec![0.0; 4 * n];
    for (p, &e) in asm.gauss_element.iter().enumerate() {
        if selected[e] {
            rho[p] = densities[p];
            sigma[4 * p..4 * p + 4].copy_from_slice(&state.sigma[4 * p..4 * p + 4]);
        }
    }
    let (weight_free, weight_prescribed) = asm.body_force_at_points(&rho, gravity)?;
    let (internal_free, internal_prescribed) = asm.internal_force(&sigma)?;
    let dofs = asm.dofs();
    let weight = dofs.scatter(&weight_free, &weight_prescribed)?;
    let internal = dofs.scatter(&internal_free, &internal_prescribed)?;
    Ok(weight
        .iter()
        .zip(&internal)
        .map(|(w, b)| [w[0] - b[0], w[1] - b[1]])
        .collect())
}

/// The Gauss point of `full` that each Gauss point of the kept model is, when the kept
/// model is built on `full.mesh.submesh(kept_elements)` with the same rule (same order,
/// same geometry): the assembly numbers points triangle by triangle, each triangle's
/// points contiguous and in the rule's order, and the submesh keeps the triangles in
/// increasing old index, so the kept points are the full model's points of the kept
/// triangles, in their order. Per-point fields carry over through it, e.g. the kept
/// model's `point_material`, `pore_pressure` or densities (before its `Assembly` exists):
/// `kept.iter().map(|&p| field[p])`. Errors name `elements` (empty, out of range or
/// repeated).
pub fn kept_points(full: &Model, kept_elements: &[usize]) -> Result<Vec<usize>, FemError> {
    if kept_elements.is_empty() {
        return Err(FemError::invalid("elements", "selects no triangle"));
    }
    let selected = selection(full.mesh.triangles.len(), kept_elements)?;
    Ok(full
        .assembly
        .gauss_element
        .iter()
        .enumerate()
        .filter(|(_, &e)| selected[e])
        .map(|(p, _)| p)
        .collect())
}

/// Nodal forces of the full mesh (`forces[n]`, e.g. from [`element_forces`]) on the kept
/// model's dofs `dofs`, through the node map of [`Mesh::submesh`](crate::Mesh::submesh):
/// `(free, prescribed)` like the `Assembly`'s loads, ready for `Model::add_load`. Forces on
/// nodes the submesh dropped are left out (0 at rest: see the module's documentation).
/// Errors name `forces` or `node_map` when their lengths, or the kept node count, disagree.
pub fn restrict_forces(
    forces: &[[f64; 2]],
    node_map: &[Option<usize>],
    dofs: &DofMap,
) -> Result<(Vec<f64>, Vec<f64>), FemError> {
    if forces.len() != node_map.len() {
        return Err(FemError::invalid(
            "forces",
            format!(
                "{} nodal forces for a node map of {} nodes",
                forces.len(),
                node_map.len()
            ),
        ));
    }
    check_node_map(node_map, dofs.n_nodes())?;
    let mut free = vec![0.0; dofs.n_free()];
    let mut prescribed = vec![0.0; dofs.n_prescribed()];
    for (force, new) in forces.iter().zip(node_map) {
        let Some(new) = *new else { continue };
        for (comp, f) in force.iter().enumerate() {
            match dofs.dof(new, comp) {
                Some(Dof::Free(i)) => free[i] += f,
                Some(Dof::Prescribed(j)) => prescribed[j] += f,
                None => unreachable!("check_node_map: every kept node is in the dof map"),
            }
        }
    }
    Ok((free, prescribed))
}

/// The map of [`Mesh::submesh`](crate::Mesh::submesh) sends the kept nodes onto
/// `0..n_kept`, increasing.
fn check_node_map(node_map: &[Option<usize>], n_kept: usize) -> Result<(), FemError> {
    let image: Vec<usize> = node_map.iter().flatten().copied().collect();
    if image.len() != n_kept || image.iter().enumerate().any(|(k, &n)| n != k) {
        return Err(FemError::invalid(
            "node_map",
            format!(
                "keeps {} nodes for a kept mesh of {n_kept}, or does not number them 0, 1, … \
                 in increasing old index as Mesh::submesh does",
                image.len()
            ),
        ));
    }
    Ok(())
}

/// The state of the kept model `kept` (built on `full.mesh.submesh(kept_elements)`, whose
/// node map is `node_map`) from the state `state` of the full model `full`: same time;
/// the stresses and plastic strains of the kept Gauss points ([`kept_points`]); the nodal
/// displacements and velocities of the kept nodes, the velocities split again into free
/// and prescribed ones by the kept model's dof map (a node's velocity is kept whatever its
/// constraints were, so that a dof newly prescribed keeps the velocity it had).
///
/// Errors name `state` (its lengths do not fit `full`), `node_map` (not `full`'s nodes,
/// or not onto `kept`'s), `elements` (as in [`kept_points`]) or `kept` (its triangles are
/// not the kept ones, in order, through `node_map`).
pub fn restrict_state(
    full: &Model,
    state: &State,
    kept: &Model,
    kept_elements: &[usize],
    node_map: &[Option<usize>],
) -> Result<State, FemError> {
    // The state's sizes are checked by `transfer_state`.
    let n_nodes = full.mesh.nodes.len();
    if node_map.len() != n_nodes {
        return Err(FemError::invalid(
            "node_map",
            format!(
                "has {} entries, the full mesh {n_nodes} nodes",
                node_map.len()
            ),
        ));
    }
    check_node_map(node_map, kept.mesh.nodes.len())?;
    let points = kept_points(full, kept_elements)?;
    let mut sorted = kept_elements.to_vec();
    sorted.sort_unstable();
    let same_triangles = sorted.len() == kept.mesh.triangles.len()
        && sorted.iter().zip(&kept.mesh.triangles).all(|(&e, new)| {
            full.mesh.triangles[e].len() == new.len()
                && full.mesh.triangles[e]
                    .iter()
                    .zip(new)
                    .all(|(&old, &n)| node_map[old] == Some(n))
        });
    if !same_triangles || points.len() != kept.n_points() {
        return Err(FemError::invalid(
            "kept",
            format!(
                "the kept model's {} triangles and {} Gauss points are not the {} kept \
                 triangles (with {} points) of the full mesh in increasing index through \
                 the node map: build it on Mesh::submesh of the same elements",
                kept.mesh.triangles.len(),
                kept.n_points(),
                sorted.len(),
                points.len()
            ),
        ));
    }

    let whole_elements: Vec<usize> = (0..full.mesh.triangles.len()).collect();
    let whole_nodes: Vec<usize> = (0..n_nodes).collect();
    let mut kept_nodes = vec![0; kept.mesh.nodes.len()];
    for (old, new) in node_map.iter().enumerate() {
        if let Some(new) = *new {
            kept_nodes[new] = old;
        }
    }
    transfer_state(
        Part {
            model: full,
            elements: &whole_elements,
            nodes: &whole_nodes,
        },
        state,
        Part {
            model: kept,
            elements: &sorted,
            nodes: &kept_nodes,
        },
        false,
    )
}

/// A model built on part of a mesh (`Mesh::submesh`, `TetrahedralMesh::submesh`): the
/// model, and the whole mesh's indices of its elements and of its nodes, both increasing
/// (the submesh's order). 2D (`D = 4`) or 3D (`D = 6`).
#[derive(Clone, Copy)]
pub struct Part<'a, const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub model: &'a Model<D>,
    pub elements: &'a [usize],
    pub nodes: &'a [usize],
}

/// The state of `to` from `state` of `from`, two models on parts of one mesh (a stage
/// of construction and the next), in 2D or 3D: same time; the stresses and plastic
/// strains of the elements both have (the others', new ones, stress free); the
/// displacements and velocities of the nodes both have (new ones at rest; displacements
/// zero everywhere when `reset`), the velocities split into free and prescribed ones by
/// `to`'s dof map. Each element's Gauss points are contiguous, in the rule's order
/// ([`kept_points`]).
///
/// Errors name `state` (its lengths do not fit `from`) or `part` (a part's index lists do
/// not fit its model).
pub fn transfer_state<const D: usize>(
    from: Part<D>,
    state: &State<D>,
    to: Part<D>,
    reset: bool,
) -> Result<State<D>, FemError>
where
    Mandel<D>: Dimension,
{
    for (name, part) in [("from", &from), ("to", &to)] {
        let m = part.model;
        let (elements, nodes) = (m.mesh.elements().len(), m.mesh.node_positions().len());
        if part.elements.len() != elements
            || part.nodes.len() != nodes
            || m.n_points() % part.elements.len().max(1) != 0
        {
            return Err(FemError::invalid(
                "part",
                format!(
                    "{name}: {} elements and {} nodes listed for a model of {elements} and \
                     {nodes}",
                    part.elements.len(),
                    part.nodes.len(),
                ),
            ));
        }
    }
    let fm = from.model;
    let from_nodes = fm.mesh.node_positions().len();
    if state.sigma.len() != D * fm.n_points()
        || state.plastic_strain.len() != fm.n_points()
        || state.displacement.len() != from_nodes
    {
        return Err(FemError::invalid(
            "state",
            format!(
                "{} stresses, {} plastic strains and {} displacements for a model of {} Gauss \
                 points (× {D}) and {from_nodes} nodes",
                state.sigma.len(),
                state.plastic_strain.len(),
                state.displacement.len(),
                fm.n_points(),
            ),
        ));
    }
    let dofs_from = fm.assembly.dofs();
    dofs_from
        .check_lengths(&state.velocity_free, &state.velocity_prescribed)
        .map_err(|e| FemError::invalid("state", format!("velocities: {e}")))?;
    let velocity = |node: usize, comp: usize| match dofs_from.dof(node, comp) {
        Some(Dof::Free(i)) => state.velocity_free[i],
        Some(Dof::Prescribed(j)) => state.velocity_prescribed[j],
        None => 0.0,
    };
    let components = dofs_from.components();
    let tm = to.model;
    let dofs = tm.assembly.dofs();
    let mut out = State::at_rest(
        tm.n_points(),
        dofs.n_free(),
        dofs.n_prescribed(),
        tm.mesh.node_positions().len(),
    );
    out.time = state.time;
    let per = tm.n_points() / to.elements.len().max(1);
    for (i, e) in to.elements.iter().enumerate() {
        if let Ok(j) = from.elements.binary_search(e) {
            out.sigma[D * per * i..D * per * (i + 1)]
                .copy_from_slice(&state.sigma[D * per * j..D * per * (j + 1)]);
            out.plastic_strain[per * i..per * (i + 1)]
                .copy_from_slice(&state.plastic_strain[per * j..per * (j + 1)]);
        }
    }
    for (new, n) in to.nodes.iter().enumerate() {
        let Ok(old) = from.nodes.binary_search(n) else {
            continue;
        };
        if !reset {
            out.displacement[new] = state.displacement[old];
        }
        for comp in 0..components {
            let v = velocity(old, comp);
            match dofs.dof(new, comp) {
                Some(Dof::Free(i)) => out.velocity_free[i] = v,
                Some(Dof::Prescribed(j)) => out.velocity_prescribed[j] = v,
                None => {}
            }
        }
    }
    Ok(out)
}
