// A 2D pad meshed with second-order quadrangles as Gmsh makes them by default
// with Mesh.SecondOrderIncomplete = 1: Quad8.
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 4, 1};
Mesh.RecombineAll = 1;
Mesh.MeshSizeMax = 0.25;
Physical Surface("pad") = {1};
Physical Curve("bottom") = Curve In BoundingBox{-1e-6, -1e-6, -1, 4+1e-6, 1e-6, 1};
Physical Curve("top") = Curve In BoundingBox{-1e-6, 1-1e-6, -1, 4+1e-6, 1+1e-6, 1};
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Mesh.MshFileVersion = 4.1;
