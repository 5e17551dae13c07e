// The rubber pad of the three-body assembly (units mm): 40 x 40 x 10, its
// bottom (z = 0) clamped, the block standing on the middle of its top (z = 10).
// Elements of size lc under the block, growing to 3 lc at the pad's sides.
// Regenerate: gmsh -3 -setnumber lc 2 pad.geo -o pad_coarse.msh
SetFactory("OpenCASCADE");
DefineConstant[ lc = 2.0 ];
Box(1) = {-20, -20, 0, 40, 40, 10};
Physical Surface("bottom") = Surface In BoundingBox {-21, -21, -0.01, 21, 21, 0.01};
Physical Surface("top") = Surface In BoundingBox {-21, -21, 9.99, 21, 21, 10.01};
Physical Volume("pad") = {1};
Field[1] = Box;
Field[1].VIn = lc;
Field[1].VOut = 3 * lc;
Field[1].XMin = -11; Field[1].XMax = 11;
Field[1].YMin = -11; Field[1].YMax = 11;
Field[1].ZMin = 5; Field[1].ZMax = 11;
Field[1].Thickness = 6;
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MshFileVersion = 4.1;
