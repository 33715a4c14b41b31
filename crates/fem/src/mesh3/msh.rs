//! Gmsh `.msh` 4.1 tetrahedral meshes (ASCII or binary), through the 2D reader's checks
//! (`mesh::msh`).
//!
//! - `Tet4` elements make a P1 mesh, `Tet10` a P2 mesh (mixing them is an error).
//! - Physical volumes become element sets; physical surfaces (`Tri3` / `Tri6`) become face
//!   sets and node sets, each face turned to point out of the tetrahedron it bounds;
//!   physical curves and points become node sets. Unnamed groups are
//!   `physical_<dim>_<tag>`.
//! - Only nodes used by tetrahedra are kept, numbered by increasing Gmsh tag.
//! - An inverted or flat tetrahedron, or a face that bounds no tetrahedron, is an error
//!   naming its Gmsh element tag.
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

use mshio::ElementType;

use super::{face_key, TetrahedralMesh};
use crate::element::ElementOrder;
use crate::error::MeshError;
use crate::mesh::msh::{entity_groups, group_name, node_coordinates, read, MAX_COORDINATE};

impl TetrahedralMesh {
    /// Reads a Gmsh 4.1 file (ASCII or binary); see the module documentation.
    pub fn from_msh(path: &Path) -> Result<TetrahedralMesh, MeshError> {
        let bytes = std::fs::read(path).map_err(|e| MeshError::Io {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        Self::from_msh_bytes(&bytes)
    }

    /// Same as [`from_msh`](Self::from_msh) for the file's content.
    pub fn from_msh_bytes(bytes: &[u8]) -> Result<TetrahedralMesh, MeshError> {
        let (file, names) = read(bytes)?;
        let physical = entity_groups(&file);
        let coords = node_coordinates(&file)?;
        let mut order: Option<(ElementOrder, u64)> = None;
        // (element tag, entity tag, nodes) by dimension: 0 points, 1 lines, 2 faces, 3 tets.
        let mut by_dim: [Vec<(u64, i32, &[u64])>; 4] = Default::default();
        if let Some(elements) = &file.data.elements {
            for block in &elements.element_blocks {
                let (dim, tet_order) = match block.element_type {
                    ElementType::Tet4 => (3, Some(ElementOrder::P1)),
                    ElementType::Tet10 => (3, Some(ElementOrder::P2)),
                    ElementType::Tri3 | ElementType::Tri6 => (2, None),
                    ElementType::Lin2 | ElementType::Lin3 => (1, None),
                    ElementType::Pnt => (0, None),
                    other => {
                        let tag = block.elements.first().map_or(0, |e| e.element_tag);
                        return Err(MeshError::element(
                            format!("Gmsh element {tag}"),
                            format!(
                                "has type {other:?}; only Tet4 / Tet10 (with Tri3 / Tri6, \
                                 Lin2 / Lin3, Pnt) are supported in 3D"
                            ),
                        ));
                    }
                };
                for el in &block.elements {
                    if let Some(o) = tet_order {
                        match order {
                            None => order = Some((o, el.element_tag)),
                            Some((first, first_tag)) if first != o => {
                                return Err(MeshError::element(
                                    format!("Gmsh element {}", el.element_tag),
                                    format!(
                                        "is {o:?} but Gmsh element {first_tag} is {first:?}: \
                                         mixed element orders"
                                    ),
                                ))
                            }
                            _ => {}
                        }
                    }
                    by_dim[dim].push((el.element_tag, block.entity_tag, &el.nodes));
                }
            }
        }
        let Some((order, _)) = order else {
            return Err(MeshError::msh(
                "the file holds no Tet4 or Tet10 elements: a triangle mesh is a 2D mesh",
            ));
        };

        // The nodes of tetrahedra, numbered by increasing tag.
        let mut used = BTreeSet::new();
        for (tag, _, nodes) in &by_dim[3] {
            for n in *nodes {
                let Some(x) = coords.get(n) else {
                    return Err(MeshError::element(
                        format!("Gmsh element {tag}"),
                        format!("refers to node {n}, which $Nodes does not define"),
                    ));
                };
                if !x.iter().all(|c| c.abs() <= MAX_COORDINATE) {
                    return Err(MeshError::msh(format!(
                        "node {n} has (x, y, z) = {x:?}: coordinates must be finite and \
                         within ±{MAX_COORDINATE:e} m"
                    )));
                }
                used.insert(*n);
            }
        }
        let index: HashMap<u64, usize> = used.iter().enumerate().map(|(i, &t)| (t, i)).collect();
        let local = |tag: u64, what: &str, n: u64| {
            index.get(&n).copied().ok_or_else(|| {
                MeshError::element(
                    format!("Gmsh element {tag}"),
                    format!("({what}) refers to node {n}, which belongs to no tetrahedron"),
                )
            })
        };
        let tetrahedra: Vec<Vec<usize>> = by_dim[3]
            .iter()
            .map(|(tag, _, nodes)| {
                nodes
                    .iter()
                    .map(|&n| local(*tag, "tetrahedron", n))
                    .collect()
            })
            .collect::<Result<_, _>>()?;
        let mut mesh = TetrahedralMesh {
            order,
            nodes: used.iter().map(|t| coords[t]).collect(),
            tetrahedra,
            node_sets: BTreeMap::new(),
            face_sets: BTreeMap::new(),
            element_sets: BTreeMap::new(),
        };
        let tags: Vec<u64> = by_dim[3].iter().map(|t| t.0).collect();
        mesh.check_elements_labelled(&|e| format!("Gmsh element {}", tags[e]))?;

        // Each face of a tetrahedron, by its sorted vertices: (tetrahedron, local face).
        let mut owner: HashMap<[usize; 3], (usize, usize)> = HashMap::new();
        for (e, t) in mesh.tetrahedra.iter().enumerate() {
            for f in 0..4 {
                owner.insert(face_key(t, f), (e, f));
            }
        }
        let per_face = match order {
            ElementOrder::P1 => 3,
            ElementOrder::P2 => 6,
        };
        for (tag, entity, nodes) in &by_dim[2] {
            let groups = physical.get(&(2, *entity)).map_or(&[][..], Vec::as_slice);
            if groups.is_empty() {
                continue;
            }
            if nodes.len() != per_face {
                return Err(MeshError::element(
                    format!("Gmsh element {tag}"),
                    format!(
                        "is a triangle of {} nodes in a {order:?} mesh (needs {per_face})",
                        nodes.len()
                    ),
                ));
            }
            let given: Vec<usize> = nodes
                .iter()
                .map(|&n| local(*tag, "triangle", n))
                .collect::<Result<_, _>>()?;
            let mut k = [given[0], given[1], given[2]];
            k.sort_unstable();
            let Some(&(e, f)) = owner.get(&k) else {
                return Err(MeshError::element(
                    format!("Gmsh element {tag}"),
                    "is a triangle of a physical surface that bounds no tetrahedron",
                ));
            };
            // The owner's face: outward by construction, with its mid-edge nodes.
            let face = mesh.boundary_face(e, f);
            for &p in groups {
                let name = group_name(&names, 2, p);
                mesh.node_sets
                    .entry(name.clone())
                    .or_default()
                    .extend(&face.nodes);
                mesh.face_sets.entry(name).or_default().push(face.clone());
            }
        }
        for dim in [0usize, 1] {
            for (tag, entity, nodes) in &by_dim[dim] {
                for &p in physical
                    .get(&(dim as i32, *entity))
                    .map_or(&[][..], Vec::as_slice)
                {
                    let set = mesh
                        .node_sets
                        .entry(group_name(&names, dim as i32, p))
                        .or_default();
                    for &n in *nodes {
                        set.push(local(*tag, "node set", n)?);
                    }
                }
            }
        }
        for set in mesh.node_sets.values_mut() {
            set.sort_unstable();
            set.dedup();
        }
        for (e, (_, entity, _)) in by_dim[3].iter().enumerate() {
            for &p in physical.get(&(3, *entity)).map_or(&[][..], Vec::as_slice) {
                mesh.element_sets
                    .entry(group_name(&names, 3, p))
                    .or_default()
                    .push(e);
            }
        }
        for set in mesh.element_sets.values_mut() {
            set.dedup();
        }
        Ok(mesh)
    }
}
