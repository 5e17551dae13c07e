// A 2 x 1 block in the plane, meshed with quadrilaterals (unstructured,
// recombined), for `mesh = { file = "block2d.msh" }` in a 2D scene.
// Regenerate: gmsh -2 block2d.geo -o block2d.msh
lc = 0.1;

Point(1) = {0, 0, 0, lc};
Point(2) = {2, 0, 0, lc};
Point(3) = {2, 1, 0, lc};
Point(4) = {0, 1, 0, lc};

Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Recombine Surface {1};

Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
Physical Surface("block") = {1};

Mesh.MshFileVersion = 4.1;
