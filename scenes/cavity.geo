// A quarter of a square block [0, 10] x [0, 10] m with a circular cavity of radius 1 m
// at the origin (symmetry on x = 0 and y = 0), P2 triangles, refined at the cavity.
// Regenerate: gmsh -2 -order 2 -format msh41 cavity.geo -o cavity.msh
a = 1.0;
L = 10.0;
h_in = 0.12;
h_out = 1.5;
Point(1) = {0, 0, 0, h_in};
Point(2) = {a, 0, 0, h_in};
Point(3) = {L, 0, 0, h_out};
Point(4) = {L, L, 0, h_out};
Point(5) = {0, L, 0, h_out};
Point(6) = {0, a, 0, h_in};
Line(1) = {2, 3};
Line(2) = {3, 4};
Line(3) = {4, 5};
Line(4) = {5, 6};
Circle(5) = {6, 1, 2};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Physical Curve("bottom") = {1};
Physical Curve("outer") = {2, 3};
Physical Curve("left") = {4};
Physical Curve("cavity") = {5};
Physical Surface("soil") = {1};
