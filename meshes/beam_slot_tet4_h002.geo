// beam_slot_tet4_h002.geo -- the notched three-point bend beam of `pdcontact fracture`
// (ASTM E399: W = 40 mm, span S = 4W, notch a = W/2) meshed as a user meshes a notched
// specimen: the notch a slot 0.5 mm wide cut out of the solid, no pre-crack. The model the
// study runs: x in [-90, 90] mm (the span and 10 mm beyond each support), half the thickness
// y in [0, 4] mm (a symmetry plane at y = 0), z in [0, W]; the slot x in [-0.25, 0.25] mm,
// z in [0, 20] mm. Metres. gmsh's default algorithms, only the element size set
// (h = 2 mm), first order (tet4). Regenerate with tools/regenerate_meshes.sh (gmsh 4.15.2,
// one thread); tools/gmsh_beam.py writes the same beam at other sizes and slot widths.
SetFactory("OpenCASCADE");
DefineConstant[ W = 0.04, L = 0.09, B = 0.004, w = 0.0005, h = 0.002 ];

Box(1) = {-L, 0, 0, 2 * L, B, W};
Box(2) = {-w / 2, -0.001, -0.001, w, B + 0.002, W / 2 + 0.001};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };

Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
General.NumThreads = 1;

Physical Volume("beam", 1) = {3};

Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 1;
