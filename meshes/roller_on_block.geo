// A roller (R = 0.3 m, 1 m long) lying on a 2 × 1 × 0.5 m block, each meshed by gmsh's
// defaults (tet4, only the size set) and never fragmented: two solids that share no node and
// touch along a line. pdcontact makes them one body in two pieces that no bond joins, kept
// apart by contact between its pieces (tests/pieces.rs).
//   gmsh meshes/roller_on_block.geo -3 -o meshes/roller_on_block.msh
SetFactory("OpenCASCADE");
Box(1) = {-1, -0.5, -0.5, 2, 1, 0.5};
Cylinder(2) = {0, -0.5, 0.3, 0, 1, 0, 0.3};
Physical Volume("block") = {1};
Physical Volume("roller") = {2};
Mesh.MeshSizeMax = 0.1;
