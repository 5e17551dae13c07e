// A 1 x 1 x 0.5 block meshed with tetrahedra, for
// `mesh = { file = "block3d.msh" }` in a 3D scene.
// Regenerate: gmsh -3 block3d.geo -o block3d.msh
SetFactory("OpenCASCADE");
lc = 0.1;

Box(1) = {0, 0, 0, 1, 1, 0.5};

Physical Surface("bottom") = Surface In BoundingBox {-0.01, -0.01, -0.01, 1.01, 1.01, 0.01};
Physical Surface("top") = Surface In BoundingBox {-0.01, -0.01, 0.49, 1.01, 1.01, 0.51};
Physical Surface("xmin") = Surface In BoundingBox {-0.01, -0.01, -0.01, 0.01, 1.01, 0.51};
Physical Surface("xmax") = Surface In BoundingBox {0.99, -0.01, -0.01, 1.01, 1.01, 0.51};
Physical Surface("ymin") = Surface In BoundingBox {-0.01, -0.01, -0.01, 1.01, 0.01, 0.51};
Physical Surface("ymax") = Surface In BoundingBox {-0.01, 0.99, -0.01, 1.01, 1.01, 0.51};
Physical Volume("block") = {1};

Mesh.MeshSizeMin = lc;
Mesh.MeshSizeMax = lc;
Mesh.MshFileVersion = 4.1;
