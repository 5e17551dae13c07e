// Two boxes that share a face (fragmented: one conforming mesh), Tet10: the
// physical volumes "lower" and "upper" make two bodies that a tie bonds, the
// whole file one body (the monolithic mesh to compare with). The curve
// "edge" lies on the shared face: a node set of both volumes.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 2, 1, 1};
Box(2) = {0, 0, 1, 2, 1, 1};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
e = 1e-6;
MeshSize{ PointsOf{ Volume{:}; } } = 0.34;
Physical Volume("lower") = Volume In BoundingBox{-e, -e, -e, 2+e, 1+e, 1+e};
Physical Volume("upper") = Volume In BoundingBox{-e, -e, 1-e, 2+e, 1+e, 2+e};
Physical Surface("bottom") = Surface In BoundingBox{-e, -e, -e, 2+e, 1+e, e};
Physical Surface("top") = Surface In BoundingBox{-e, -e, 2-e, 2+e, 1+e, 2+e};
Physical Surface("interface") = Surface In BoundingBox{-e, -e, 1-e, 2+e, 1+e, 1+e};
Physical Curve("edge") = Curve In BoundingBox{2-e, -e, 1-e, 2+e, 1+e, 1+e};
Mesh.ElementOrder = 2;
Mesh.MshFileVersion = 4.1;
