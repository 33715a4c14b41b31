//! Fuzzing of the Gmsh `.msh` readers (`[mesh.gmsh]` of a scene): mutated meshes (the
//! shipped scene meshes, small ASCII P1 and P2 squares and a binary one; P1 and P2
//! tetrahedral blocks for the 3D reader) and generated rectangles. The reader returns a mesh or an error and never panics; a mesh it returns is
//! consistent (node counts per triangle, indices in range, finite coordinates, positive
//! areas, sets in range) and assembles without panicking.
//! `TALUS_FUZZ_CASES` / `TALUS_FUZZ_SCALE` raise the case count (`cargo xtask fuzz`);
//! `docs/scenes.md`, 'Fuzzing'.
use std::panic::{catch_unwind, AssertUnwindSafe};

use proptest::prelude::*;
use talus_fem::{Assembly, DofMap, ElementOrder, Mesh, TetrahedralMesh};

#[path = "../../ssn/tests/common/mutations.rs"]
mod mutations;
use mutations::{apply, cases, fuzz, mutated, Outcome};

// The small files of `gmsh_reader.rs` (see the drawing there).
use crate::common;
use common::gmsh_block::{block, to_msh};
use common::gmsh_square::{binary_square, p1_file, p2_file, P1_TRIANGLES};

fn seeds() -> Vec<Vec<u8>> {
    let scenes = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/");
    let mut seeds = vec![
        p1_file(P1_TRIANGLES).into_bytes(),
        p2_file().into_bytes(),
        binary_square(),
    ];
    for name in ["slope.msh", "cavity.msh", "lame_cylinder.msh"] {
        seeds.push(std::fs::read(format!("{scenes}{name}")).expect("shipped mesh"));
    }
    seeds
}

/// Checks what the reader promises of a mesh it returned, then assembles it.
fn consistent(mesh: &Mesh) -> Result<(), String> {
    let n = mesh.nodes.len();
    if let Some(p) = mesh
        .nodes
        .iter()
        .find(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Err(format!("node at {p:?}"));
    }
    let per = match mesh.order {
        ElementOrder::P1 => 3,
        ElementOrder::P2 => 6,
    };
    if mesh.triangles.is_empty() {
        return Err("no triangles".into());
    }
    for (e, t) in mesh.triangles.iter().enumerate() {
        if t.len() != per || t.iter().any(|&i| i >= n) {
            return Err(format!(
                "triangle {e} = {t:?} with {n} nodes, {:?}",
                mesh.order
            ));
        }
        let [a, b, c] = [mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]]];
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
        if area.is_nan() || area <= 0.0 {
            return Err(format!("triangle {e} has area {area}"));
        }
    }
    for (name, set) in &mesh.node_sets {
        if set.iter().any(|&i| i >= n) || set.windows(2).any(|w| w[0] >= w[1]) {
            return Err(format!("node set {name} = {set:?} with {n} nodes"));
        }
    }
    for (name, edges) in &mesh.edge_sets {
        if let Some(e) = edges.iter().find(|e| {
            e.nodes.len() != if per == 3 { 2 } else { 3 } || e.nodes.iter().any(|&i| i >= n)
        }) {
            return Err(format!("edge set {name} holds {e:?} with {n} nodes"));
        }
    }
    // What a scene does next: number the dofs and assemble B, M and the Gauss points.
    let assembled = catch_unwind(AssertUnwindSafe(|| {
        let dofs = DofMap::new(n, &[]).map_err(|e| e.to_string())?;
        Assembly::new(mesh, &dofs, 1.0)
            .map(|_| ())
            .map_err(|e| e.to_string())
    }))
    .map_err(|_| "the assembly panicked on a mesh the reader accepted".to_string())?;
    if let Err(e) = assembled {
        return Err(format!(
            "the assembly refused a mesh the reader accepted: {e}"
        ));
    }
    Ok(())
}

fn read(bytes: &[u8]) -> Result<Outcome, String> {
    match Mesh::from_msh_bytes(bytes) {
        Ok(mesh) => consistent(&mesh).map(|()| Outcome::Read),
        Err(e) => Ok(Outcome::Refused(e.to_string())),
    }
}

#[test]
fn mutated_meshes_are_read_or_refused_never_panic() {
    let seeds = seeds();
    fuzz(
        "gmsh .msh (mutated files)",
        cases(10_000),
        mutated(seeds.len()),
        |(seed, mutations)| read(&apply(&seeds[*seed], mutations)),
    );
}

// ------------------------------------------------------------------ tetrahedra

/// What `TetrahedralMesh::from_msh_bytes` promises of a mesh it returned.
fn consistent_3d(mesh: &TetrahedralMesh) -> Result<(), String> {
    let n = mesh.nodes.len();
    if let Some(p) = mesh.nodes.iter().find(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(format!("node at {p:?}"));
    }
    if mesh.tetrahedra.is_empty() {
        return Err("no tetrahedra".into());
    }
    // counts, indices and det J > 0, as the reader checked them
    mesh.check_elements().map_err(|e| e.to_string())?;
    let per_face = match mesh.order {
        ElementOrder::P1 => 3,
        ElementOrder::P2 => 6,
    };
    for (name, faces) in &mesh.face_sets {
        if let Some(f) = faces
            .iter()
            .find(|f| f.nodes.len() != per_face || f.nodes.iter().any(|&i| i >= n))
        {
            return Err(format!("face set {name} holds {f:?} with {n} nodes"));
        }
    }
    for (name, set) in &mesh.node_sets {
        if set.iter().any(|&i| i >= n) || set.windows(2).any(|w| w[0] >= w[1]) {
            return Err(format!("node set {name} = {set:?} with {n} nodes"));
        }
    }
    for (name, set) in &mesh.element_sets {
        if set.iter().any(|&e| e >= mesh.tetrahedra.len()) {
            return Err(format!("element set {name} = {set:?}"));
        }
    }
    Ok(())
}

#[test]
fn mutated_tetrahedral_meshes_are_read_or_refused_never_panic() {
    let seeds: Vec<Vec<u8>> = [ElementOrder::P1, ElementOrder::P2]
        .into_iter()
        .map(|order| {
            let mesh = block(order);
            to_msh(&mesh, &mesh.tetrahedra).into_bytes()
        })
        .collect();
    fuzz(
        "gmsh .msh tetrahedra (mutated files)",
        cases(2_000),
        mutated(seeds.len()),
        |(seed, mutations)| match TetrahedralMesh::from_msh_bytes(&apply(&seeds[*seed], mutations))
        {
            Ok(mesh) => consistent_3d(&mesh).map(|()| Outcome::Read),
            Err(e) => Ok(Outcome::Refused(e.to_string())),
        },
    );
}

// ------------------------------------------------------------------ generated rectangles

/// An `nx` x `ny` rectangle of P1 triangles from (x0, y0), cells `dx` x `dy`, its node
/// tags `first + stride * k` (stride 1: the contiguous tags mshio renumbers; else sparse
/// tags it keeps), its bottom edge the physical group "bottom".
#[derive(Debug, Clone)]
struct Rectangle {
    nx: usize,
    ny: usize,
    origin: [f64; 2],
    cell: [f64; 2],
    first: u64,
    stride: u64,
}

fn rectangle() -> impl Strategy<Value = Rectangle> {
    (
        1usize..6,
        1usize..6,
        [-1e3f64..1e3, -1e3f64..1e3],
        [1e-3f64..1e3, 1e-3f64..1e3],
        1u64..1000,
        1u64..4,
    )
        .prop_map(|(nx, ny, origin, cell, first, stride)| Rectangle {
            nx,
            ny,
            origin,
            cell,
            first,
            stride,
        })
}

impl Rectangle {
    fn tag(&self, i: usize, j: usize) -> u64 {
        self.first + self.stride * (j * (self.nx + 1) + i) as u64
    }

    fn x(&self, i: usize, j: usize) -> [f64; 2] {
        [
            self.origin[0] + i as f64 * self.cell[0],
            self.origin[1] + j as f64 * self.cell[1],
        ]
    }

    fn text(&self) -> String {
        let (nx, ny) = (self.nx, self.ny);
        let nodes = (nx + 1) * (ny + 1);
        let (lo, hi) = (self.tag(0, 0), self.tag(nx, ny));
        let mut t = String::from(
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n1 1 \"bottom\"\n\
             $EndPhysicalNames\n$Entities\n0 1 1 0\n",
        );
        t += "1 0 0 0 1 0 0 1 1 0\n1 0 0 0 1 1 0 0 1 1\n$EndEntities\n$Nodes\n";
        t += &format!("1 {nodes} {lo} {hi}\n2 1 0 {nodes}\n");
        for j in 0..=ny {
            for i in 0..=nx {
                t += &format!("{}\n", self.tag(i, j));
            }
        }
        for j in 0..=ny {
            for i in 0..=nx {
                let [x, y] = self.x(i, j);
                t += &format!("{x:e} {y:e} 0\n");
            }
        }
        let tris = 2 * nx * ny;
        t += &format!("$EndNodes\n$Elements\n2 {} 1 {}\n", nx + tris, nx + tris);
        t += &format!("1 1 1 {nx}\n");
        for i in 0..nx {
            t += &format!("{} {} {}\n", i + 1, self.tag(i, 0), self.tag(i + 1, 0));
        }
        t += &format!("2 1 2 {tris}\n");
        let mut e = nx;
        for j in 0..ny {
            for i in 0..nx {
                let (a, b, c, d) = (
                    self.tag(i, j),
                    self.tag(i + 1, j),
                    self.tag(i + 1, j + 1),
                    self.tag(i, j + 1),
                );
                t += &format!("{} {a} {b} {c}\n{} {a} {c} {d}\n", e + 1, e + 2);
                e += 2;
            }
        }
        t + "$EndElements\n"
    }
}

/// Generated rectangles read back with their nodes (in tag order), triangles, area and
/// bottom edge.
#[test]
fn generated_rectangles_read_back() {
    fuzz("gmsh .msh (generated)", cases(5_000), rectangle(), |r| {
        let text = r.text();
        let mesh = Mesh::from_msh_bytes(text.as_bytes())
            .map_err(|e| format!("refused a valid mesh: {e}\n{text}"))?;
        consistent(&mesh)?;
        let (nx, ny) = (r.nx, r.ny);
        if mesh.nodes.len() != (nx + 1) * (ny + 1) || mesh.triangles.len() != 2 * nx * ny {
            return Err(format!(
                "{} nodes, {} triangles",
                mesh.nodes.len(),
                mesh.triangles.len()
            ));
        }
        for j in 0..=ny {
            for i in 0..=nx {
                let k = j * (nx + 1) + i;
                if mesh.nodes[k] != r.x(i, j) {
                    return Err(format!(
                        "node {k} at {:?}, want {:?}",
                        mesh.nodes[k],
                        r.x(i, j)
                    ));
                }
            }
        }
        let area: f64 = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = [mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]]];
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
            })
            .sum();
        let want = nx as f64 * r.cell[0] * ny as f64 * r.cell[1];
        // Coordinates up to 6e3 in magnitude: the area to a few ulps of x * y per triangle.
        if (area - want).abs() > 1e-9 * want.max(1.0) * (nx * ny) as f64 {
            return Err(format!("area {area}, want {want}"));
        }
        let bottom: Vec<usize> = (0..=nx).collect();
        if mesh.node_sets.get("bottom") != Some(&bottom) || mesh.edge_sets["bottom"].len() != nx {
            return Err(format!("bottom set {:?}", mesh.node_sets.get("bottom")));
        }
        Ok(Outcome::Read)
    });
}

#[test]
fn mutated_generated_meshes_never_panic() {
    fuzz(
        "gmsh .msh (generated, mutated)",
        cases(5_000),
        (
            rectangle(),
            proptest::collection::vec(mutations::mutation(), 1..=mutations::MAX_MUTATIONS),
        ),
        |(r, m)| read(&apply(r.text().as_bytes(), m)),
    );
}

/// Every field of the binary square overwritten, at every byte offset, by sizes that would
/// make a reader allocate without bound (2⁶⁴ − 1, 2⁶², 2⁴⁰, 2³¹) or read a negative
/// count: refused, never a panic nor an abort.
#[test]
fn binary_sizes_overwritten_at_every_offset_never_panic() {
    let seed = binary_square();
    let mut cases = 0;
    for at in 0..seed.len() {
        for v in [u64::MAX, 1 << 62, 1 << 40, 1 << 31] {
            for width in [8usize, 4] {
                if at + width > seed.len() {
                    continue;
                }
                let mut b = seed.clone();
                b[at..at + width].copy_from_slice(&v.to_le_bytes()[..width]);
                let outcome = catch_unwind(AssertUnwindSafe(|| read(&b)));
                match outcome {
                    Ok(Ok(_)) => cases += 1,
                    Ok(Err(e)) => panic!("offset {at}, {v:#x} ({width} bytes): {e}"),
                    Err(_) => panic!("offset {at}, {v:#x} ({width} bytes): the reader panicked"),
                }
            }
        }
    }
    println!("fuzz gmsh .msh (binary sizes): {cases} cases, 0 panics");
}
