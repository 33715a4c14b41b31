//! The ground of a scene: each element's material from `[[region]]` boxes, the mesh's
//! Gmsh physical surfaces and the materials' `regions` (`docs/scenes.md`, 'Regions and
//! materials'). Every element is claimed by exactly one material.
use std::collections::BTreeMap;

use talus_bipotential::Material;
use talus_fem::Mesh;

use crate::scene::{check, Materials, Scene, SceneError};

/// The scene's materials, checked, and each element's index into them.
pub struct Ground {
    pub materials: Vec<Material>,
    pub element_material: Vec<usize>,
    /// The named regions and their elements (stages switch them off and on).
    pub regions: BTreeMap<String, Vec<usize>>,
}

/// The centroid of element `e`'s vertices (m).
fn centroid(mesh: &Mesh, e: usize) -> [f64; 2] {
    let t = &mesh.triangles[e];
    let [a, b, c] = [mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]]];
    [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0]
}

/// The named regions: the mesh's element sets (Gmsh physical surfaces), then the scene's
/// `[[region]]` boxes.
fn regions(scene: &Scene, mesh: &Mesh) -> Result<BTreeMap<String, Vec<usize>>, SceneError> {
    let mut regions = mesh.element_sets.clone();
    for (k, r) in scene.spec.region.iter().enumerate() {
        let [[x0, y0], [x1, y1]] = r.corners;
        if !(r.corners.iter().flatten().all(|v| v.is_finite()) && x0 < x1 && y0 < y1) {
            return Err(scene.error(
                &format!("region[{k}].box"),
                format!(
                    "{:?} must be finite with x0 < x1 and y0 < y1 ([[x0, y0], [x1, y1]], m)",
                    r.corners
                ),
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
        let inside: Vec<usize> = (0..mesh.triangles.len())
            .filter(|&e| {
                let c = centroid(mesh, e);
                (x0..=x1).contains(&c[0]) && (y0..=y1).contains(&c[1])
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
    scene: &Scene,
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
pub fn ground(scene: &Scene, mesh: &Mesh) -> Result<Ground, SceneError> {
    let spec = &scene.spec;
    let all = spec.material.all();
    let mut materials = Vec::with_capacity(all.len());
    for (k, m) in all.iter().enumerate() {
        materials.push(check::material(scene, &spec.material.field(k), m)?);
    }
    let regions = regions(scene, mesh)?;
    let n = mesh.triangles.len();
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
                let c = centroid(mesh, e);
                return Err(scene.error(
                    "material",
                    format!(
                        "the element with centroid ({:.6}, {:.6}) m is claimed by no material: \
                         add its region to a material's regions",
                        c[0], c[1]
                    ),
                ));
            }
            [a, b, ..] => {
                let c = centroid(mesh, e);
                return Err(scene.error(
                    &format!("{}.regions", spec.material.field(*b)),
                    format!(
                        "the element with centroid ({:.6}, {:.6}) m is claimed by {} and by {}: \
                         regions of two materials overlap",
                        c[0],
                        c[1],
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
