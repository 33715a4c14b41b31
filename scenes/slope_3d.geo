// The homogeneous 3D slope of Sysala et al. (slope_stability, `slope_stability_3D_homo_SSR.m`;
// Sysala, Béreš, Bérešová, Haslinger, Kružík, Luber, arXiv:2312.12170): a 45° slope of
// height 10 m on a 10 m thick base, x ∈ [−30, 10] (crest behind x = −15, toe at x = −5),
// y ∈ [0, 20] (up), z ∈ [0, 5]. Unstructured tetrahedra of size h (finer, h/2, along
// the slope face where the slip surface runs), P2.
// Regenerate: gmsh -3 -order 2 -format msh41 -setnumber h 2.0 slope_3d.geo -o slope_3d.msh
//             gmsh -3 -order 2 -format msh41 -setnumber h 1.25 slope_3d.geo -o slope_3d_fine.msh
DefineConstant[ h = {2.0, Name "element size"} ];
Point(1) = {-30, 0, 0, h};
Point(2) = {10, 0, 0, h};
Point(3) = {10, 10, 0, h};
Point(4) = {-5, 10, 0, h / 2};
Point(5) = {-15, 20, 0, h / 2};
Point(6) = {-30, 20, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
out[] = Extrude {0, 0, 5} { Surface{1}; };
// out[0]: the surface at z = 5, out[1]: the volume, out[2 + k]: the side over line k + 1.
Physical Surface("bottom") = {out[2]};
Physical Surface("right") = {out[3]};
Physical Surface("toe") = {out[4]};
Physical Surface("face") = {out[5]};
Physical Surface("crest") = {out[6]};
Physical Surface("left") = {out[7]};
Physical Surface("back") = {1};
Physical Surface("front") = {out[0]};
Physical Volume("soil") = {out[1]};
