// A bracket (20 x 20 x 30 mm) on a plate (100 x 60 x 10 mm), two physical
// volumes of one file, second-order tetrahedra (Tet10); each volume meshed on
// its own (the bracket's bottom and the plate's top do not share nodes).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 100, 60, 10};
Box(2) = {40, 20, 10, 20, 20, 30};
e = 1e-6;
MeshSize{ PointsOf{ Volume{1}; } } = 10;
MeshSize{ PointsOf{ Volume{2}; } } = 6;
Physical Volume("plate") = {1};
Physical Volume("bracket") = {2};
Physical Surface("plate_bottom") = Surface In BoundingBox{-e, -e, -e, 100+e, 60+e, e};
plate_faces() = Boundary{ Volume{1}; };
bracket_faces() = Boundary{ Volume{2}; };
Physical Surface("plate_top") = {};
Physical Surface("bracket_bottom") = {};
Physical Surface("bracket_top") = {};
For i In {0 : #plate_faces() - 1}
  bb() = BoundingBox Surface{ plate_faces(i) };
  If (Fabs(bb(2) - 10) < e && Fabs(bb(5) - 10) < e)
    Physical Surface("plate_top") += {plate_faces(i)};
  EndIf
EndFor
For i In {0 : #bracket_faces() - 1}
  bb() = BoundingBox Surface{ bracket_faces(i) };
  If (Fabs(bb(2) - 10) < e && Fabs(bb(5) - 10) < e)
    Physical Surface("bracket_bottom") += {bracket_faces(i)};
  EndIf
  If (Fabs(bb(2) - 40) < e && Fabs(bb(5) - 40) < e)
    Physical Surface("bracket_top") += {bracket_faces(i)};
  EndIf
EndFor
// the corner point of the bracket's top (a point load on a node)
Physical Point("bracket_corner") = Point In BoundingBox{60-e, 40-e, 40-e, 60+e, 40+e, 40+e};
// the plate's corner nodes (an empty group below is a separate file)
Physical Point("plate_corner") = Point In BoundingBox{-e, -e, -e, e, e, e};
Mesh.ElementOrder = 2;
Mesh.MshFileVersion = 4.1;
