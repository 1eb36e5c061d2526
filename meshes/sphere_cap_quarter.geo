// sphere_cap_quarter.geo -- the part of a solid sphere (radius R = 1 m, centred at the
// origin) that a contact at its south pole needs, a quarter of it: the shell between radii
// R - w a and R under the surface patch that reaches w a to each side of the pole, cut by the
// symmetry planes x = 0 and y = 0. Hex8 in radial layers under a cubed-sphere patch (the four
// edges of each spherical face are great-circle arcs), a node at the pole. The mesh of
// `pdcontact demo`: a = 0.15 m (a/R = 0.15, where Hertz's theory holds), cells of d = 0.0125 m
// on the surface (12 across the contact radius).
// Physical groups: volume "cap"; surface "top", the inner spherical face, where the load goes.
// Regenerate with tools/regenerate_meshes.sh (gmsh 4.15.2).
DefineConstant[ a = 0.15, d = 0.0125, R = 1.0, w = 2 ];
D = w*a;                       // depth of the shell under the pole
t = Tan(Asin(w*a/R));          // the patch edges in cubed-sphere coordinates (x/z, y/z)
Ri = R - D;
s1 = 1/Sqrt(1 + t*t); s2 = 1/Sqrt(1 + 2*t*t);
Point(1) = {0, 0, 0};
For k In {0:1}
  r = (k == 0) ? R : Ri;
  Point(10*k + 2) = {0, 0, -r};
  Point(10*k + 3) = {r*t*s1, 0, -r*s1};
  Point(10*k + 4) = {r*t*s2, r*t*s2, -r*s2};
  Point(10*k + 5) = {0, r*t*s1, -r*s1};
  Circle(10*k + 1) = {10*k + 2, 1, 10*k + 3};
  Circle(10*k + 2) = {10*k + 3, 1, 10*k + 4};
  Circle(10*k + 3) = {10*k + 4, 1, 10*k + 5};
  Circle(10*k + 4) = {10*k + 5, 1, 10*k + 2};
  Curve Loop(10*k + 1) = {10*k + 1, 10*k + 2, 10*k + 3, 10*k + 4};
  Surface(10*k + 1) = {10*k + 1} In Sphere {1};
EndFor
For c In {2:5}
  Line(20 + c) = {10 + c, c};  // radial edges, inner sphere to outer
EndFor
Curve Loop(31) = {11, 23, -1, -22}; Plane Surface(31) = {31};   // on y = 0
Curve Loop(32) = {12, 24, -2, -23}; Surface(32) = {32};         // the x side
Curve Loop(33) = {13, 25, -3, -24}; Surface(33) = {33};         // the y side
Curve Loop(34) = {14, 22, -4, -25}; Plane Surface(34) = {34};   // on x = 0
Surface Loop(1) = {1, 11, 31, 32, 33, 34};
Volume(1) = {1};
N = Round(w*a/d) + 1;          // nodes along each patch edge
M = Round(D/d) + 1;            // nodes along each radial edge
Transfinite Curve {1:4, 11:14} = N;
Transfinite Curve {22:25} = M;
Transfinite Surface {1, 11, 31:34};
Recombine Surface {1, 11, 31:34};
Transfinite Volume {1};
Physical Volume("cap", 1) = {1};
Physical Surface("top", 2) = {11};
Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 0;
