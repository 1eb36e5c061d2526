// sphere_cap_quarter_shape.geo -- the geometry of the demo's body: the part of a solid sphere
// (radius R, centred at the origin) that a contact at its south pole needs, a quarter of it:
// the shell between radii R - w a and R under the surface patch that reaches w a to each side
// of the pole (its four edges great-circle arcs, as on a cubed sphere), cut by the symmetry
// planes x = 0 and y = 0; a geometry point at the pole. Set a, R and w, then Include this file:
// sphere_cap_quarter.geo meshes it with structured hex8, sphere_cap_quarter_tet4.geo with
// gmsh's default tets.
// Physical groups: volume "cap"; surface "top", the inner spherical face, where the load goes.
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
Physical Volume("cap", 1) = {1};
Physical Surface("top", 2) = {11};
