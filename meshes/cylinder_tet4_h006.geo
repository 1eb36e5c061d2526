// cylinder_tet4_h006.geo -- solid circular cylinder, radius 1 m, axis along y from y = 0 to
// y = 0.3 m, meshed as a user would: gmsh's default algorithms, only the element size set
// (h = 0.06 m). A slice for the plane-strain Hertz roller of `pdcontact validate --mesh
// --case roller`, which puts symmetry planes on both end faces.
// Regenerate with tools/regenerate_meshes.sh (gmsh 4.15.2, one thread so that the output is
// reproducible).
SetFactory("OpenCASCADE");
DefineConstant[ R = 1.0, L = 0.3, h = 0.06 ];

Cylinder(1) = {0, 0, 0, 0, L, 0, R};

Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.ElementOrder = 1;
General.NumThreads = 1;

Physical Volume("roller", 1) = {1};
Physical Surface("surface", 2) = {Boundary{ Volume{1}; }};

Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 1;
