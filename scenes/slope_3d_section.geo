// Griffiths & Lane (1999), example 1: a homogeneous 2:1 slope of height H = 10 m on a rough
// rigid base at the level of its toe (depth factor D = 1). The crest runs 2H = 20 m behind
// the top of the slope, far enough that the toe mechanism never reaches the left side.
// P2 triangles, finer along the slope where the slip surface runs. This is the section of
// `slope.geo` at twice its element size, which crates/talus/tests/slope_extruded_3d.rs
// runs in 2D (`slope.toml`) and extruded (`slope_extruded.toml`) to compare their factors
// of safety on matched meshes in a test's time.
// Regenerate: gmsh -2 -order 2 -format msh41 slope_3d_section.geo -o slope_3d_section.msh
H = 10.0;
crest = 20.0;      // x of the top of the slope
toe = crest + 2 * H;
h_fine = 1.6;
h_coarse = 3.2;
Point(1) = {0, 0, 0, h_coarse};
Point(2) = {toe, 0, 0, h_fine};
Point(3) = {crest, H, 0, h_fine};
Point(4) = {0, H, 0, h_coarse};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("base") = {1};
Physical Curve("face") = {2};
Physical Curve("crest") = {3};
Physical Curve("left") = {4};
Physical Surface("soil") = {1};
