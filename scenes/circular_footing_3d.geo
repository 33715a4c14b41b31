// The meridian section of a rigid circular footing, radius R = 0.5 m, on a cylinder of
// soil of radius L = 1.5 m and depth H = 1.5 m: x = r ≥ 0, y vertical (ground at y = 0),
// z = 0 (docs/axisymmetry.md). Structured triangles graded toward the footing's edge
// (r = R, y = 0). Two uses:
// - the axisymmetric run meshes it in 2D (scenes/circular_footing_axi.msh):
//     gmsh -2 -order 2 -format msh41 circular_footing_3d.geo -o circular_footing_axi.msh
// - the 3D run revolves the same triangles a quarter turn about y into P2 tetrahedra
//   (scenes/circular_footing_3d.py, which writes scenes/circular_footing_3d.msh): Gmsh's
//   own `Extrude {Rotate …} {Layers …}` cannot split the prisms that meet the axis
//   ("Unable to subdivide extruded mesh"), so the script sweeps them itself.
// Physical groups (2D): curves footing (y = 0, r ≤ R), surface (y = 0, r ≥ R), base
// (y = -H), outer (r = L), axis (r = 0); surface soil.
// The scenes' mesh: 8, 10, 12 cells, ratio √1.15 (docs/3d.md, 'The circular footing
// against its axisymmetric run', has the others: -setnumber nf 4 -setnumber no 5 …).
DefineConstant[ nf = {8, Name "cells along the footing's radius"},
                no = {10, Name "cells from the footing's edge to r = L"},
                ny = {12, Name "cells in depth"},
                g = {1.15^(1/2), Name "grading ratio away from the footing's edge"} ];
R = 0.5; L = 1.5; H = 1.5;
Point(1) = {0, 0, 0};
Point(2) = {R, 0, 0};
Point(3) = {L, 0, 0};
Point(4) = {L, -H, 0};
Point(5) = {R, -H, 0};
Point(6) = {0, -H, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Line(7) = {2, 5};
Curve Loop(1) = {-6, -5, -7, -1};  // counter-clockwise: Talus refuses inverted triangles
Plane Surface(1) = {1};
Curve Loop(2) = {7, -4, -3, -2};
Plane Surface(2) = {2};
// Cells shrink by 1/g toward the footing's edge, in r from both sides and in y upward.
Transfinite Curve{1} = nf + 1 Using Progression 1 / g;
Transfinite Curve{5} = nf + 1 Using Progression g;
Transfinite Curve{2} = no + 1 Using Progression g;
Transfinite Curve{4} = no + 1 Using Progression 1 / g;
Transfinite Curve{7, 3} = ny + 1 Using Progression 1 / g;
Transfinite Curve{6} = ny + 1 Using Progression g;
Transfinite Surface{1} Alternate;
Transfinite Surface{2} Alternate;
Physical Curve("footing") = {1};
Physical Curve("surface") = {2};
Physical Curve("base") = {4, 5};
Physical Curve("outer") = {3};
Physical Curve("axis") = {6};
Physical Surface("soil") = {1, 2};
