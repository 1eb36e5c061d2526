// sphere_r1_d008.geo -- hex8 cubed sphere, R = 1 m, target median edge 0.08 m (the default).
// The construction is in sphere_r1_cubed.geo; this file only fixes d.
// Regenerate with tools/regenerate_meshes.sh (gmsh 4.15.2).
d = 0.08;
Include "sphere_r1_cubed.geo";
