// The steel cylinder ("bolt head") of examples/assembly3d.toml: radius 6 mm,
// height 8 mm, on the block's top at the origin, tetrahedra.
// Regenerate: gmsh -3 assembly3d_cylinder.geo -o assembly3d_cylinder.msh
SetFactory("OpenCASCADE");
lc = 2;
Cylinder(1) = {0, 0, 20, 0, 0, 8, 6};
Physical Surface("bottom") = Surface In BoundingBox {-6.1, -6.1, 19.9, 6.1, 6.1, 20.1};
Physical Surface("top") = Surface In BoundingBox {-6.1, -6.1, 27.9, 6.1, 6.1, 28.1};
Physical Volume("cylinder") = {1};
Mesh.MeshSizeMin = lc;
Mesh.MeshSizeMax = lc;
Mesh.MshFileVersion = 4.1;
