// The rubber pad of examples/assembly3d.toml: 40 x 40 x 10 mm, tetrahedra.
// Regenerate: gmsh -3 assembly3d_pad.geo -o assembly3d_pad.msh
SetFactory("OpenCASCADE");
lc = 3.5;
Box(1) = {-20, -20, 0, 40, 40, 10};
Physical Surface("bottom") = Surface In BoundingBox {-20.1, -20.1, -0.1, 20.1, 20.1, 0.1};
Physical Surface("top") = Surface In BoundingBox {-20.1, -20.1, 9.9, 20.1, 20.1, 10.1};
Physical Volume("pad") = {1};
Mesh.MeshSizeMin = lc;
Mesh.MeshSizeMax = lc;
Mesh.MshFileVersion = 4.1;
