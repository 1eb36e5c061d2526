// inclined_block_tet4_h007.geo -- half of a 1 x 1 x 2 m block: the box [-0.5, 0.5] x
// [0, 0.5] x [0, 1], meshed as a user would: gmsh's default algorithms, only the element
// size set (h = 0.07 m), first order (tet4). Regenerate with tools/regenerate_meshes.sh
// (gmsh 4.15.2, one thread). With symmetry planes y = 0 and z = 0 it is the whole block of
// docs/FRACTURE.md, "The 30° crack against CalculiX": loaded on "top" (z = 1), held along x
// there and on "bottom" (z = 0), cut at 30° to the load (tests/crack_contact_gmsh.rs).
SetFactory("OpenCASCADE");
DefineConstant[ h = 0.07 ];

Box(1) = {-0.5, 0, 0, 1, 0.5, 1};

Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
General.NumThreads = 1;

Physical Volume("block", 1) = {1};
top() = Surface In BoundingBox{-0.5 - 1e-6, -1e-6, 1 - 1e-6, 0.5 + 1e-6, 0.5 + 1e-6, 1 + 1e-6};
Physical Surface("top", 2) = {top()};
bottom() = Surface In BoundingBox{-0.5 - 1e-6, -1e-6, -1e-6, 0.5 + 1e-6, 0.5 + 1e-6, 1e-6};
Physical Surface("bottom", 3) = {bottom()};

Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 1;
