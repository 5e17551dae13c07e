// 2D: a bracket (20 x 30) on a plate (100 x 10), two physical surfaces of one
// file, second-order triangles (Tri6), meshed apart (non-matching at y = 10);
// a third surface, a block (30 x 10) beside the bracket on the plate.
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 100, 10};
Rectangle(2) = {40, 10, 0, 20, 30};
Rectangle(3) = {70, 10, 0, 30, 10};
e = 1e-6;
MeshSize{ PointsOf{ Surface{1}; } } = 4;
MeshSize{ PointsOf{ Surface{2}; } } = 3;
MeshSize{ PointsOf{ Surface{3}; } } = 2.5;
Physical Surface("plate") = {1};
Physical Surface("bracket") = {2};
Physical Surface("block") = {3};
Physical Curve("plate_bottom") = Curve In BoundingBox{-e, -e, -1, 100+e, e, 1};
Physical Curve("plate_left") = Curve In BoundingBox{-e, -e, -1, e, 10+e, 1};
c1() = Boundary{ Surface{1}; };
c2() = Boundary{ Surface{2}; };
c3() = Boundary{ Surface{3}; };
Physical Curve("plate_top") = {};
Physical Curve("bracket_bottom") = {};
Physical Curve("bracket_top") = {};
Physical Curve("block_bottom") = {};
For i In {0 : #c1() - 1}
  bb() = BoundingBox Curve{ c1(i) };
  If (Fabs(bb(1) - 10) < e && Fabs(bb(4) - 10) < e)
    Physical Curve("plate_top") += {c1(i)};
  EndIf
EndFor
For i In {0 : #c2() - 1}
  bb() = BoundingBox Curve{ c2(i) };
  If (Fabs(bb(1) - 10) < e && Fabs(bb(4) - 10) < e)
    Physical Curve("bracket_bottom") += {c2(i)};
  EndIf
  If (Fabs(bb(1) - 40) < e && Fabs(bb(4) - 40) < e)
    Physical Curve("bracket_top") += {c2(i)};
  EndIf
EndFor
For i In {0 : #c3() - 1}
  bb() = BoundingBox Curve{ c3(i) };
  If (Fabs(bb(1) - 10) < e && Fabs(bb(4) - 10) < e)
    Physical Curve("block_bottom") += {c3(i)};
  EndIf
EndFor
Physical Point("bracket_corner") = Point In BoundingBox{60-e, 40-e, -1, 60+e, 40+e, 1};
Mesh.ElementOrder = 2;
Mesh.MshFileVersion = 4.1;
