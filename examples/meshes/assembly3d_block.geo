// The steel block of examples/assembly3d.toml: 20 x 20 x 10 mm, tetrahedra.
// Regenerate: gmsh -3 assembly3d_block.geo -o assembly3d_block.msh
SetFactory("OpenCASCADE");
lc = 2.5;
Box(1) = {-10, -10, 10, 20, 20, 10};
Physical Surface("bottom") = Surface In BoundingBox {-10.1, -10.1, 9.9, 10.1, 10.1, 10.1};
Physical Surface("top") = Surface In BoundingBox {-10.1, -10.1, 19.9, 10.1, 10.1, 20.1};
Physical Volume("block") = {1};
Mesh.MeshSizeMin = lc;
Mesh.MeshSizeMax = lc;
Mesh.MshFileVersion = 4.1;
