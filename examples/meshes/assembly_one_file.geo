// Three bodies in one Gmsh file: a base, a pad bonded on it (non-matching
// meshes: separate volumes, each meshed on its own) and a slider pressed on
// the pad. Physical volumes name the bodies; physical surfaces their faces;
// the physical curve "pull" is the slider's edge that a force pulls.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 2, 2, 1};
Box(2) = {0, 0, 1, 2, 2, 0.5};
Box(3) = {0.5, 0.5, 1.5, 1, 1, 0.5};
e = 1e-6;
MeshSize{ PointsOf{ Volume{1}; } } = 0.5;
MeshSize{ PointsOf{ Volume{2}; } } = 0.34;
MeshSize{ PointsOf{ Volume{3}; } } = 0.3;
Physical Volume("base") = {1};
Physical Volume("pad") = {2};
Physical Volume("slider") = {3};
Physical Surface("base_bottom") = Surface In BoundingBox{-e, -e, -e, 2+e, 2+e, e};
// faces found volume by volume: the base's top and the pad's bottom both lie
// at z = 1 (the volumes are separate, so each has its own face)
pad_faces() = Boundary{ Volume{2}; };
slider_faces() = Boundary{ Volume{3}; };
base_faces() = Boundary{ Volume{1}; };
Physical Surface("base_top") = {};
Physical Surface("pad_bottom") = {};
Physical Surface("pad_top") = {};
Physical Surface("slider_bottom") = {};
Physical Surface("slider_top") = {};
For i In {0 : #base_faces() - 1}
  bb() = BoundingBox Surface{ base_faces(i) };
  If (Fabs(bb(2) - 1) < e && Fabs(bb(5) - 1) < e)
    Physical Surface("base_top") += {base_faces(i)};
  EndIf
EndFor
For i In {0 : #pad_faces() - 1}
  bb() = BoundingBox Surface{ pad_faces(i) };
  If (Fabs(bb(2) - 1) < e && Fabs(bb(5) - 1) < e)
    Physical Surface("pad_bottom") += {pad_faces(i)};
  EndIf
  If (Fabs(bb(2) - 1.5) < e && Fabs(bb(5) - 1.5) < e)
    Physical Surface("pad_top") += {pad_faces(i)};
  EndIf
EndFor
For i In {0 : #slider_faces() - 1}
  bb() = BoundingBox Surface{ slider_faces(i) };
  If (Fabs(bb(2) - 1.5) < e && Fabs(bb(5) - 1.5) < e)
    Physical Surface("slider_bottom") += {slider_faces(i)};
  EndIf
  If (Fabs(bb(2) - 2) < e && Fabs(bb(5) - 2) < e)
    Physical Surface("slider_top") += {slider_faces(i)};
  EndIf
EndFor
// the slider's edge x = 0.5, z = 2 (along y)
Physical Curve("pull") = Curve In BoundingBox{0.5-e, 0.5-e, 2-e, 0.5+e, 1.5+e, 2+e};
Mesh.MshFileVersion = 4.1;
