//! A Gmsh 4.1 file of two soil layers, written here in ASCII and in binary from one
//! description (so both encode the same mesh): the unit square, "sand" below y = 0.5 and
//! "clay" above, each of four Tri3 triangles, an unnamed physical surface 7 holding both,
//! and the physical curve "bottom" (two Lin2 lines). Included with `#[path]` by the tests
//! that use it.
//!
//! ```text
//!  7-----8-----9   y = 1        physical surfaces: 1 "sand" = surface 1,
//!  |   / |   / |                2 "clay" = surface 2, 7 (unnamed) = surfaces 1 and 2;
//!  | /   | /   |   clay         physical curve 3 "bottom" = curve 1 (lines 1–2, 2–3)
//!  4-----5-----6   y = 0.5
//!  | \   | \   |   sand         element blocks, in file order: sand (tags 21, 22),
//!  |   \ |   \ |                clay (31..34), sand (23, 24), the bottom lines
//!  1-----2-----3   y = 0
//! ```
//!
//! So the triangles are, by index: 0, 1 sand; 2..5 clay; 6, 7 sand.

/// One `$Elements` block: entity dimension and tag, Gmsh element type (1 = Lin2,
/// 2 = Tri3), and (element tag, node tags) per element.
pub struct Block {
    pub dim: i32,
    pub entity: i32,
    pub kind: i32,
    pub elements: Vec<(u64, Vec<u64>)>,
}

/// What the file holds: physical names (dimension, tag, name), curves and surfaces with
/// their physical tags, nodes (tags 1, 2, ... in order) and element blocks.
pub struct Msh {
    pub names: Vec<(i32, i32, &'static str)>,
    pub curves: Vec<(i32, Vec<i32>)>,
    pub surfaces: Vec<(i32, Vec<i32>)>,
    pub nodes: Vec<[f64; 2]>,
    pub blocks: Vec<Block>,
}

/// The two-layer square of the module documentation.
pub fn layers() -> Msh {
    let tri = |tag: u64, n: [u64; 3]| (tag, n.to_vec());
    Msh {
        names: vec![(1, 3, "bottom"), (2, 1, "sand"), (2, 2, "clay")],
        curves: vec![(1, vec![3])],
        surfaces: vec![(1, vec![1, 7]), (2, vec![2, 7])],
        nodes: vec![
            [0.0, 0.0],
            [0.5, 0.0],
            [1.0, 0.0],
            [0.0, 0.5],
            [0.5, 0.5],
            [1.0, 0.5],
            [0.0, 1.0],
            [0.5, 1.0],
            [1.0, 1.0],
        ],
        blocks: vec![
            Block {
                dim: 2,
                entity: 1,
                kind: 2,
                elements: vec![tri(21, [1, 2, 5]), tri(22, [1, 5, 4])],
            },
            Block {
                dim: 2,
                entity: 2,
                kind: 2,
                elements: vec![
                    tri(31, [4, 5, 8]),
                    tri(32, [4, 8, 7]),
                    tri(33, [5, 6, 9]),
                    tri(34, [5, 9, 8]),
                ],
            },
            Block {
                dim: 2,
                entity: 1,
                kind: 2,
                elements: vec![tri(23, [2, 3, 6]), tri(24, [2, 6, 5])],
            },
            Block {
                dim: 1,
                entity: 1,
                kind: 1,
                elements: vec![(1, vec![1, 2]), (2, vec![2, 3])],
            },
        ],
    }
}

const BBOX: [f64; 6] = [0.0, 0.0, 0.0, 1.0, 1.0, 0.0];

impl Msh {
    fn element_tag_range(&self) -> (usize, u64, u64) {
        let tags = self
            .blocks
            .iter()
            .flat_map(|b| b.elements.iter().map(|e| e.0));
        let n = tags.clone().count();
        (n, tags.clone().min().unwrap(), tags.max().unwrap())
    }

    fn physical_names(&self) -> String {
        let mut s = format!("$PhysicalNames\n{}\n", self.names.len());
        for (dim, tag, name) in &self.names {
            s += &format!("{dim} {tag} \"{name}\"\n");
        }
        s + "$EndPhysicalNames\n"
    }

    /// The ASCII file (`4.1 0 8`).
    pub fn ascii(&self) -> String {
        let join = |v: &[i32]| v.iter().map(|t| format!(" {t}")).collect::<String>();
        let bbox = BBOX.map(|v| v.to_string()).join(" ");
        let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
        s += &self.physical_names();
        s += &format!(
            "$Entities\n0 {} {} 0\n",
            self.curves.len(),
            self.surfaces.len()
        );
        for (tag, phys) in self.curves.iter().chain(&self.surfaces) {
            s += &format!("{tag} {bbox} {}{} 0\n", phys.len(), join(phys));
        }
        let n = self.nodes.len();
        s += &format!("$EndEntities\n$Nodes\n1 {n} 1 {n}\n2 1 0 {n}\n");
        for t in 1..=n {
            s += &format!("{t}\n");
        }
        for p in &self.nodes {
            s += &format!("{} {} 0\n", p[0], p[1]);
        }
        let (count, min, max) = self.element_tag_range();
        s += &format!(
            "$EndNodes\n$Elements\n{} {count} {min} {max}\n",
            self.blocks.len()
        );
        for b in &self.blocks {
            s += &format!("{} {} {} {}\n", b.dim, b.entity, b.kind, b.elements.len());
            for (tag, nodes) in &b.elements {
                let nodes: String = nodes.iter().map(|n| format!(" {n}")).collect();
                s += &format!("{tag}{nodes}\n");
            }
        }
        s + "$EndElements\n"
    }

    /// The binary file (`4.1 1 8`, little-endian, 8-byte size_t; `$PhysicalNames` stays
    /// ASCII), field by field as in `gmsh_square::binary_square`.
    pub fn binary(&self) -> Vec<u8> {
        let mut b: Vec<u8> = Vec::new();
        let st = |b: &mut Vec<u8>, v: u64| b.extend_from_slice(&v.to_le_bytes());
        let int = |b: &mut Vec<u8>, v: i32| b.extend_from_slice(&v.to_le_bytes());
        let dbl = |b: &mut Vec<u8>, v: f64| b.extend_from_slice(&v.to_le_bytes());
        b.extend_from_slice(b"$MeshFormat\n4.1 1 8\n");
        int(&mut b, 1);
        b.extend_from_slice(b"\n$EndMeshFormat\n");
        b.extend_from_slice(self.physical_names().as_bytes());
        b.extend_from_slice(b"$Entities\n");
        for n in [0, self.curves.len(), self.surfaces.len(), 0] {
            st(&mut b, n as u64);
        }
        for (tag, phys) in self.curves.iter().chain(&self.surfaces) {
            int(&mut b, *tag);
            for v in BBOX {
                dbl(&mut b, v);
            }
            st(&mut b, phys.len() as u64);
            for &p in phys {
                int(&mut b, p);
            }
            st(&mut b, 0); // no bounding points / curves
        }
        b.extend_from_slice(b"\n$EndEntities\n$Nodes\n");
        let n = self.nodes.len() as u64;
        for v in [1, n, 1, n] {
            st(&mut b, v);
        }
        int(&mut b, 2);
        int(&mut b, 1);
        int(&mut b, 0);
        st(&mut b, n);
        for t in 1..=n {
            st(&mut b, t);
        }
        for p in &self.nodes {
            dbl(&mut b, p[0]);
            dbl(&mut b, p[1]);
            dbl(&mut b, 0.0);
        }
        b.extend_from_slice(b"\n$EndNodes\n$Elements\n");
        let (count, min, max) = self.element_tag_range();
        for v in [self.blocks.len() as u64, count as u64, min, max] {
            st(&mut b, v);
        }
        for block in &self.blocks {
            int(&mut b, block.dim);
            int(&mut b, block.entity);
            int(&mut b, block.kind);
            st(&mut b, block.elements.len() as u64);
            for (tag, nodes) in &block.elements {
                st(&mut b, *tag);
                for &v in nodes {
                    st(&mut b, v);
                }
            }
        }
        b.extend_from_slice(b"\n$EndElements\n");
        b
    }
}
