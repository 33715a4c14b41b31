//! The ground of a scene: each element's material from `[[region]]` boxes, the mesh's
//! Gmsh physical surfaces and the materials' `regions` (`docs/scenes.md`, 'Regions and
//! materials'). Every element is claimed by exactly one material.
use std::collections::BTreeMap;

use talus_bipotential::Material;
use talus_fem::ElementMesh;

use crate::scene::{check, Materials, SceneDocument, SceneError, SceneSpec, SceneVector};

/// The scene's materials, checked, and each element's index into them.
pub struct Ground {
    pub materials: Vec<Material>,
    pub element_material: Vec<usize>,
    /// The named regions and their elements (stages switch them off and on).
    pub regions: BTreeMap<String, Vec<usize>>,
}

/// What the ground reads from a mesh of either dimension: its elements and their
/// vertices, and its named element sets (Gmsh physical surfaces, 3D: volumes).
pub trait GroundMesh: ElementMesh {
    fn element_sets(&self) -> &BTreeMap<String, Vec<usize>>;
}

impl GroundMesh for talus_fem::Mesh {
    fn element_sets(&self) -> &BTreeMap<String, Vec<usize>> {
        &self.element_sets
    }
}

impl GroundMesh for talus_fem::TetrahedralMesh {
    fn element_sets(&self) -> &BTreeMap<String, Vec<usize>> {
        &self.element_sets
    }
}

/// The centroid of element `e`'s vertices (m): its first `V::DIM + 1` nodes (triangle,
/// tetrahedron), summed in node order and divided once (2D: as before, bit for bit).
fn centroid<V: SceneVector>(mesh: &impl GroundMesh, e: usize) -> V {
    let element = &mesh.elements()[e];
    let nodes = mesh.node_positions();
    let vertices = V::DIM + 1;
    let mut c = V::default();
    for (k, x) in c.as_mut().iter_mut().enumerate() {
        let sum = (element.iter().take(vertices))
            .map(|&n| nodes[n].as_ref()[k])
            .reduce(|a, b| a + b)
            .unwrap_or(0.0);
        *x = sum / vertices as f64;
    }
    c
}

/// `(x, y)` or `(x, y, z)` to 6 decimals, for messages.
fn coordinates<V: SceneVector>(c: V) -> String {
    let parts: Vec<String> = c.as_ref().iter().map(|v| format!("{v:.6}")).collect();
    format!("({})", parts.join(", "))
}

/// The named regions: the mesh's element sets (Gmsh physical surfaces), then the scene's
/// `[[region]]` boxes.
fn regions<V: SceneVector>(
    scene: &SceneDocument<SceneSpec<V>>,
    mesh: &impl GroundMesh,
) -> Result<BTreeMap<String, Vec<usize>>, SceneError> {
    let mut regions = mesh.element_sets().clone();
    for (k, r) in scene.spec.region.iter().enumerate() {
        let [lo, hi] = r.corners;
        let (lo, hi) = (lo.as_ref(), hi.as_ref());
        let ordered = (0..V::DIM).all(|i| lo[i] < hi[i]);
        if !(lo.iter().chain(hi).all(|v| v.is_finite()) && ordered) {
            let (shape, order) = match V::DIM {
                2 => ("[[x0, y0], [x1, y1]]", "x0 < x1 and y0 < y1"),
                _ => (
                    "[[x0, y0, z0], [x1, y1, z1]]",
                    "x0 < x1, y0 < y1 and z0 < z1",
                ),
            };
            return Err(scene.error(
                &format!("region[{k}].box"),
                format!("{:?} must be finite with {order} ({shape}, m)", r.corners),
            ));
        }
        if regions.contains_key(&r.name) {
            return Err(scene.error(
                &format!("region[{k}].name"),
                format!(
                    "\"{}\" is already a region (an earlier [[region]] or a physical surface \
                     of the mesh)",
                    r.name
                ),
            ));
        }
        let inside: Vec<usize> = (0..mesh.elements().len())
            .filter(|&e| {
                let c: V = centroid(mesh, e);
                (0..V::DIM).all(|i| (lo[i]..=hi[i]).contains(&c.as_ref()[i]))
            })
            .collect();
        if inside.is_empty() {
            return Err(scene.error(
                &format!("region[{k}].box"),
                format!("{:?} holds no element centroid", r.corners),
            ));
        }
        regions.insert(r.name.clone(), inside);
    }
    Ok(regions)
}

/// The elements of the region `name`, or an error at `field` listing the regions.
pub(super) fn region<'a>(
    scene: &impl crate::scene::Locate,
    regions: &'a BTreeMap<String, Vec<usize>>,
    field: &str,
    name: &str,
) -> Result<&'a Vec<usize>, SceneError> {
    regions.get(name).ok_or_else(|| {
        let known: Vec<&str> = regions.keys().map(String::as_str).collect();
        scene.error(
            field,
            format!(
                "\"{name}\" is no region of the scene (regions: {})",
                if known.is_empty() {
                    "none".into()
                } else {
                    known.join(", ")
                }
            ),
        )
    })
}

/// The checked materials and the material of every element.
pub fn ground<V: SceneVector>(
    scene: &SceneDocument<SceneSpec<V>>,
    mesh: &impl GroundMesh,
) -> Result<Ground, SceneError> {
    let spec = &scene.spec;
    let all = spec.material.all();
    let mut materials = Vec::with_capacity(all.len());
    for (k, m) in all.iter().enumerate() {
        materials.push(check::material(scene, &spec.material.field(k), m)?);
    }
    let regions = regions(scene, mesh)?;
    let n = mesh.elements().len();
    // One material without regions fills the mesh.
    if let Materials::One(m) = &spec.material {
        if m.regions.is_empty() {
            return Ok(Ground {
                materials,
                element_material: vec![0; n],
                regions,
            });
        }
    }
    let mut names = BTreeMap::new();
    let mut claimed: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (k, m) in all.iter().enumerate() {
        let field = spec.material.field(k);
        let name = match (&m.name, &spec.material) {
            (Some(name), _) => name.clone(),
            (None, Materials::Many(_)) => {
                return Err(scene.error(
                    &format!("{field}.name"),
                    "is required in a [[material]] list (errors and outputs name it)",
                ))
            }
            (None, Materials::One(_)) => "material".into(),
        };
        if let Some(first) = names.insert(name.clone(), k) {
            return Err(scene.error(
                &format!("{field}.name"),
                format!("\"{name}\" is also the name of material[{first}]"),
            ));
        }
        if m.regions.is_empty() {
            return Err(scene.error(
                &format!("{field}.regions"),
                "names no region: give regions = [\"...\"] (a [[region]] or a physical \
                 surface of the mesh)",
            ));
        }
        for (j, r) in m.regions.iter().enumerate() {
            let elements = region(scene, &regions, &format!("{field}.regions[{j}]"), r)?;
            for &e in elements {
                if !claimed[e].contains(&k) {
                    claimed[e].push(k);
                }
            }
        }
    }
    let label = |k: usize| match &all[k].name {
        Some(name) => format!("{} (\"{name}\")", spec.material.field(k)),
        None => spec.material.field(k),
    };
    let mut element_material = Vec::with_capacity(n);
    for (e, owners) in claimed.iter().enumerate() {
        match owners.as_slice() {
            [k] => element_material.push(*k),
            [] => {
                let c = coordinates::<V>(centroid(mesh, e));
                return Err(scene.error(
                    "material",
                    format!(
                        "the element with centroid {c} m is claimed by no material: add its \
                         region to a material's regions"
                    ),
                ));
            }
            [a, b, ..] => {
                let c = coordinates::<V>(centroid(mesh, e));
                return Err(scene.error(
                    &format!("{}.regions", spec.material.field(*b)),
                    format!(
                        "the element with centroid {c} m is claimed by {} and by {}: regions \
                         of two materials overlap",
                        label(*a),
                        label(*b)
                    ),
                ));
            }
        }
    }
    Ok(Ground {
        materials,
        element_material,
        regions,
    })
}
