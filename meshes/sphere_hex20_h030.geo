// sphere_hex20_h030.geo -- solid sphere of radius 1 m centred at the origin, meshed as a user
// who wants second-order hexes would: gmsh's default tets (h = 0.3 m) each split into four
// hexes (Mesh.SubdivisionAlgorithm = 2), second order without face and centre nodes
// (hex20: Mesh.SecondOrderIncomplete = 1), nothing else set.
// Regenerate with tools/regenerate_meshes.sh (gmsh 4.15.2, one thread so that the output is
// reproducible).
SetFactory("OpenCASCADE");
DefineConstant[ R = 1.0, h = 0.3 ];

Sphere(1) = {0, 0, 0, R};

Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.SubdivisionAlgorithm = 2;
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
General.NumThreads = 1;

Physical Volume("ball", 1) = {1};
Physical Surface("surface", 2) = {Boundary{ Volume{1}; }};

Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 1;
