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
