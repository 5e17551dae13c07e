// A 1 x 1 x 0.5 block of second-order tetrahedra (Tet10, Tri6 faces).
// Regenerate: gmsh -3 -order 2 block_tet10.geo -o block_tet10.msh
SetFactory("OpenCASCADE");
lc = 0.3;

Box(1) = {0, 0, 0, 1, 1, 0.5};

Physical Surface("bottom") = Surface In BoundingBox {-0.01, -0.01, -0.01, 1.01, 1.01, 0.01};
Physical Surface("top") = Surface In BoundingBox {-0.01, -0.01, 0.49, 1.01, 1.01, 0.51};
Physical Surface("xmin") = Surface In BoundingBox {-0.01, -0.01, -0.01, 0.01, 1.01, 0.51};
Physical Surface("ymin") = Surface In BoundingBox {-0.01, -0.01, -0.01, 1.01, 0.01, 0.51};
Physical Volume("block") = {1};

Mesh.MeshSizeMin = lc;
Mesh.MeshSizeMax = lc;
Mesh.ElementOrder = 2;
Mesh.MshFileVersion = 4.1;
