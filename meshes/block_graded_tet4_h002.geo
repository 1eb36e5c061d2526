// A flat block pressed by a rigid ball (tests/curved_master.rs; docs/VALIDATION.md, "A sphere
// pressed into a block", "Where Hertz holds"): the quarter [0, 1] x [0, 1] x [-2, 0] of a
// 2 x 2 x 2 m block whose top face's corner at the origin is where the ball touches; meshed
// as tools/gmsh_sphere_block.py meshes its block (--l 2 --a 0.1 with H = 0.02): gmsh's
// default algorithms, tet4, size 0.02 m within 0.15 m of that corner, growing with slope 0.1
// to 0.3 m, nothing else set.
// gmsh block_graded_tet4_h002.geo -3 -o block_graded_tet4_h002.msh
SetFactory("OpenCASCADE");
Box(1) = {0, 0, -2, 1, 1, 2};
Field[1] = Distance;
Field[1].PointsList = {1};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = 0.02;
Field[2].SizeMax = 0.3;
Field[2].DistMin = 0.15;
Field[2].DistMax = 2.95;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
General.NumThreads = 1;
Mesh.MshFileVersion = 4.1;
