// The upper block of a flat contact patch test, 1 x 1 x 0.5 at z = 0.5 (on
// tests/data/quadratic/block_*.msh, the lower one, 3 x 3 x 2 Hex20 or Tet10
// of size 0.3): non-matching second-order meshes.
// hex = 1: a transfinite 4 x 4 x 2 grid of Hex20 (Quad8 faces);
// hex = 0: Tet10 (Tri6 faces) of size 0.22.
// Regenerate: gmsh -3 -order 2 -setnumber hex 1 block_upper.geo -o block_upper_hex20.msh
//             gmsh -3 -order 2 -setnumber hex 0 block_upper.geo -o block_upper_tet10.msh
DefineConstant[ hex = 1 ];
lc = 0.22;
Point(1) = {0, 0, 0.5, lc};
Point(2) = {1, 0, 0.5, lc};
Point(3) = {1, 1, 0.5, lc};
Point(4) = {0, 1, 0.5, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
If (hex)
  Transfinite Curve{1, 2, 3, 4} = 5;
  Transfinite Surface{1};
  Recombine Surface{1};
  out[] = Extrude {0, 0, 0.5} { Surface{1}; Layers{2}; Recombine; };
Else
  out[] = Extrude {0, 0, 0.5} { Surface{1}; };
EndIf

Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
Physical Surface("ymin") = {out[2]};
Physical Surface("xmin") = {out[5]};
Physical Volume("block") = {out[1]};

Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Mesh.MshFileVersion = 4.1;
