// sphere_tet4_graded.geo -- solid sphere of radius 1 m centred at the origin, meshed as an FE
// user meshes a contact: gmsh's default tets, refined towards the south pole (0, 0, -R) where
// the contact will be. A Threshold size field on the distance from the pole: size hf within
// 1.5 a of it (a = 0.3 m, the contact radius of `pdcontact validate --mesh`), growing
// linearly to hc at 1.5 a + 8 hc, hc beyond. Nothing else set. Stored: hf = 0.0333 m.
// Regenerate with tools/regenerate_meshes.sh (gmsh 4.15.2, one thread so that the output is
// reproducible); other sizes with `-setnumber hf 0.02` and so on.
SetFactory("OpenCASCADE");
DefineConstant[ R = 1.0, a = 0.3, hf = 0.0333, hc = 0.15, order = 1, hexes = 0 ];

Sphere(1) = {0, 0, 0, R};

Field[1] = MathEval;
Field[1].F = Sprintf("Sqrt(x*x + y*y + (z + %g)*(z + %g))", R, R);
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hf;
Field[2].SizeMax = hc;
Field[2].DistMin = 1.5 * a;
Field[2].DistMax = 1.5 * a + 8 * hc;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.ElementOrder = order;
Mesh.SubdivisionAlgorithm = 2 * hexes;
General.NumThreads = 1;

Physical Volume("ball", 1) = {1};
Physical Surface("surface", 2) = {Boundary{ Volume{1}; }};

Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 0;
