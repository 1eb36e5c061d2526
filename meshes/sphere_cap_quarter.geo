// sphere_cap_quarter.geo -- the part of a solid sphere (radius R = 1 m, centred at the
// origin) that a contact at its south pole needs, a quarter of it: the shell between radii
// R - w a and R under the surface patch that reaches w a to each side of the pole, cut by the
// symmetry planes x = 0 and y = 0. Hex8 in radial layers under a cubed-sphere patch (the four
// edges of each spherical face are great-circle arcs), a node at the pole. The mesh of
// `pdcontact demo`: a = 0.15 m (a/R = 0.15, where Hertz's theory holds), cells of d = 0.0125 m
// on the surface (12 across the contact radius). The geometry is in
// sphere_cap_quarter_shape.geo; this file meshes it.
// Physical groups: volume "cap"; surface "top", the inner spherical face, where the load goes.
// Regenerate with tools/regenerate_meshes.sh (gmsh 4.15.2).
DefineConstant[ a = 0.15, d = 0.0125, R = 1.0, w = 2 ];
Include "sphere_cap_quarter_shape.geo";
N = Round(w*a/d) + 1;          // nodes along each patch edge
M = Round(D/d) + 1;            // nodes along each radial edge
Transfinite Curve {1:4, 11:14} = N;
Transfinite Curve {22:25} = M;
Transfinite Surface {1, 11, 31:34};
Recombine Surface {1, 11, 31:34};
Transfinite Volume {1};
Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 0;
