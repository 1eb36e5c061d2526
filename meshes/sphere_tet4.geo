// sphere_tet4.geo -- solid sphere of radius 1 m centred at the origin, meshed
// with linear tetrahedra (tet4), characteristic length 0.15 m.
// Regenerate with tools/regenerate_meshes.sh (gmsh 4.15.2, OpenCASCADE kernel,
// 3D Delaunay, one thread so that the output is reproducible).
SetFactory("OpenCASCADE");
DefineConstant[ R = 1.0, lc = 0.15 ];

Sphere(1) = {0, 0, 0, R};

Mesh.MeshSizeMin = lc;
Mesh.MeshSizeMax = lc;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 1;
Mesh.Algorithm = 6;      // Frontal-Delaunay for the surface
Mesh.Algorithm3D = 1;    // Delaunay for the volume
Mesh.ElementOrder = 1;
Mesh.OptimizeNetgen = 1;  // removes the worst slivers (min scaled Jacobian 0.20 -> 0.31)
General.NumThreads = 1;

Physical Volume("ball", 1) = {1};
Physical Surface("surface", 2) = {Boundary{ Volume{1}; }};

Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 0;
