// A 1 x 1 x 0.5 block of serendipity hexahedra (Hex20, Quad8 faces), a
// transfinite 3 x 3 x 2 grid.
// Regenerate: gmsh -3 -order 2 block_hex20.geo -o block_hex20.msh
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {1, 1, 0};
Point(4) = {0, 1, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 4;
Transfinite Surface{1};
Recombine Surface{1};
out[] = Extrude {0, 0, 0.5} { Surface{1}; Layers{2}; Recombine; };

Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
Physical Surface("ymin") = {out[2]};
Physical Surface("xmin") = {out[5]};
Physical Volume("block") = {out[1]};

Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Mesh.MshFileVersion = 4.1;
