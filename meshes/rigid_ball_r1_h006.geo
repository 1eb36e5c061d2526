// A rigid ball (tests/two_bodies.rs, docs/VALIDATION.md, "Two deformable bodies"): the surface
// of a sphere of R = 1 m centred at (0, 0, 1), touching the origin from above, where it presses
// the lower sphere of two_spheres_lower_h006.geo; only its cap below latitude -45° (r < 0.71 m,
// closed by a flat disc far above the contact); gmsh's defaults with only the size set
// (triangles, h = 0.06 m). tools/gmsh_ball_on_sphere.py makes the same at any size.
// gmsh rigid_ball_r1_h006.geo -2 -o rigid_ball_r1_h006.msh
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 1, 1, -Pi/2, -Pi/4, 2*Pi};
Mesh.MeshSizeMin = 0.06;
Mesh.MeshSizeMax = 0.06;
Mesh.Binary = 1;
Mesh.MshFileVersion = 4.1;
