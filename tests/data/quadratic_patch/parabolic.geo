// A curved contact patch test whose interface two non-matching quadratic
// meshes represent exactly: the box [0, 1]^2 x [0, 1] cut along the parabolic
// cylinder z = 0.5 + c x^2 (axis y). This file meshes one of the two straight
// blocks, the lower (z in [0, 0.5]) or the upper (z in [0.5, 1]), in n x n x 2
// transfinite Hex20 (hex = 1) or Tet10 (hex = 0, each prism of the extruded
// grid split into tetrahedra); parabolic.py then moves every node along z,
// z' = z + c x^2 z / 0.5 (lower) or z + c x^2 (1 - z) / 0.5 (upper), which
// keeps x and y: the faces of the cut keep an affine in-plane map with their
// mid-side nodes centred, and every node of the cut, mid-side ones included,
// lands on the parabola, so the Quad8 and Tri6 faces of either side
// interpolate the same surface exactly.
// Regenerate (the files of tests/integration/quadratic_patch.rs):
//   for b in "0 3 1 hex20" "1 3 1 hex20" "1 4 1 hex20" "0 3 0 tet10" "1 3 0 tet10" "1 4 0 tet10"; do
//     set -- $b; s=$([ $1 = 1 ] && echo upper || echo lower)
//     gmsh -3 -order 2 -setnumber upper $1 -setnumber n $2 -setnumber hex $3 parabolic.geo -o /tmp/straight.msh
//     python3 parabolic.py /tmp/straight.msh parabolic_${s}_$4_$2.msh $s
//   done
DefineConstant[ upper = 0, n = 3, hex = 1 ];
z0 = 0.5 * upper;
Point(1) = {0, 0, z0};
Point(2) = {1, 0, z0};
Point(3) = {1, 1, z0};
Point(4) = {0, 1, z0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = n + 1;
Transfinite Surface{1};
If (hex)
  Recombine Surface{1};
  out[] = Extrude {0, 0, 0.5} { Surface{1}; Layers{2}; Recombine; };
Else
  out[] = Extrude {0, 0, 0.5} { Surface{1}; Layers{2}; };
EndIf

Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
Physical Surface("ymin") = {out[2]};
Physical Surface("xmax") = {out[3]};
Physical Surface("ymax") = {out[4]};
Physical Surface("xmin") = {out[5]};
Physical Volume("block") = {out[1]};

Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Mesh.MshFileVersion = 4.1;
