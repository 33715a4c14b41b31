//! Gmsh `.msh` 4.1 reader (ASCII or binary), through `mshio`.
//!
//! - `Tri3` elements make a P1 mesh, `Tri6` a P2 mesh (mixing them is an error); other
//!   surface or volume elements are rejected.
//! - Physical groups of dimension 0 and 1 become node sets, and those of dimension 1 also
//!   edge sets (`Lin2` / `Lin3`); physical groups of dimension 2 (physical surfaces) become
//!   element sets (the indices of their triangles). All are named from `$PhysicalNames`
//!   (`physical_<dim>_<tag>` if unnamed). Every triangle belongs to the mesh, whether in a
//!   physical surface or not; a triangle in several physical surfaces is in each set.
//! - Only nodes used by triangles are kept, numbered by increasing Gmsh tag.
//! - The mesh must lie in the plane z = 0 (up to rounding) and its triangles must be
//!   counter-clockwise; errors name the Gmsh element tag.
//!
//! `mshio` ignores `$PhysicalNames`, so that section (always ASCII, also in binary files)
//! is read here. `mshio` discards node tags when they are contiguous; they are then taken
//! as consecutive in file order, which is how Gmsh writes them.
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use mshio::{ElementType, MshFile};

use super::{BoundaryEdge, Mesh};
use crate::element::ElementOrder;
use crate::error::MeshError;

pub(crate) type Names = HashMap<(i32, i32), String>;

/// Largest coordinate magnitude (m): areas and mass terms (lengths squared, times a density)
/// stay far from overflow.
pub(crate) const MAX_COORDINATE: f64 = 1e100;

impl Mesh {
    /// Reads a Gmsh 4.1 file (ASCII or binary); see the module documentation.
    pub fn from_msh(path: &Path) -> Result<Mesh, MeshError> {
        let bytes = std::fs::read(path).map_err(|e| MeshError::Io {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        Self::from_msh_bytes(&bytes)
    }

    /// Same as [`from_msh`](Self::from_msh) for the file's content.
    pub fn from_msh_bytes(bytes: &[u8]) -> Result<Mesh, MeshError> {
        let (file, names) = read(bytes)?;
        build(&file, &names)
    }
}

/// The parsed file and its `$PhysicalNames`, after the checks `mshio` does not make (the
/// 2D and 3D readers share them).
pub(crate) fn read(bytes: &[u8]) -> Result<(MshFile<u64, i32, f64>, Names), MeshError> {
    check_header(bytes)?;
    check_ascii_node_tags(bytes)?;
    let names = physical_names(bytes)?;
    let file = parse(bytes)?;
    Ok((file, names))
}

/// The physical tags of each entity, by `(dimension, entity tag)`.
pub(crate) fn entity_groups(file: &MshFile<u64, i32, f64>) -> HashMap<(i32, i32), Vec<i32>> {
    let mut physical: HashMap<(i32, i32), Vec<i32>> = HashMap::new();
    if let Some(ent) = &file.data.entities {
        for p in &ent.points {
            physical.insert((0, p.tag), p.physical_tags.clone());
        }
        for c in &ent.curves {
            physical.insert((1, c.tag), c.physical_tags.clone());
        }
        for s in &ent.surfaces {
            physical.insert((2, s.tag), s.physical_tags.clone());
        }
        for v in &ent.volumes {
            physical.insert((3, v.tag), v.physical_tags.clone());
        }
    }
    physical
}

/// A physical group's name from `$PhysicalNames`, or `physical_<dim>_<tag>`.
pub(crate) fn group_name(names: &Names, dim: i32, p: i32) -> String {
    names
        .get(&(dim, p))
        .cloned()
        .unwrap_or_else(|| format!("physical_{dim}_{p}"))
}

/// Node coordinates by Gmsh tag.
pub(crate) fn node_coordinates(
    file: &MshFile<u64, i32, f64>,
) -> Result<HashMap<u64, [f64; 3]>, MeshError> {
    let mut coords: HashMap<u64, [f64; 3]> = HashMap::new();
    if let Some(nodes) = &file.data.nodes {
        let mut next = nodes.min_node_tag;
        for block in &nodes.node_blocks {
            match &block.node_tags {
                Some(tags) => {
                    // mshio keeps one index per tag: fewer tags than nodes is a repeat.
                    if tags.len() != block.nodes.len() {
                        return Err(MeshError::msh(format!(
                            "a $Nodes block of entity {} lists {} nodes under {} distinct \
                             tags: a node tag is repeated",
                            block.entity_tag,
                            block.nodes.len(),
                            tags.len()
                        )));
                    }
                    for (&tag, &i) in tags {
                        let n = block.nodes.get(i).ok_or_else(|| {
                            MeshError::msh(format!("node tag {tag} has no coordinates"))
                        })?;
                        insert_node(&mut coords, tag, [n.x, n.y, n.z])?;
                    }
                }
                None => {
                    for n in &block.nodes {
                        insert_node(&mut coords, next, [n.x, n.y, n.z])?;
                        next += 1;
                    }
                }
            }
        }
    }
    Ok(coords)
}

/// Checks `$MeshFormat` before handing the bytes to `mshio`, whose header parser panics on
/// some malformed headers.
fn check_header(bytes: &[u8]) -> Result<(), MeshError> {
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(256)]);
    let mut lines = text.trim_start().lines();
    if lines.next().map(str::trim) != Some("$MeshFormat") {
        return Err(MeshError::msh("does not start with $MeshFormat"));
    }
    let fields: Vec<&str> = lines.next().unwrap_or("").split_whitespace().collect();
    match fields.as_slice() {
        [version, file_type, size] => {
            if version.parse::<f64>().ok() != Some(4.1) {
                return Err(MeshError::msh(format!(
                    "format version {version} is not supported (only 4.1)"
                )));
            }
            if !matches!(*file_type, "0" | "1") {
                return Err(MeshError::msh(format!(
                    "file type {file_type} is neither 0 (ASCII) nor 1 (binary)"
                )));
            }
            if !matches!(*size, "4" | "8") {
                return Err(MeshError::msh(format!(
                    "data size {size} is not supported (4 or 8)"
                )));
            }
            Ok(())
        }
        _ => Err(MeshError::msh(
            "the $MeshFormat line must be `version file-type data-size`",
        )),
    }
}

/// Finds `needle` at the start of a line.
fn find_line(bytes: &[u8], needle: &[u8]) -> Option<usize> {
    (0..bytes.len().saturating_sub(needle.len() - 1))
        .find(|&i| bytes[i..].starts_with(needle) && (i == 0 || bytes[i - 1] == b'\n'))
}

/// Reads `$PhysicalNames`: `count`, then `dim tag "name"` per line. Only the part of the
/// file before the first binary-capable section is searched.
fn physical_names(bytes: &[u8]) -> Result<Names, MeshError> {
    let head_end = [b"$Entities".as_slice(), b"$Nodes", b"$Elements"]
        .iter()
        .filter_map(|s| find_line(bytes, s))
        .min()
        .unwrap_or(bytes.len());
    let head = &bytes[..head_end];
    let mut names = Names::new();
    let Some(start) = find_line(head, b"$PhysicalNames") else {
        return Ok(names);
    };
    // The end after the start: an `$EndPhysicalNames` line before `$PhysicalNames` is no end.
    let body_start = start + b"$PhysicalNames".len();
    let end = find_line(&head[body_start..], b"$EndPhysicalNames")
        .map(|e| body_start + e)
        .ok_or_else(|| MeshError::msh("$PhysicalNames has no $EndPhysicalNames after it"))?;
    let body = std::str::from_utf8(&head[body_start..end])
        .map_err(|_| MeshError::msh("$PhysicalNames is not valid UTF-8"))?;
    let mut lines = body.lines().map(str::trim).filter(|l| !l.is_empty());
    let count: usize = lines
        .next()
        .and_then(|l| l.parse().ok())
        .ok_or_else(|| MeshError::msh("$PhysicalNames must start with the number of names"))?;
    for line in lines.by_ref().take(count) {
        let bad = || MeshError::msh(format!("$PhysicalNames: cannot read line `{line}`"));
        let mut it = line.splitn(3, char::is_whitespace);
        let dim: i32 = it.next().and_then(|s| s.parse().ok()).ok_or_else(bad)?;
        let tag: i32 = it
            .next()
            .and_then(|s| s.trim().parse().ok())
            .ok_or_else(bad)?;
        let name = it.next().map(str::trim).ok_or_else(bad)?;
        let name = name
            .strip_prefix('"')
            .and_then(|n| n.strip_suffix('"'))
            .ok_or_else(bad)?;
        names.insert((dim, tag), name.to_string());
    }
    if names.len() != count || lines.next().is_some() {
        return Err(MeshError::msh(format!(
            "$PhysicalNames announces {count} names but holds a different number"
        )));
    }
    Ok(names)
}

/// `mshio::parse_msh_bytes` with its error turned into a short message (kind, section,
/// byte offset and line) and any panic on malformed input turned into an error.
fn parse(bytes: &[u8]) -> Result<MshFile<u64, i32, f64>, MeshError> {
    let result = catch_unwind(AssertUnwindSafe(|| {
        mshio::parse_msh_bytes(bytes).map_err(|e| {
            // The innermost entry locates the failure; `mshio`'s own kinds and contexts
            // (nom's internal ones filtered out) say what was being read.
            let offset = e.backtrace.first().map_or(0, |(at, _)| {
                (at.as_ptr() as usize).saturating_sub(bytes.as_ptr() as usize)
            });
            let offset = offset.min(bytes.len());
            let line = bytes[..offset].iter().filter(|&&b| b == b'\n').count() + 1;
            let trace = e.filtered_backtrace();
            let mut what: Vec<String> = trace
                .iter()
                .rev()
                .map(|(_, k)| k.context().map_or_else(|| k.to_string(), str::to_string))
                .collect();
            what.dedup();
            let place = if offset == bytes.len() {
                "unexpected end of file".to_string()
            } else {
                format!("byte {offset}, line {line}")
            };
            if what.is_empty() {
                MeshError::msh(format!("malformed or truncated content ({place})"))
            } else {
                MeshError::msh(format!("cannot parse {} ({place})", what.join(" > ")))
            }
        })
    }));
    match result {
        Ok(r) => r,
        Err(panic) => {
            let what = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Err(MeshError::msh(format!("malformed file ({what})")))
        }
    }
}

fn build(file: &MshFile<u64, i32, f64>, names: &Names) -> Result<Mesh, MeshError> {
    let physical = entity_groups(file);
    let coords = node_coordinates(file)?;

    // Elements by kind.
    let mut order: Option<(ElementOrder, u64)> = None;
    // (element tag, entity tag, nodes)
    let mut triangles: Vec<(u64, i32, &[u64])> = Vec::new();
    let mut lines: Vec<(u64, i32, &[u64])> = Vec::new();
    let mut points: Vec<(u64, i32, &[u64])> = Vec::new();
    if let Some(elements) = &file.data.elements {
        for block in &elements.element_blocks {
            for el in &block.elements {
                let tag = el.element_tag;
                let label = || format!("Gmsh element {tag}");
                let tri_order = match block.element_type {
                    ElementType::Tri3 => Some(ElementOrder::P1),
                    ElementType::Tri6 => Some(ElementOrder::P2),
                    ElementType::Lin2 | ElementType::Lin3 => {
                        lines.push((tag, block.entity_tag, &el.nodes));
                        None
                    }
                    ElementType::Pnt => {
                        points.push((tag, block.entity_tag, &el.nodes));
                        None
                    }
                    other => {
                        return Err(MeshError::element(
                            label(),
                            format!("has type {other:?}; only Tri3 / Tri6 (with Lin2 / Lin3, Pnt) are supported"),
                        ))
                    }
                };
                if let Some(o) = tri_order {
                    match order {
                        None => order = Some((o, tag)),
                        Some((first, first_tag)) if first != o => {
                            return Err(MeshError::element(
                                label(),
                                format!("is {o:?} but Gmsh element {first_tag} is {first:?}: mixed element orders"),
                            ))
                        }
                        _ => {}
                    }
                    triangles.push((tag, block.entity_tag, &el.nodes));
                }
            }
        }
    }
    let Some((order, _)) = order else {
        return Err(MeshError::msh("the file holds no Tri3 or Tri6 elements"));
    };

    // Keep the nodes of triangles, numbered by increasing tag.
    let mut used = BTreeSet::new();
    for (tag, _, nodes) in &triangles {
        for n in *nodes {
            if !coords.contains_key(n) {
                return Err(MeshError::element(
                    format!("Gmsh element {tag}"),
                    format!("refers to node {n}, which $Nodes does not define"),
                ));
            }
            used.insert(*n);
        }
    }
    let index: HashMap<u64, usize> = used.iter().enumerate().map(|(i, &t)| (t, i)).collect();
    let xyz: Vec<[f64; 3]> = used.iter().map(|t| coords[t]).collect();
    let extent = xyz
        .iter()
        .flat_map(|p| [p[0].abs(), p[1].abs()])
        .fold(0.0, f64::max);
    if let Some((i, p)) = xyz
        .iter()
        .enumerate()
        .find(|(_, p)| p[2].is_nan() || p[2].abs() > 1e-9 * extent)
    {
        return Err(MeshError::msh(format!(
            "node {} has z = {}: a plane-strain mesh must lie in the plane z = 0",
            used.iter().nth(i).copied().unwrap_or(0),
            p[2]
        )));
    }
    if let Some((i, p)) = xyz
        .iter()
        .enumerate()
        .find(|(_, p)| !(p[0].abs() <= MAX_COORDINATE && p[1].abs() <= MAX_COORDINATE))
    {
        return Err(MeshError::msh(format!(
            "node {} has (x, y) = ({:e}, {:e}): coordinates must be finite and within \
             ±{MAX_COORDINATE:e} m (the element arithmetic squares lengths)",
            used.iter().nth(i).copied().unwrap_or(0),
            p[0],
            p[1]
        )));
    }
    let local = |tag: u64, what: &str, n: u64| {
        index.get(&n).copied().ok_or_else(|| {
            MeshError::element(
                format!("Gmsh element {tag}"),
                format!("({what}) refers to node {n}, which belongs to no triangle"),
            )
        })
    };

    let mut node_sets: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    let mut edge_sets: BTreeMap<String, Vec<BoundaryEdge>> = BTreeMap::new();
    let group_name = |dim: i32, p: i32| group_name(names, dim, p);
    for (tag, entity, nodes) in &lines {
        let groups = physical.get(&(1, *entity)).map_or(&[][..], Vec::as_slice);
        if groups.is_empty() {
            continue;
        }
        if nodes.len() != order.nodes_per_edge() {
            return Err(MeshError::element(
                format!("Gmsh element {tag}"),
                format!(
                    "is a line of {} nodes in a {order:?} mesh (needs {})",
                    nodes.len(),
                    order.nodes_per_edge()
                ),
            ));
        }
        let edge = BoundaryEdge {
            nodes: nodes
                .iter()
                .map(|&n| local(*tag, "line", n))
                .collect::<Result<_, _>>()?,
        };
        for &p in groups {
            let name = group_name(1, p);
            node_sets
                .entry(name.clone())
                .or_default()
                .extend(&edge.nodes);
            edge_sets.entry(name).or_default().push(edge.clone());
        }
    }
    for (tag, entity, nodes) in &points {
        for &p in physical.get(&(0, *entity)).map_or(&[][..], Vec::as_slice) {
            let set = node_sets.entry(group_name(0, p)).or_default();
            for &n in *nodes {
                set.push(local(*tag, "point", n)?);
            }
        }
    }
    for set in node_sets.values_mut() {
        set.sort_unstable();
        set.dedup();
    }
    // Triangles are indexed in file order, so each set comes out sorted; a physical tag
    // listed twice by one surface would repeat a triangle, hence the dedup.
    let mut element_sets: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (e, (_, entity, _)) in triangles.iter().enumerate() {
        for &p in physical.get(&(2, *entity)).map_or(&[][..], Vec::as_slice) {
            element_sets.entry(group_name(2, p)).or_default().push(e);
        }
    }
    for set in element_sets.values_mut() {
        set.dedup();
    }

    let tags: Vec<u64> = triangles.iter().map(|t| t.0).collect();
    let mesh = Mesh {
        order,
        nodes: xyz.iter().map(|p| [p[0], p[1]]).collect(),
        triangles: triangles
            .iter()
            .map(|(tag, _, nodes)| nodes.iter().map(|&n| local(*tag, "triangle", n)).collect())
            .collect::<Result<_, _>>()?,
        node_sets,
        edge_sets,
        element_sets,
    };
    mesh.validate_labelled(&|e| format!("Gmsh element {}", tags[e]))?;
    Ok(mesh)
}

/// A node's coordinates under its tag; a tag given twice is an error naming it.
fn insert_node(
    coords: &mut HashMap<u64, [f64; 3]>,
    tag: u64,
    x: [f64; 3],
) -> Result<(), MeshError> {
    match coords.insert(tag, x) {
        Some(_) => Err(MeshError::msh(format!("node tag {tag} is given twice"))),
        None => Ok(()),
    }
}

/// mshio drops the node tags of a `$Nodes` section whose header says they are contiguous,
/// renumbering the nodes by position: a repeated tag there would pass silently. The tags
/// of an ASCII file are read here first; a repeat is an error naming the tag.
fn check_ascii_node_tags(bytes: &[u8]) -> Result<(), MeshError> {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return Ok(()); // binary: mshio keeps the tags of sparse sections, checked in `build`
    };
    let Some(start) = text.find("$Nodes") else {
        return Ok(());
    };
    let Some(len) = text[start..].find("$EndNodes") else {
        return Ok(());
    };
    let mut tokens = text[start + "$Nodes".len()..start + len].split_whitespace();
    let mut int = || tokens.next().and_then(|t| t.parse::<u64>().ok());
    let (Some(blocks), Some(_), Some(_), Some(_)) = (int(), int(), int(), int()) else {
        return Ok(()); // malformed: mshio reports it
    };
    let mut seen = std::collections::HashSet::new();
    for _ in 0..blocks {
        let (Some(_), Some(_), Some(parametric), Some(count)) = (int(), int(), int(), int()) else {
            return Ok(());
        };
        if parametric != 0 {
            return Ok(()); // parametric coordinates: not read here
        }
        for _ in 0..count {
            let Some(tag) = int() else { return Ok(()) };
            if !seen.insert(tag) {
                return Err(MeshError::msh(format!("node tag {tag} is given twice")));
            }
        }
        for _ in 0..3 * count {
            int(); // coordinates
        }
    }
    Ok(())
}
