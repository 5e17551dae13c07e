// Quarter of the lower hemisphere of radius 1 centred at (0,0,1), pole at the origin.
SetFactory("OpenCASCADE");
// Mesh sizes for the GetFEM Hertz comparison (getfem_hertz.py): level L has elements of
// 0.02 / L within 0.15 of the pole, growing to 0.25 / L beyond 0.7 (P2 tetrahedra).
//   gmsh -3 -setnumber level 1 getfem_hertz_quarter.geo -o getfem_hertz_level1.msh
If (!Exists(level)) level = 1; EndIf
hmin = 0.02 / level;
hmax = 0.25 / level;
Sphere(1) = {0, 0, 1, 1, -Pi/2, 0, Pi/2};
eps = 1e-6;
Physical Volume(1) = {1};
sx() = Surface In BoundingBox{-eps, -eps, -eps, eps, 1+eps, 1+eps};
sy() = Surface In BoundingBox{-eps, -eps, -eps, 1+eps, eps, 1+eps};
st() = Surface In BoundingBox{-eps, -eps, 1-eps, 1+eps, 1+eps, 1+eps};
all() = Surface{:};
Physical Surface(11) = {sx()};
Physical Surface(12) = {sy()};
Physical Surface(13) = {st()};
sd() = all();
sd() -= {sx(), sy(), st()};
Physical Surface(14) = {sd()};
Point(100) = {0, 0, 0, hmin};
Field[1] = Distance; Field[1].PointsList = {100};
Field[2] = Threshold; Field[2].InField = 1; Field[2].SizeMin = hmin; Field[2].SizeMax = hmax;
Field[2].DistMin = 0.15; Field[2].DistMax = 0.7;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.ElementOrder = 2;
Mesh.MshFileVersion = 2.2;
