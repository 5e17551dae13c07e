// A curved contact patch test: the square [0, 1.5]^2 x [0, 0.5] cut along the
// cylinder r = 1 (axis z) into a quarter cylinder (outer = 0) and the rest
// (outer = 1), meshed apart in transfinite Hex20 (Quad8 faces): the quarter
// disk as an O-grid (a square n x n, two curved patches n x m), the rest as
// two patches cut along the diagonal, n2 cells along each half of the arc;
// mid-side nodes on the cylinder. x = 0 and y = 0 are symmetry planes, so
// every slave node's support is mirror-symmetric about its planes of the
// mesh or lies on a roller.
// Regenerate (the files of tests/integration/quadratic_patch.rs):
//   gmsh -3 -order 2 -setnumber outer 0 -setnumber n 3 tubes.geo -o tube_inner_3.msh
//   gmsh -3 -order 2 -setnumber outer 1 -setnumber n 3 tubes.geo -o tube_outer_3.msh
//   gmsh -3 -order 2 -setnumber outer 1 -setnumber n 4 tubes.geo -o tube_outer_4.msh
DefineConstant[ outer = 0, n = 3 ];
m = 2;
h = 0.5;
c = Sqrt(0.5);
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {c, c, 0};
Point(4) = {0, 1, 0};
If (outer)
  Point(5) = {1.5, 0, 0};
  Point(6) = {1.5, 1.5, 0};
  Point(7) = {0, 1.5, 0};
  Circle(1) = {2, 1, 3};
  Circle(2) = {3, 1, 4};
  Line(3) = {2, 5};
  Line(4) = {5, 6};
  Line(5) = {6, 3};
  Line(6) = {6, 7};
  Line(7) = {7, 4};
  Curve Loop(1) = {3, 4, 5, -1};
  Curve Loop(2) = {-5, 6, 7, -2};
  Plane Surface(1) = {1};
  Plane Surface(2) = {2};
  Transfinite Curve{1, 2, 4, 6} = n + 1;
  Transfinite Curve{3, 5, 7} = m + 1;
  Transfinite Surface{1, 2};
  Recombine Surface{1, 2};
  a[] = Extrude {0, 0, h} { Surface{1}; Layers{2}; Recombine; };
  b[] = Extrude {0, 0, h} { Surface{2}; Layers{2}; Recombine; };
  Physical Surface("ymin") = {a[2]};
  Physical Surface("xmax") = {a[3]};
  Physical Surface("ymax") = {b[3]};
  Physical Surface("xmin") = {b[4]};
  Physical Surface("curved") = {a[5], b[5]};
  Physical Surface("bottom") = {1, 2};
  Physical Surface("top") = {a[0], b[0]};
  Physical Volume("body") = {a[1], b[1]};
Else
  Point(5) = {0.5, 0, 0};
  Point(6) = {0.5, 0.5, 0};
  Point(7) = {0, 0.5, 0};
  Circle(1) = {2, 1, 3};
  Circle(2) = {3, 1, 4};
  Line(3) = {1, 5};
  Line(4) = {5, 6};
  Line(5) = {6, 7};
  Line(6) = {7, 1};
  Line(7) = {5, 2};
  Line(8) = {3, 6};
  Line(9) = {4, 7};
  Curve Loop(1) = {3, 4, 5, 6};
  Curve Loop(2) = {7, 1, 8, -4};
  Curve Loop(3) = {-8, 2, 9, -5};
  Plane Surface(1) = {1};
  Plane Surface(2) = {2};
  Plane Surface(3) = {3};
  Transfinite Curve{1, 2, 3, 4, 5, 6} = n + 1;
  Transfinite Curve{7, 8, 9} = m + 1;
  Transfinite Surface{1, 2, 3};
  Recombine Surface{1, 2, 3};
  s[] = Extrude {0, 0, h} { Surface{1}; Layers{2}; Recombine; };
  a[] = Extrude {0, 0, h} { Surface{2}; Layers{2}; Recombine; };
  b[] = Extrude {0, 0, h} { Surface{3}; Layers{2}; Recombine; };
  Physical Surface("ymin") = {s[2], a[2]};
  Physical Surface("xmin") = {s[5], b[4]};
  Physical Surface("curved") = {a[3], b[3]};
  Physical Surface("bottom") = {1, 2, 3};
  Physical Surface("top") = {s[0], a[0], b[0]};
  Physical Volume("body") = {s[1], a[1], b[1]};
EndIf

Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Mesh.MshFileVersion = 4.1;
