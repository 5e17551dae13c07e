// A curved contact patch test: a 1 x 1 block cut along a cylinder of radius
// 2 (axis along y through x = 0.5, z = -1.5; the interface rises from
// z = 0.4365 at x = 0, 1 to 0.5 at x = 0.5) into a lower body (upper = 0,
// from z = 0 to the cylinder) and an upper one (upper = 1, from the
// cylinder to z = 1), meshed apart: second-order meshes whose mid-side
// nodes lie on the cylinder.
// hex = 1: transfinite Hex20 (Quad8 faces), n x 2 cells in the xz-section,
// n layers along y; hex = 0: Tet10 (Tri6 faces) of size 1 / n.
// Regenerate (the files of tests/integration/quadratic_patch.rs):
//   gmsh -3 -order 2 -setnumber upper 0 -setnumber hex 1 -setnumber n 4 curved.geo -o curved_lower_hex20_4.msh
//   gmsh -3 -order 2 -setnumber upper 1 -setnumber hex 1 -setnumber n 4 curved.geo -o curved_upper_hex20_4.msh
//   gmsh -3 -order 2 -setnumber upper 1 -setnumber hex 1 -setnumber n 5 curved.geo -o curved_upper_hex20_5.msh
//   gmsh -3 -order 2 -setnumber upper 0 -setnumber hex 0 -setnumber n 4 curved.geo -o curved_lower_tet10_4.msh
//   gmsh -3 -order 2 -setnumber upper 1 -setnumber hex 0 -setnumber n 5 curved.geo -o curved_upper_tet10_5.msh
DefineConstant[ upper = 0, hex = 1, n = 4 ];
lc = 1.0 / n;
ze = -1.5 + Sqrt(3.75);
Point(1) = {0, 0, 0, lc};
Point(2) = {1, 0, 0, lc};
Point(3) = {1, 0, ze, lc};
Point(4) = {0, 0, ze, lc};
Point(5) = {0.5, 0, -1.5, lc};
Point(6) = {1, 0, 1, lc};
Point(7) = {0, 0, 1, lc};
If (upper)
  Circle(1) = {4, 5, 3};
  Line(2) = {3, 6};
  Line(3) = {6, 7};
  Line(4) = {7, 4};
Else
  Line(1) = {1, 2};
  Line(2) = {2, 3};
  Circle(3) = {3, 5, 4};
  Line(4) = {4, 1};
EndIf
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
If (hex)
  Transfinite Curve{1, 3} = n + 1;
  Transfinite Curve{2, 4} = 3;
  Transfinite Surface{1};
  Recombine Surface{1};
  out[] = Extrude {0, 1, 0} { Surface{1}; Layers{n}; Recombine; };
Else
  out[] = Extrude {0, 1, 0} { Surface{1}; };
EndIf

Physical Surface("ymin") = {1};
Physical Surface("ymax") = {out[0]};
Physical Surface("xmax") = {out[3]};
Physical Surface("xmin") = {out[5]};
If (upper)
  Physical Surface("curved") = {out[2]};
  Physical Surface("top") = {out[4]};
Else
  Physical Surface("bottom") = {out[2]};
  Physical Surface("curved") = {out[4]};
EndIf
Physical Volume("body") = {out[1]};

Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Mesh.MshFileVersion = 4.1;
