// A rigid ball's cap (tests/curved_master.rs, docs/VALIDATION.md, "A sphere pressed into a
// block", "Where Hertz holds"): the surface of a sphere of R = 1 m centred at (0, 0, 1),
// touching the origin from above, where it presses a flat block; only its cap within
// r < 0.35 m of the axis (latitude below -69.5°, closed by a flat disc 6.3 cm above the
// contact), enough for a contact of a = 0.1 m; gmsh's defaults with only the size set
// (triangles, h = 0.015 m).
// gmsh rigid_ball_cap_r1_h0015.geo -2 -o rigid_ball_cap_r1_h0015.msh
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 1, 1, -Pi/2, -Pi/2 + Asin(0.35), 2*Pi};
Mesh.MeshSizeMin = 0.015;
Mesh.MeshSizeMax = 0.015;
Mesh.Binary = 1;
Mesh.MshFileVersion = 4.1;
