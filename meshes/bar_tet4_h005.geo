// bar_tet4_h005.geo -- an eighth of a bar 2L x 2B x 2B (L = 1.6 m, B = 0.8 m): the box
// [0, L] x [0, B] x [0, B], meshed as a user would: gmsh's default algorithms, only the
// element size set (h = 0.05 m), first order (tet4). Regenerate with tools/regenerate_meshes.sh
// (gmsh 4.15.2, one thread). With symmetry planes x = 0, y = 0, z = 0
// it is the whole bar, pulled on its end faces ("end", x = L).
SetFactory("OpenCASCADE");
DefineConstant[ L = 1.6, B = 0.8, h = 0.05 ];

Box(1) = {0, 0, 0, L, B, B};

Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
General.NumThreads = 1;

Physical Volume("bar", 1) = {1};
end() = Surface In BoundingBox{L - 1e-6, -1e-6, -1e-6, L + 1e-6, B + 1e-6, B + 1e-6};
Physical Surface("end", 2) = {end()};

Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 1;
