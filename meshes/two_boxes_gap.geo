// Two 1 m cubes stacked 0.1 m apart in one file, meshed by gmsh's defaults (tet4), as a user
// writes two solids that were never fragmented: they share no node. pdcontact makes them one
// body in two pieces (tests/pieces.rs).
//   gmsh meshes/two_boxes_gap.geo -3 -o meshes/two_boxes_gap.msh
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Box(2) = {0, 0, 1.1, 1, 1, 1};
Mesh.MeshSizeMax = 0.15;
