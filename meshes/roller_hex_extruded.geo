// The Hertz roller as a user meshes a cylinder in hexes: a disc of R = 1 m meshed by
// gmsh's defaults (h = 0.05), its triangles recombined into quads, extruded along y in
// 6 layers of 0.05 m (axis y, as cylinder_tet4_h006.geo). Unstructured across the axis,
// hex8 throughout.
//   gmsh -3 meshes/roller_hex_extruded.geo -o meshes/roller_hex_extruded.msh
SetFactory("OpenCASCADE");
DefineConstant[ R = 1.0, L = 0.3, h = 0.05, layers = 6 ];

Disk(1) = {0, 0, 0, R};
Rotate {{1, 0, 0}, {0, 0, 0}, -Pi/2} { Surface{1}; }
Extrude {0, L, 0} { Surface{1}; Layers{layers}; Recombine; }
Recombine Surface{1};

Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
General.NumThreads = 1;

Physical Volume("roller", 1) = {1};

Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 1;
