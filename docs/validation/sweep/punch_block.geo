// A hexahedral punch (Hex20: structured, second order incomplete) on a
// tetrahedral block (Tet10), two physical volumes of one file.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 4, 4, 2};
Box(2) = {1.5, 1.5, 2, 1, 1, 1};
e = 1e-6;
MeshSize{ PointsOf{ Volume{1}; } } = 0.5;
Transfinite Curve{ Abs(Boundary{ Boundary{ Volume{2}; } }) } = 5;
Transfinite Surface{ Boundary{ Volume{2}; } };
Recombine Surface{ Boundary{ Volume{2}; } };
Transfinite Volume{2};
Physical Volume("block") = {1};
Physical Volume("punch") = {2};
Physical Surface("block_bottom") = Surface In BoundingBox{-e, -e, -e, 4+e, 4+e, e};
block_faces() = Boundary{ Volume{1}; };
punch_faces() = Boundary{ Volume{2}; };
Physical Surface("block_top") = {};
Physical Surface("punch_bottom") = {};
Physical Surface("punch_top") = {};
For i In {0 : #block_faces() - 1}
  bb() = BoundingBox Surface{ block_faces(i) };
  If (Fabs(bb(2) - 2) < e && Fabs(bb(5) - 2) < e)
    Physical Surface("block_top") += {block_faces(i)};
  EndIf
EndFor
For i In {0 : #punch_faces() - 1}
  bb() = BoundingBox Surface{ punch_faces(i) };
  If (Fabs(bb(2) - 2) < e && Fabs(bb(5) - 2) < e)
    Physical Surface("punch_bottom") += {punch_faces(i)};
  EndIf
  If (Fabs(bb(2) - 3) < e && Fabs(bb(5) - 3) < e)
    Physical Surface("punch_top") += {punch_faces(i)};
  EndIf
EndFor
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Mesh.MshFileVersion = 4.1;
