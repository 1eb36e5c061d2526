// sphere_tet10_h008.geo -- solid sphere of radius 1 m centred at the origin, meshed as a
// user would: gmsh's default algorithms, only the element size set (h = 0.08 m), second order (tet10)
// Regenerate with tools/regenerate_meshes.sh (gmsh 4.15.2, one thread so that the output is
// reproducible).
SetFactory("OpenCASCADE");
DefineConstant[ R = 1.0, h = 0.08 ];

Sphere(1) = {0, 0, 0, R};

Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.ElementOrder = 2;
General.NumThreads = 1;

Physical Volume("ball", 1) = {1};
Physical Surface("surface", 2) = {Boundary{ Volume{1}; }};

Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 1;
