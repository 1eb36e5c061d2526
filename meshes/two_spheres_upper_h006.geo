// The upper body of the two-sphere test (tests/two_bodies.rs, docs/VALIDATION.md,
// "Two deformable bodies"): a quarter (x >= 0, y >= 0) of a sphere of R = 1 m centred at
// (0, 0, 1), touching the origin; gmsh's defaults with only the size set (tet4, h = 0.06 m).
// gmsh two_spheres_upper_h006.geo -3 -o two_spheres_upper_h006.msh
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 1, 1};
Box(2) = {0, 0, -0.5, 2, 2, 3};
BooleanIntersection(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Mesh.MeshSizeMin = 0.06;
Mesh.MeshSizeMax = 0.06;
Mesh.Binary = 1;
Mesh.MshFileVersion = 4.1;
