// A quarter of a thick-walled cylinder, inner radius a = 1 m, outer radius b = 2 m
// (symmetry on x = 0 and y = 0), P2 triangles with curved (quadratic) arcs.
// Regenerate: gmsh -2 -order 2 -format msh41 lame_cylinder.geo -o lame_cylinder.msh
a = 1.0;
b = 2.0;
lc = 0.1;
Point(1) = {0, 0, 0, lc};
Point(2) = {a, 0, 0, lc};
Point(3) = {b, 0, 0, lc};
Point(4) = {0, b, 0, lc};
Point(5) = {0, a, 0, lc};
Line(1) = {2, 3};
Circle(2) = {3, 1, 4};
Line(3) = {4, 5};
Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("bottom") = {1};
Physical Curve("outer") = {2};
Physical Curve("left") = {3};
Physical Curve("inner") = {4};
Physical Surface("wall") = {1};
