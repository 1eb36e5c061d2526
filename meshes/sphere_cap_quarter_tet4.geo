// sphere_cap_quarter_tet4.geo -- the demo's body (sphere_cap_quarter_shape.geo: a quarter of
// the shell 2a deep around the south pole of a sphere of R = 1 m, a = 0.15 m) meshed as a user
// would: gmsh's default algorithms, only the element size set (h = 0.02 m, a/h = 7.5).
// tools/gmsh_hertz_cap.py meshes it at other sizes (-setnumber h H).
// Physical groups: volume "cap"; surface "top", the inner spherical face, where the load goes.
// Regenerate with tools/regenerate_meshes.sh (gmsh 4.15.2, one thread so that the output is
// reproducible).
DefineConstant[ a = 0.15, R = 1.0, w = 2, h = 0.02 ];
Include "sphere_cap_quarter_shape.geo";
Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.ElementOrder = 1;
General.NumThreads = 1;
Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 0;
