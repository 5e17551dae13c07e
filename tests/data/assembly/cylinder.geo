// The punch of the three-body assembly (units mm): a steel cylinder, radius 6,
// height 8, axis z at x = xc (default: through the block's centre), standing
// on the block top (z = 20).
// Regenerate: gmsh -3 -setnumber lc 2 cylinder.geo -o cylinder_coarse.msh
SetFactory("OpenCASCADE");
DefineConstant[ lc = 2.0, xc = 0.0 ];
Cylinder(1) = {xc, 0, 20, 0, 0, 8, 6};
Physical Surface("bottom") = Surface In BoundingBox {xc - 7, -7, 19.99, xc + 7, 7, 20.01};
Physical Surface("top") = Surface In BoundingBox {xc - 7, -7, 27.99, xc + 7, 7, 28.01};
Physical Volume("cylinder") = {1};
Mesh.MeshSizeMin = lc;
Mesh.MeshSizeMax = lc;
Mesh.MshFileVersion = 4.1;
