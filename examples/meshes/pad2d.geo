// A 2 x 0.5 pad lying on top of block2d.geo's block (y from 1 to 1.5),
// meshed with triangles of another size: its bottom does not match the
// block's top. For `mesh = { file = "pad2d.msh" }` in a 2D scene.
// Regenerate: gmsh -2 pad2d.geo -o pad2d.msh
lc = 0.07;

Point(1) = {0, 1, 0, lc};
Point(2) = {2, 1, 0, lc};
Point(3) = {2, 1.5, 0, lc};
Point(4) = {0, 1.5, 0, lc};

Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
Physical Surface("pad") = {1};

Mesh.MshFileVersion = 4.1;
