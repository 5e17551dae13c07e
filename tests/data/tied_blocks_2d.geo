// Two blocks in one Gmsh file, meshed apart (non-matching at y = 1): the
// lower [0,1]x[0,1] (size 0.25), the upper [0,1]x[1,2] (size 0.17).
Point(1) = {0, 0, 0, 0.25};
Point(2) = {1, 0, 0, 0.25};
Point(3) = {1, 1, 0, 0.25};
Point(4) = {0, 1, 0, 0.25};
Point(5) = {0, 1, 0, 0.17};
Point(6) = {1, 1, 0, 0.17};
Point(7) = {1, 2, 0, 0.17};
Point(8) = {0, 2, 0, 0.17};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Physical Surface("lower") = {1};
Physical Surface("upper") = {2};
Physical Curve("lower_bottom") = {1};
Physical Curve("lower_top") = {3};
Physical Curve("upper_bottom") = {5};
Physical Curve("upper_top") = {7};
Physical Point("origin") = {1};
Physical Point("top_corners") = {7, 8};
Mesh.MshFileVersion = 4.1;
