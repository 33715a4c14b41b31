//! The small Gmsh 4.1 files of the reader tests: a unit square of four nodes in two
//! triangles with named physical groups (drawn in `gmsh_reader.rs`), as P1 and P2.
pub const HEADER: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
3
0 3 \"corner\"
1 1 \"bottom\"
2 2 \"domain\"
$EndPhysicalNames
$Entities
4 4 1 0
1 0 0 0 0
2 1 0 0 1 3
3 1 1 0 0
4 0 1 0 0
1 0 0 0 1 0 0 1 1 2 1 -2
2 1 0 0 1 1 0 0 2 2 -3
3 0 1 0 1 1 0 0 2 3 -4
4 0 0 0 0 1 0 0 2 4 -1
1 0 0 0 1 1 0 1 2 4 1 2 3 4
$EndEntities
";

pub fn p1_file(triangles: &str) -> String {
    format!(
        "{HEADER}$Nodes
1 5 1 5
2 1 0 5
1
2
3
4
5
0 0 0
1 0 0
1 1 0
0 1 0
0.5 0.5 0
$EndNodes
$Elements
3 6 1 6
0 2 15 1
6 2
1 1 1 1
1 1 2
2 1 2 4
{triangles}$EndElements
"
    )
}

pub const P1_TRIANGLES: &str = "2 1 2 5
3 2 3 5
4 3 4 5
5 4 1 5
";

pub fn p2_file() -> String {
    format!(
        "{HEADER}$Nodes
1 9 1 9
2 1 0 9
1
2
3
4
5
6
7
8
9
0 0 0
1 0 0
1 1 0
0 1 0
0.5 0 0
1 0.5 0
0.5 1 0
0 0.5 0
0.5 0.5 0
$EndNodes
$Elements
2 3 1 3
1 1 8 1
1 1 2 5
2 1 9 2
2 1 2 3 5 6 9
3 1 3 4 9 7 8
$EndElements
"
    )
}

/// The same P1 square in binary (little-endian, 8-byte size_t), built field by field
/// following the Gmsh 4.1 binary layout; `$PhysicalNames` stays ASCII.
pub fn binary_square() -> Vec<u8> {
    let mut b: Vec<u8> = Vec::new();
    let st = |b: &mut Vec<u8>, v: u64| b.extend_from_slice(&v.to_le_bytes());
    let int = |b: &mut Vec<u8>, v: i32| b.extend_from_slice(&v.to_le_bytes());
    let dbl = |b: &mut Vec<u8>, v: f64| b.extend_from_slice(&v.to_le_bytes());
    b.extend_from_slice(b"$MeshFormat\n4.1 1 8\n");
    int(&mut b, 1);
    b.extend_from_slice(
        b"\n$EndMeshFormat\n$PhysicalNames\n1\n1 1 \"bottom\"\n$EndPhysicalNames\n",
    );
    b.extend_from_slice(b"$Entities\n");
    for n in [0u64, 1, 1, 0] {
        st(&mut b, n);
    }
    // curve 1: bbox, one physical tag (1), two bounding points
    int(&mut b, 1);
    for v in [0.0, 0.0, 0.0, 1.0, 0.0, 0.0] {
        dbl(&mut b, v);
    }
    st(&mut b, 1);
    int(&mut b, 1);
    st(&mut b, 2);
    int(&mut b, 1);
    int(&mut b, -2);
    // surface 1: bbox, no physical tag, one bounding curve
    int(&mut b, 1);
    for v in [0.0, 0.0, 0.0, 1.0, 1.0, 0.0] {
        dbl(&mut b, v);
    }
    st(&mut b, 0);
    st(&mut b, 1);
    int(&mut b, 1);
    b.extend_from_slice(b"\n$EndEntities\n$Nodes\n");
    for v in [1u64, 5, 1, 5] {
        st(&mut b, v);
    }
    int(&mut b, 2);
    int(&mut b, 1);
    int(&mut b, 0);
    st(&mut b, 5);
    for t in 1..=5u64 {
        st(&mut b, t);
    }
    for p in [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]] {
        dbl(&mut b, p[0]);
        dbl(&mut b, p[1]);
        dbl(&mut b, 0.0);
    }
    b.extend_from_slice(b"\n$EndNodes\n$Elements\n");
    for v in [2u64, 5, 1, 5] {
        st(&mut b, v);
    }
    int(&mut b, 1);
    int(&mut b, 1);
    int(&mut b, 1); // Lin2
    st(&mut b, 1);
    for v in [1u64, 1, 2] {
        st(&mut b, v);
    }
    int(&mut b, 2);
    int(&mut b, 1);
    int(&mut b, 2); // Tri3
    st(&mut b, 4);
    for tri in [[2u64, 1, 2, 5], [3, 2, 3, 5], [4, 3, 4, 5], [5, 4, 1, 5]] {
        for v in tri {
            st(&mut b, v);
        }
    }
    b.extend_from_slice(b"\n$EndElements\n");

    b
}
