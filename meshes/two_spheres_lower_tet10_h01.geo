// The lower body of the one-pass cut-back test (tests/two_bodies.rs, docs/VALIDATION.md, "One
// pass, and pairs of other sizes"): an eighth (x >= 0, y >= 0, z >= -1) of a sphere of R = 1 m
// centred at (0, 0, -1), touching the origin; its equator becomes a symmetry plane;
// gmsh's defaults with only the size and the order set (tet10, h = 0.1 m; every node a
// particle: second_order = "all-nodes").
// gmsh two_spheres_lower_tet10_h01.geo -3 -o two_spheres_lower_tet10_h01.msh
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, -1, 1};
Box(2) = {0, 0, -1, 2, 2, 2.5};
BooleanIntersection(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Mesh.MeshSizeMin = 0.1;
Mesh.MeshSizeMax = 0.1;
Mesh.ElementOrder = 2;
Mesh.Binary = 1;
Mesh.MshFileVersion = 4.1;
