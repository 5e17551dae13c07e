// The middle body of the three-body assembly (units mm): a steel block
// 20 x 20 x 10 between the pad (below, z = 10) and the cylinder (above, z = 20).
// Its top corners (-10, -10, 20) and (10, -10, 20) are mesh nodes, for pinning.
// Regenerate: gmsh -3 -setnumber lc 2.5 block.geo -o block_coarse.msh
SetFactory("OpenCASCADE");
DefineConstant[ lc = 2.5 ];
Box(1) = {-10, -10, 10, 20, 20, 10};
Physical Surface("bottom") = Surface In BoundingBox {-11, -11, 9.99, 11, 11, 10.01};
Physical Surface("top") = Surface In BoundingBox {-11, -11, 19.99, 11, 11, 20.01};
Physical Volume("block") = {1};
Mesh.MeshSizeMin = lc;
Mesh.MeshSizeMax = lc;
Mesh.MshFileVersion = 4.1;
