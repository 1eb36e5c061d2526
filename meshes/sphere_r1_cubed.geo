// sphere_r1_cubed.geo -- solid sphere of radius R (default 1 m) centred at the
// origin, meshed with hex8 elements only: a structured "cubed sphere".
//
// Parameterised source of meshes/sphere_r1_d0XX.geo, which only set d and
// Include this file. Opened on its own it builds the d = 0.08 mesh. Every
// stored .msh is rebuilt by tools/regenerate_meshes.sh (gmsh 4.15.2).
//
// Topology. An inner block (a cube with slightly bulged faces), six shells
// between the block faces and a sphere of radius Rb = R - kb tb d, one per cube
// face (the classic 7-block cubed sphere), and a boundary layer: six more
// shells, concentric, between the spheres Rb and R. Each block is cut into
// its 2 x 2 (x 2) quarters by the planes x = 0, y = 0, z = 0, giving
// 8 + 24 + 24 = 56 transfinite volumes. The cuts change nothing in the topology
// of the mesh (it is the same N x N x N cube plus six N x N x M shells plus six
// N x N x kb shells, N = 2n); they are there so that the sphere patches are
// bounded by short great-circle arcs: a patch bounded by four 70-degree arcs
// is interpolated (Coons patch projected on the sphere) with cells about 1.45x
// larger at its centre than along its edges, a quarter patch about 1.27x.
// They also put a geometry point, hence a mesh node, exactly at the face
// centres, among them the south pole (0, 0, -R), where the sphere touches the
// plane: the grid is regular and symmetric around it. The mesh is conforming:
// blocks share points, curves and surfaces.
//
// Boundary layer. The sphere Rb carries the same arcs and patches as the sphere
// R, scaled by Rb/R (the same angles, the same transfinite grading), and the
// layer's edges are radial segments of kb equal cells. With kb = 1 every node
// of the sphere R sits on a radial edge of length exactly tb d, and the first
// node layer under the surface lies at depth tb d everywhere. Without the layer
// (shells reaching the sphere R) the shells are thinner along the cube
// diagonals than along the axes, and so was the outermost cell: at d = 0.08,
// 0.044 m under the eight cube corners against 0.087 m at the poles, which put
// the first interior nodes there at 0.5 median edge depth, where pdcontact's
// eigenvalue detector (Gaussian kernel of width h = median edge) flags them as
// surface (3.4 % of the interior nodes). The non-uniform thickness is now left
// to the shells under the layer.
//
// Sizes (calibrated with tools/check_meshes.py and pdcontact convert; see
// meshes/README.md):
//   n = Round(cn R / d) cells along each half great-circle arc of a cube face
//       (N = 2n across a face), and the same along the inner-block edges;
//   M = Round(cm R / d) cells radially through a shell (inner block -> Rb);
//   kb cells of tb d each through the boundary layer (Rb -> R).
// Two gradings, the same at every d so the meshes form a refinement family:
//   Gt: along every half arc, the cell next to the face's middle lines is Gt
//       times the cell at the cube edge (Gt < 1 shrinks the cells at the face
//       centres, the pole among them, and grows those at the cube edges);
//   Gr: along every radial line of a shell, the outermost cell is Gr times the
//       innermost (the boundary layer is uniform).
// Inner block: corners at +-a (a = inner R, corner radius a sqrt(3)); its faces
// are caps of spheres bulging out to f = a (1 + bulge (sqrt(3) - 1)) on the
// axes; 0 < bulge < 1. Towards 0 the block becomes a flat cube (cells at the
// shell corners squeezed, and bulge = 0 itself is not allowed: zc infinite),
// towards 1 a sphere (inner-block corners flat, scaled Jacobian -> 0). The
// block must stay inside the sphere Rb (a sqrt(3) < Rb).

DefineConstant[
  d = 0.08,     // target median element edge (m)
  R = 1.0,      // sphere radius (m)
  inner = 0.46, // half-side of the inner block at its corners, / R
  bulge = 0.4,  // in (0, 1): towards 0 flat cube faces, towards 1 spherical
  Gt = 0.75,    // tangential grading, face-middle cell / cube-edge cell
  Gr = 1.0,     // radial grading in the shells, outermost / innermost cell
  cn = 0.58,    // n = Round(cn R / d)
  cm = 0.25,    // M = Round(cm R / d)
  kb = 1,       // cells through the boundary layer (an integer >= 1)
  tb = 1.1      // thickness of a boundary-layer cell, / d
];

If (bulge <= 0 || bulge >= 1)
  Error("sphere_r1_cubed.geo: bulge = %g, must be strictly between 0 and 1", bulge);
  Abort;
EndIf
n = Round(cn*R/d); If (n < 2) n = 2; EndIf
M = Round(cm*R/d); If (M < 2) M = 2; EndIf
tg = Gt^(1/(n-1));   // progression ratio per cell along the half arcs
rp = Gr^(1/(M-1));   // progression ratio per cell along the radial lines

a = inner*R;
f = a + bulge*(Sqrt(3) - 1)*a;   // inner face centre: distance from the origin
zc = (3*a*a - f*f)/(2*(f - a));  // its sphere is centred at -zc on the face axis
rho = zc + f;                    // ... with radius rho
// inner edge midpoint at distance m: where the two face spheres meet,
// the positive root of m^2 + sqrt(2) zc m + zc^2 - rho^2 = 0
m = (-Sqrt(2)*zc + Sqrt(2*zc*zc - 4*(zc*zc - rho*rho)))/2;
me = m/Sqrt(2);      // inner edge midpoint = me*(+-1, +-1, 0) and permutations
ze = zc/2;           // inner edges are arcs centred at -ze*(+-1, +-1, 0)...
Re = R/Sqrt(2);      // sphere point above an edge midpoint
Rc = R/Sqrt(3);      // sphere point above a corner
Rb = R - kb*tb*d;    // inner radius of the boundary layer
Reb = Rb/Sqrt(2);
Rcb = Rb/Sqrt(3);
If (kb < 1 || kb != Round(kb) || Rb <= a*Sqrt(3))
  Error("sphere_r1_cubed.geo: kb = %g, tb = %g: kb must be a positive integer and R - kb tb d > inner sqrt(3) R", kb, tb);
  Abort;
EndIf
Printf("cubed sphere: R = %g, d = %g: n = %g (N = %g), M = %g, tg = %g, rp = %g, boundary layer %g x %g from Rb = %g",
       R, d, n, 2*n, M, tg, rp, kb, tb*d, Rb);

// ---- points ----------------------------------------------------------------
// lattice (i,j,k) in {-1,0,1}^3: corners, edge midpoints, face centres, centre
// inner block: tags 1-27 (14 = the centre, also the centre of the sphere arcs)
Point(1) = {-a, -a, -a};  // corner (-,-,-)
Point(2) = {-me, -me, 0};  // edge midpoint (-,-,0)
Point(3) = {-a, -a, a};  // corner (-,-,+)
Point(4) = {-me, 0, -me};  // edge midpoint (-,0,-)
Point(5) = {-f, 0, 0};  // face centre (-,0,0)
Point(6) = {-me, 0, me};  // edge midpoint (-,0,+)
Point(7) = {-a, a, -a};  // corner (-,+,-)
Point(8) = {-me, me, 0};  // edge midpoint (-,+,0)
Point(9) = {-a, a, a};  // corner (-,+,+)
Point(10) = {0, -me, -me};  // edge midpoint (0,-,-)
Point(11) = {0, -f, 0};  // face centre (0,-,0)
Point(12) = {0, -me, me};  // edge midpoint (0,-,+)
Point(13) = {0, 0, -f};  // face centre (0,0,-)
Point(14) = {0, 0, 0};  // centre (0,0,0)
Point(15) = {0, 0, f};  // face centre (0,0,+)
Point(16) = {0, me, -me};  // edge midpoint (0,+,-)
Point(17) = {0, f, 0};  // face centre (0,+,0)
Point(18) = {0, me, me};  // edge midpoint (0,+,+)
Point(19) = {a, -a, -a};  // corner (+,-,-)
Point(20) = {me, -me, 0};  // edge midpoint (+,-,0)
Point(21) = {a, -a, a};  // corner (+,-,+)
Point(22) = {me, 0, -me};  // edge midpoint (+,0,-)
Point(23) = {f, 0, 0};  // face centre (+,0,0)
Point(24) = {me, 0, me};  // edge midpoint (+,0,+)
Point(25) = {a, a, -a};  // corner (+,+,-)
Point(26) = {me, me, 0};  // edge midpoint (+,+,0)
Point(27) = {a, a, a};  // corner (+,+,+)
// sphere: tags 101-127, the point R*(i,j,k)/|(i,j,k)|
Point(101) = {-Rc, -Rc, -Rc};  // corner (-,-,-)
Point(102) = {-Re, -Re, 0};  // edge midpoint (-,-,0)
Point(103) = {-Rc, -Rc, Rc};  // corner (-,-,+)
Point(104) = {-Re, 0, -Re};  // edge midpoint (-,0,-)
Point(105) = {-R, 0, 0};  // face centre (-,0,0)
Point(106) = {-Re, 0, Re};  // edge midpoint (-,0,+)
Point(107) = {-Rc, Rc, -Rc};  // corner (-,+,-)
Point(108) = {-Re, Re, 0};  // edge midpoint (-,+,0)
Point(109) = {-Rc, Rc, Rc};  // corner (-,+,+)
Point(110) = {0, -Re, -Re};  // edge midpoint (0,-,-)
Point(111) = {0, -R, 0};  // face centre (0,-,0)
Point(112) = {0, -Re, Re};  // edge midpoint (0,-,+)
Point(113) = {0, 0, -R};  // face centre (0,0,-)  <- south pole
Point(115) = {0, 0, R};  // face centre (0,0,+)
Point(116) = {0, Re, -Re};  // edge midpoint (0,+,-)
Point(117) = {0, R, 0};  // face centre (0,+,0)
Point(118) = {0, Re, Re};  // edge midpoint (0,+,+)
Point(119) = {Rc, -Rc, -Rc};  // corner (+,-,-)
Point(120) = {Re, -Re, 0};  // edge midpoint (+,-,0)
Point(121) = {Rc, -Rc, Rc};  // corner (+,-,+)
Point(122) = {Re, 0, -Re};  // edge midpoint (+,0,-)
Point(123) = {R, 0, 0};  // face centre (+,0,0)
Point(124) = {Re, 0, Re};  // edge midpoint (+,0,+)
Point(125) = {Rc, Rc, -Rc};  // corner (+,+,-)
Point(126) = {Re, Re, 0};  // edge midpoint (+,+,0)
Point(127) = {Rc, Rc, Rc};  // corner (+,+,+)
// sphere Rb (inner side of the boundary layer): tags 401-427, the point
// Rb*(i,j,k)/|(i,j,k)| (tag = 300 + tag of the sphere point)
Point(401) = {-Rcb, -Rcb, -Rcb};  // corner (-,-,-)
Point(402) = {-Reb, -Reb, 0};  // edge midpoint (-,-,0)
Point(403) = {-Rcb, -Rcb, Rcb};  // corner (-,-,+)
Point(404) = {-Reb, 0, -Reb};  // edge midpoint (-,0,-)
Point(405) = {-Rb, 0, 0};  // face centre (-,0,0)
Point(406) = {-Reb, 0, Reb};  // edge midpoint (-,0,+)
Point(407) = {-Rcb, Rcb, -Rcb};  // corner (-,+,-)
Point(408) = {-Reb, Reb, 0};  // edge midpoint (-,+,0)
Point(409) = {-Rcb, Rcb, Rcb};  // corner (-,+,+)
Point(410) = {0, -Reb, -Reb};  // edge midpoint (0,-,-)
Point(411) = {0, -Rb, 0};  // face centre (0,-,0)
Point(412) = {0, -Reb, Reb};  // edge midpoint (0,-,+)
Point(413) = {0, 0, -Rb};  // face centre (0,0,-)
Point(415) = {0, 0, Rb};  // face centre (0,0,+)
Point(416) = {0, Reb, -Reb};  // edge midpoint (0,+,-)
Point(417) = {0, Rb, 0};  // face centre (0,+,0)
Point(418) = {0, Reb, Reb};  // edge midpoint (0,+,+)
Point(419) = {Rcb, -Rcb, -Rcb};  // corner (+,-,-)
Point(420) = {Reb, -Reb, 0};  // edge midpoint (+,-,0)
Point(421) = {Rcb, -Rcb, Rcb};  // corner (+,-,+)
Point(422) = {Reb, 0, -Reb};  // edge midpoint (+,0,-)
Point(423) = {Rb, 0, 0};  // face centre (+,0,0)
Point(424) = {Reb, 0, Reb};  // edge midpoint (+,0,+)
Point(425) = {Rcb, Rcb, -Rcb};  // corner (+,+,-)
Point(426) = {Reb, Reb, 0};  // edge midpoint (+,+,0)
Point(427) = {Rcb, Rcb, Rcb};  // corner (+,+,+)
// centres of the six spheres that carry the faces of the inner block (201-206)
Point(201) = {zc, 0, 0};  // face -x
Point(202) = {-zc, 0, 0};  // face +x
Point(203) = {0, zc, 0};  // face -y
Point(204) = {0, -zc, 0};  // face +y
Point(205) = {0, 0, zc};  // face -z
Point(206) = {0, 0, -zc};  // face +z
// centres of the circles that carry the edges of the inner block (301-312)
Point(301) = {ze, ze, 0};  // edge (-,-,0)
Point(302) = {ze, 0, ze};  // edge (-,0,-)
Point(303) = {ze, 0, -ze};  // edge (-,0,+)
Point(304) = {ze, -ze, 0};  // edge (-,+,0)
Point(305) = {0, ze, ze};  // edge (0,-,-)
Point(306) = {0, ze, -ze};  // edge (0,-,+)
Point(307) = {0, -ze, ze};  // edge (0,+,-)
Point(308) = {0, -ze, -ze};  // edge (0,+,+)
Point(309) = {-ze, ze, 0};  // edge (+,-,0)
Point(310) = {-ze, 0, ze};  // edge (+,0,-)
Point(311) = {-ze, 0, -ze};  // edge (+,0,+)
Point(312) = {-ze, -ze, 0};  // edge (+,+,0)

// ---- curves ----------------------------------------------------------------
// inner block, tags 1-54, all oriented from the end with |coordinate| = 1 to
// the end with coordinate = 0 (towards the middle lines of a cube face)
Circle(1) = {1, 305, 10};  // corner -> edge midpoint
Circle(2) = {1, 302, 4};  // corner -> edge midpoint
Circle(3) = {1, 301, 2};  // corner -> edge midpoint
Circle(4) = {2, 203, 11};  // edge midpoint -> face centre
Circle(5) = {2, 201, 5};  // edge midpoint -> face centre
Circle(6) = {3, 306, 12};  // corner -> edge midpoint
Circle(7) = {3, 303, 6};  // corner -> edge midpoint
Circle(8) = {3, 301, 2};  // corner -> edge midpoint
Circle(9) = {4, 205, 13};  // edge midpoint -> face centre
Circle(10) = {4, 201, 5};  // edge midpoint -> face centre
Line(11) = {5, 14};  // face centre -> centre
Circle(12) = {6, 206, 15};  // edge midpoint -> face centre
Circle(13) = {6, 201, 5};  // edge midpoint -> face centre
Circle(14) = {7, 307, 16};  // corner -> edge midpoint
Circle(15) = {7, 302, 4};  // corner -> edge midpoint
Circle(16) = {7, 304, 8};  // corner -> edge midpoint
Circle(17) = {8, 204, 17};  // edge midpoint -> face centre
Circle(18) = {8, 201, 5};  // edge midpoint -> face centre
Circle(19) = {9, 308, 18};  // corner -> edge midpoint
Circle(20) = {9, 303, 6};  // corner -> edge midpoint
Circle(21) = {9, 304, 8};  // corner -> edge midpoint
Circle(22) = {10, 205, 13};  // edge midpoint -> face centre
Circle(23) = {10, 203, 11};  // edge midpoint -> face centre
Line(24) = {11, 14};  // face centre -> centre
Circle(25) = {12, 206, 15};  // edge midpoint -> face centre
Circle(26) = {12, 203, 11};  // edge midpoint -> face centre
Line(27) = {13, 14};  // face centre -> centre
Line(28) = {15, 14};  // face centre -> centre
Circle(29) = {16, 205, 13};  // edge midpoint -> face centre
Circle(30) = {16, 204, 17};  // edge midpoint -> face centre
Line(31) = {17, 14};  // face centre -> centre
Circle(32) = {18, 206, 15};  // edge midpoint -> face centre
Circle(33) = {18, 204, 17};  // edge midpoint -> face centre
Circle(34) = {19, 305, 10};  // corner -> edge midpoint
Circle(35) = {19, 310, 22};  // corner -> edge midpoint
Circle(36) = {19, 309, 20};  // corner -> edge midpoint
Circle(37) = {20, 203, 11};  // edge midpoint -> face centre
Circle(38) = {20, 202, 23};  // edge midpoint -> face centre
Circle(39) = {21, 306, 12};  // corner -> edge midpoint
Circle(40) = {21, 311, 24};  // corner -> edge midpoint
Circle(41) = {21, 309, 20};  // corner -> edge midpoint
Circle(42) = {22, 205, 13};  // edge midpoint -> face centre
Circle(43) = {22, 202, 23};  // edge midpoint -> face centre
Line(44) = {23, 14};  // face centre -> centre
Circle(45) = {24, 206, 15};  // edge midpoint -> face centre
Circle(46) = {24, 202, 23};  // edge midpoint -> face centre
Circle(47) = {25, 307, 16};  // corner -> edge midpoint
Circle(48) = {25, 310, 22};  // corner -> edge midpoint
Circle(49) = {25, 312, 26};  // corner -> edge midpoint
Circle(50) = {26, 204, 17};  // edge midpoint -> face centre
Circle(51) = {26, 202, 23};  // edge midpoint -> face centre
Circle(52) = {27, 308, 18};  // corner -> edge midpoint
Circle(53) = {27, 311, 24};  // corner -> edge midpoint
Circle(54) = {27, 312, 26};  // corner -> edge midpoint
// sphere: tag = 100 + tag of the inner-block curve between the same lattice
// points (great-circle arcs centred at the origin, same orientation)
Circle(101) = {101, 14, 110};
Circle(102) = {101, 14, 104};
Circle(103) = {101, 14, 102};
Circle(104) = {102, 14, 111};
Circle(105) = {102, 14, 105};
Circle(106) = {103, 14, 112};
Circle(107) = {103, 14, 106};
Circle(108) = {103, 14, 102};
Circle(109) = {104, 14, 113};
Circle(110) = {104, 14, 105};
Circle(112) = {106, 14, 115};
Circle(113) = {106, 14, 105};
Circle(114) = {107, 14, 116};
Circle(115) = {107, 14, 104};
Circle(116) = {107, 14, 108};
Circle(117) = {108, 14, 117};
Circle(118) = {108, 14, 105};
Circle(119) = {109, 14, 118};
Circle(120) = {109, 14, 106};
Circle(121) = {109, 14, 108};
Circle(122) = {110, 14, 113};
Circle(123) = {110, 14, 111};
Circle(125) = {112, 14, 115};
Circle(126) = {112, 14, 111};
Circle(129) = {116, 14, 113};
Circle(130) = {116, 14, 117};
Circle(132) = {118, 14, 115};
Circle(133) = {118, 14, 117};
Circle(134) = {119, 14, 110};
Circle(135) = {119, 14, 122};
Circle(136) = {119, 14, 120};
Circle(137) = {120, 14, 111};
Circle(138) = {120, 14, 123};
Circle(139) = {121, 14, 112};
Circle(140) = {121, 14, 124};
Circle(141) = {121, 14, 120};
Circle(142) = {122, 14, 113};
Circle(143) = {122, 14, 123};
Circle(145) = {124, 14, 115};
Circle(146) = {124, 14, 123};
Circle(147) = {125, 14, 116};
Circle(148) = {125, 14, 122};
Circle(149) = {125, 14, 126};
Circle(150) = {126, 14, 117};
Circle(151) = {126, 14, 123};
Circle(152) = {127, 14, 118};
Circle(153) = {127, 14, 124};
Circle(154) = {127, 14, 126};
// sphere Rb: tag = 300 + tag of the sphere arc (same lattice points, same
// orientation)
Circle(401) = {401, 14, 410};
Circle(402) = {401, 14, 404};
Circle(403) = {401, 14, 402};
Circle(404) = {402, 14, 411};
Circle(405) = {402, 14, 405};
Circle(406) = {403, 14, 412};
Circle(407) = {403, 14, 406};
Circle(408) = {403, 14, 402};
Circle(409) = {404, 14, 413};
Circle(410) = {404, 14, 405};
Circle(412) = {406, 14, 415};
Circle(413) = {406, 14, 405};
Circle(414) = {407, 14, 416};
Circle(415) = {407, 14, 404};
Circle(416) = {407, 14, 408};
Circle(417) = {408, 14, 417};
Circle(418) = {408, 14, 405};
Circle(419) = {409, 14, 418};
Circle(420) = {409, 14, 406};
Circle(421) = {409, 14, 408};
Circle(422) = {410, 14, 413};
Circle(423) = {410, 14, 411};
Circle(425) = {412, 14, 415};
Circle(426) = {412, 14, 411};
Circle(429) = {416, 14, 413};
Circle(430) = {416, 14, 417};
Circle(432) = {418, 14, 415};
Circle(433) = {418, 14, 417};
Circle(434) = {419, 14, 410};
Circle(435) = {419, 14, 422};
Circle(436) = {419, 14, 420};
Circle(437) = {420, 14, 411};
Circle(438) = {420, 14, 423};
Circle(439) = {421, 14, 412};
Circle(440) = {421, 14, 424};
Circle(441) = {421, 14, 420};
Circle(442) = {422, 14, 413};
Circle(443) = {422, 14, 423};
Circle(445) = {424, 14, 415};
Circle(446) = {424, 14, 423};
Circle(447) = {425, 14, 416};
Circle(448) = {425, 14, 422};
Circle(449) = {425, 14, 426};
Circle(450) = {426, 14, 417};
Circle(451) = {426, 14, 423};
Circle(452) = {427, 14, 418};
Circle(453) = {427, 14, 424};
Circle(454) = {427, 14, 426};
// radial lines, inner block -> sphere Rb: tag = 200 + tag of the inner point
Line(201) = {1, 401};
Line(202) = {2, 402};
Line(203) = {3, 403};
Line(204) = {4, 404};
Line(205) = {5, 405};
Line(206) = {6, 406};
Line(207) = {7, 407};
Line(208) = {8, 408};
Line(209) = {9, 409};
Line(210) = {10, 410};
Line(211) = {11, 411};
Line(212) = {12, 412};
Line(213) = {13, 413};
Line(215) = {15, 415};
Line(216) = {16, 416};
Line(217) = {17, 417};
Line(218) = {18, 418};
Line(219) = {19, 419};
Line(220) = {20, 420};
Line(221) = {21, 421};
Line(222) = {22, 422};
Line(223) = {23, 423};
Line(224) = {24, 424};
Line(225) = {25, 425};
Line(226) = {26, 426};
Line(227) = {27, 427};
// radial lines through the boundary layer, sphere Rb -> sphere R:
// tag = 400 + tag of the point on the sphere R
Line(501) = {401, 101};
Line(502) = {402, 102};
Line(503) = {403, 103};
Line(504) = {404, 104};
Line(505) = {405, 105};
Line(506) = {406, 106};
Line(507) = {407, 107};
Line(508) = {408, 108};
Line(509) = {409, 109};
Line(510) = {410, 110};
Line(511) = {411, 111};
Line(512) = {412, 112};
Line(513) = {413, 113};
Line(515) = {415, 115};
Line(516) = {416, 116};
Line(517) = {417, 117};
Line(518) = {418, 118};
Line(519) = {419, 119};
Line(520) = {420, 120};
Line(521) = {421, 121};
Line(522) = {422, 122};
Line(523) = {423, 123};
Line(524) = {424, 124};
Line(525) = {425, 125};
Line(526) = {426, 126};
Line(527) = {427, 127};

// ---- surfaces --------------------------------------------------------------
// 1-12: planes inside the inner block (centre, two face centres, edge midpoint)
Curve Loop(1) = {-11, -5, 4, 24};
Surface(1) = {1};
Curve Loop(2) = {-11, -10, 9, 27};
Surface(2) = {2};
Curve Loop(3) = {-11, -13, 12, 28};
Surface(3) = {3};
Curve Loop(4) = {-11, -18, 17, 31};
Surface(4) = {4};
Curve Loop(5) = {-24, -23, 22, 27};
Surface(5) = {5};
Curve Loop(6) = {-24, -26, 25, 28};
Surface(6) = {6};
Curve Loop(7) = {-31, -30, 29, 27};
Surface(7) = {7};
Curve Loop(8) = {-31, -33, 32, 28};
Surface(8) = {8};
Curve Loop(9) = {-44, -38, 37, 24};
Surface(9) = {9};
Curve Loop(10) = {-44, -43, 42, 27};
Surface(10) = {10};
Curve Loop(11) = {-44, -46, 45, 28};
Surface(11) = {11};
Curve Loop(12) = {-44, -51, 50, 31};
Surface(12) = {12};
// 101-124: quarter faces of the inner block (on the sphere centred at 201-206)
// 201-224: quarter patches of the sphere (on the sphere centred at the origin)
Curve Loop(101) = {2, 10, -5, -3};  // face -x, quarter at corner (-,-,-)
Surface(101) = {101} In Sphere {201};
Curve Loop(201) = {102, 110, -105, -103};
Surface(201) = {201} In Sphere {14};
Curve Loop(102) = {7, 13, -5, -8};  // face -x, quarter at corner (-,-,+)
Surface(102) = {102} In Sphere {201};
Curve Loop(202) = {107, 113, -105, -108};
Surface(202) = {202} In Sphere {14};
Curve Loop(103) = {15, 10, -18, -16};  // face -x, quarter at corner (-,+,-)
Surface(103) = {103} In Sphere {201};
Curve Loop(203) = {115, 110, -118, -116};
Surface(203) = {203} In Sphere {14};
Curve Loop(104) = {20, 13, -18, -21};  // face -x, quarter at corner (-,+,+)
Surface(104) = {104} In Sphere {201};
Curve Loop(204) = {120, 113, -118, -121};
Surface(204) = {204} In Sphere {14};
Curve Loop(105) = {35, 43, -38, -36};  // face +x, quarter at corner (+,-,-)
Surface(105) = {105} In Sphere {202};
Curve Loop(205) = {135, 143, -138, -136};
Surface(205) = {205} In Sphere {14};
Curve Loop(106) = {40, 46, -38, -41};  // face +x, quarter at corner (+,-,+)
Surface(106) = {106} In Sphere {202};
Curve Loop(206) = {140, 146, -138, -141};
Surface(206) = {206} In Sphere {14};
Curve Loop(107) = {48, 43, -51, -49};  // face +x, quarter at corner (+,+,-)
Surface(107) = {107} In Sphere {202};
Curve Loop(207) = {148, 143, -151, -149};
Surface(207) = {207} In Sphere {14};
Curve Loop(108) = {53, 46, -51, -54};  // face +x, quarter at corner (+,+,+)
Surface(108) = {108} In Sphere {202};
Curve Loop(208) = {153, 146, -151, -154};
Surface(208) = {208} In Sphere {14};
Curve Loop(109) = {1, 23, -4, -3};  // face -y, quarter at corner (-,-,-)
Surface(109) = {109} In Sphere {203};
Curve Loop(209) = {101, 123, -104, -103};
Surface(209) = {209} In Sphere {14};
Curve Loop(110) = {6, 26, -4, -8};  // face -y, quarter at corner (-,-,+)
Surface(110) = {110} In Sphere {203};
Curve Loop(210) = {106, 126, -104, -108};
Surface(210) = {210} In Sphere {14};
Curve Loop(111) = {34, 23, -37, -36};  // face -y, quarter at corner (+,-,-)
Surface(111) = {111} In Sphere {203};
Curve Loop(211) = {134, 123, -137, -136};
Surface(211) = {211} In Sphere {14};
Curve Loop(112) = {39, 26, -37, -41};  // face -y, quarter at corner (+,-,+)
Surface(112) = {112} In Sphere {203};
Curve Loop(212) = {139, 126, -137, -141};
Surface(212) = {212} In Sphere {14};
Curve Loop(113) = {14, 30, -17, -16};  // face +y, quarter at corner (-,+,-)
Surface(113) = {113} In Sphere {204};
Curve Loop(213) = {114, 130, -117, -116};
Surface(213) = {213} In Sphere {14};
Curve Loop(114) = {19, 33, -17, -21};  // face +y, quarter at corner (-,+,+)
Surface(114) = {114} In Sphere {204};
Curve Loop(214) = {119, 133, -117, -121};
Surface(214) = {214} In Sphere {14};
Curve Loop(115) = {47, 30, -50, -49};  // face +y, quarter at corner (+,+,-)
Surface(115) = {115} In Sphere {204};
Curve Loop(215) = {147, 130, -150, -149};
Surface(215) = {215} In Sphere {14};
Curve Loop(116) = {52, 33, -50, -54};  // face +y, quarter at corner (+,+,+)
Surface(116) = {116} In Sphere {204};
Curve Loop(216) = {152, 133, -150, -154};
Surface(216) = {216} In Sphere {14};
Curve Loop(117) = {1, 22, -9, -2};  // face -z, quarter at corner (-,-,-)
Surface(117) = {117} In Sphere {205};
Curve Loop(217) = {101, 122, -109, -102};
Surface(217) = {217} In Sphere {14};
Curve Loop(118) = {14, 29, -9, -15};  // face -z, quarter at corner (-,+,-)
Surface(118) = {118} In Sphere {205};
Curve Loop(218) = {114, 129, -109, -115};
Surface(218) = {218} In Sphere {14};
Curve Loop(119) = {34, 22, -42, -35};  // face -z, quarter at corner (+,-,-)
Surface(119) = {119} In Sphere {205};
Curve Loop(219) = {134, 122, -142, -135};
Surface(219) = {219} In Sphere {14};
Curve Loop(120) = {47, 29, -42, -48};  // face -z, quarter at corner (+,+,-)
Surface(120) = {120} In Sphere {205};
Curve Loop(220) = {147, 129, -142, -148};
Surface(220) = {220} In Sphere {14};
Curve Loop(121) = {6, 25, -12, -7};  // face +z, quarter at corner (-,-,+)
Surface(121) = {121} In Sphere {206};
Curve Loop(221) = {106, 125, -112, -107};
Surface(221) = {221} In Sphere {14};
Curve Loop(122) = {19, 32, -12, -20};  // face +z, quarter at corner (-,+,+)
Surface(122) = {122} In Sphere {206};
Curve Loop(222) = {119, 132, -112, -120};
Surface(222) = {222} In Sphere {14};
Curve Loop(123) = {39, 25, -45, -40};  // face +z, quarter at corner (+,-,+)
Surface(123) = {123} In Sphere {206};
Curve Loop(223) = {139, 125, -145, -140};
Surface(223) = {223} In Sphere {14};
Curve Loop(124) = {52, 32, -45, -53};  // face +z, quarter at corner (+,+,+)
Surface(124) = {124} In Sphere {206};
Curve Loop(224) = {152, 132, -145, -153};
Surface(224) = {224} In Sphere {14};
// 401-424: quarter patches of the sphere Rb (tag = 200 + tag of the patch of R)
Curve Loop(401) = {402, 410, -405, -403};
Surface(401) = {401} In Sphere {14};
Curve Loop(402) = {407, 413, -405, -408};
Surface(402) = {402} In Sphere {14};
Curve Loop(403) = {415, 410, -418, -416};
Surface(403) = {403} In Sphere {14};
Curve Loop(404) = {420, 413, -418, -421};
Surface(404) = {404} In Sphere {14};
Curve Loop(405) = {435, 443, -438, -436};
Surface(405) = {405} In Sphere {14};
Curve Loop(406) = {440, 446, -438, -441};
Surface(406) = {406} In Sphere {14};
Curve Loop(407) = {448, 443, -451, -449};
Surface(407) = {407} In Sphere {14};
Curve Loop(408) = {453, 446, -451, -454};
Surface(408) = {408} In Sphere {14};
Curve Loop(409) = {401, 423, -404, -403};
Surface(409) = {409} In Sphere {14};
Curve Loop(410) = {406, 426, -404, -408};
Surface(410) = {410} In Sphere {14};
Curve Loop(411) = {434, 423, -437, -436};
Surface(411) = {411} In Sphere {14};
Curve Loop(412) = {439, 426, -437, -441};
Surface(412) = {412} In Sphere {14};
Curve Loop(413) = {414, 430, -417, -416};
Surface(413) = {413} In Sphere {14};
Curve Loop(414) = {419, 433, -417, -421};
Surface(414) = {414} In Sphere {14};
Curve Loop(415) = {447, 430, -450, -449};
Surface(415) = {415} In Sphere {14};
Curve Loop(416) = {452, 433, -450, -454};
Surface(416) = {416} In Sphere {14};
Curve Loop(417) = {401, 422, -409, -402};
Surface(417) = {417} In Sphere {14};
Curve Loop(418) = {414, 429, -409, -415};
Surface(418) = {418} In Sphere {14};
Curve Loop(419) = {434, 422, -442, -435};
Surface(419) = {419} In Sphere {14};
Curve Loop(420) = {447, 429, -442, -448};
Surface(420) = {420} In Sphere {14};
Curve Loop(421) = {406, 425, -412, -407};
Surface(421) = {421} In Sphere {14};
Curve Loop(422) = {419, 432, -412, -420};
Surface(422) = {422} In Sphere {14};
Curve Loop(423) = {439, 425, -445, -440};
Surface(423) = {423} In Sphere {14};
Curve Loop(424) = {452, 432, -445, -453};
Surface(424) = {424} In Sphere {14};
// 301-348: radial surfaces between the shell blocks, one per segment of the
// sphere Rb
Curve Loop(301) = {1, 210, -401, -201};
Surface(301) = {301};
Curve Loop(302) = {2, 204, -402, -201};
Surface(302) = {302};
Curve Loop(303) = {3, 202, -403, -201};
Surface(303) = {303};
Curve Loop(304) = {4, 211, -404, -202};
Surface(304) = {304};
Curve Loop(305) = {5, 205, -405, -202};
Surface(305) = {305};
Curve Loop(306) = {6, 212, -406, -203};
Surface(306) = {306};
Curve Loop(307) = {7, 206, -407, -203};
Surface(307) = {307};
Curve Loop(308) = {8, 202, -408, -203};
Surface(308) = {308};
Curve Loop(309) = {9, 213, -409, -204};
Surface(309) = {309};
Curve Loop(310) = {10, 205, -410, -204};
Surface(310) = {310};
Curve Loop(311) = {12, 215, -412, -206};
Surface(311) = {311};
Curve Loop(312) = {13, 205, -413, -206};
Surface(312) = {312};
Curve Loop(313) = {14, 216, -414, -207};
Surface(313) = {313};
Curve Loop(314) = {15, 204, -415, -207};
Surface(314) = {314};
Curve Loop(315) = {16, 208, -416, -207};
Surface(315) = {315};
Curve Loop(316) = {17, 217, -417, -208};
Surface(316) = {316};
Curve Loop(317) = {18, 205, -418, -208};
Surface(317) = {317};
Curve Loop(318) = {19, 218, -419, -209};
Surface(318) = {318};
Curve Loop(319) = {20, 206, -420, -209};
Surface(319) = {319};
Curve Loop(320) = {21, 208, -421, -209};
Surface(320) = {320};
Curve Loop(321) = {22, 213, -422, -210};
Surface(321) = {321};
Curve Loop(322) = {23, 211, -423, -210};
Surface(322) = {322};
Curve Loop(323) = {25, 215, -425, -212};
Surface(323) = {323};
Curve Loop(324) = {26, 211, -426, -212};
Surface(324) = {324};
Curve Loop(325) = {29, 213, -429, -216};
Surface(325) = {325};
Curve Loop(326) = {30, 217, -430, -216};
Surface(326) = {326};
Curve Loop(327) = {32, 215, -432, -218};
Surface(327) = {327};
Curve Loop(328) = {33, 217, -433, -218};
Surface(328) = {328};
Curve Loop(329) = {34, 210, -434, -219};
Surface(329) = {329};
Curve Loop(330) = {35, 222, -435, -219};
Surface(330) = {330};
Curve Loop(331) = {36, 220, -436, -219};
Surface(331) = {331};
Curve Loop(332) = {37, 211, -437, -220};
Surface(332) = {332};
Curve Loop(333) = {38, 223, -438, -220};
Surface(333) = {333};
Curve Loop(334) = {39, 212, -439, -221};
Surface(334) = {334};
Curve Loop(335) = {40, 224, -440, -221};
Surface(335) = {335};
Curve Loop(336) = {41, 220, -441, -221};
Surface(336) = {336};
Curve Loop(337) = {42, 213, -442, -222};
Surface(337) = {337};
Curve Loop(338) = {43, 223, -443, -222};
Surface(338) = {338};
Curve Loop(339) = {45, 215, -445, -224};
Surface(339) = {339};
Curve Loop(340) = {46, 223, -446, -224};
Surface(340) = {340};
Curve Loop(341) = {47, 216, -447, -225};
Surface(341) = {341};
Curve Loop(342) = {48, 222, -448, -225};
Surface(342) = {342};
Curve Loop(343) = {49, 226, -449, -225};
Surface(343) = {343};
Curve Loop(344) = {50, 217, -450, -226};
Surface(344) = {344};
Curve Loop(345) = {51, 223, -451, -226};
Surface(345) = {345};
Curve Loop(346) = {52, 218, -452, -227};
Surface(346) = {346};
Curve Loop(347) = {53, 224, -453, -227};
Surface(347) = {347};
Curve Loop(348) = {54, 226, -454, -227};
Surface(348) = {348};
// 501-548: radial surfaces between the boundary-layer blocks (tag = 200 + tag
// of the shell surface below)
Curve Loop(501) = {401, 510, -101, -501};
Surface(501) = {501};
Curve Loop(502) = {402, 504, -102, -501};
Surface(502) = {502};
Curve Loop(503) = {403, 502, -103, -501};
Surface(503) = {503};
Curve Loop(504) = {404, 511, -104, -502};
Surface(504) = {504};
Curve Loop(505) = {405, 505, -105, -502};
Surface(505) = {505};
Curve Loop(506) = {406, 512, -106, -503};
Surface(506) = {506};
Curve Loop(507) = {407, 506, -107, -503};
Surface(507) = {507};
Curve Loop(508) = {408, 502, -108, -503};
Surface(508) = {508};
Curve Loop(509) = {409, 513, -109, -504};
Surface(509) = {509};
Curve Loop(510) = {410, 505, -110, -504};
Surface(510) = {510};
Curve Loop(511) = {412, 515, -112, -506};
Surface(511) = {511};
Curve Loop(512) = {413, 505, -113, -506};
Surface(512) = {512};
Curve Loop(513) = {414, 516, -114, -507};
Surface(513) = {513};
Curve Loop(514) = {415, 504, -115, -507};
Surface(514) = {514};
Curve Loop(515) = {416, 508, -116, -507};
Surface(515) = {515};
Curve Loop(516) = {417, 517, -117, -508};
Surface(516) = {516};
Curve Loop(517) = {418, 505, -118, -508};
Surface(517) = {517};
Curve Loop(518) = {419, 518, -119, -509};
Surface(518) = {518};
Curve Loop(519) = {420, 506, -120, -509};
Surface(519) = {519};
Curve Loop(520) = {421, 508, -121, -509};
Surface(520) = {520};
Curve Loop(521) = {422, 513, -122, -510};
Surface(521) = {521};
Curve Loop(522) = {423, 511, -123, -510};
Surface(522) = {522};
Curve Loop(523) = {425, 515, -125, -512};
Surface(523) = {523};
Curve Loop(524) = {426, 511, -126, -512};
Surface(524) = {524};
Curve Loop(525) = {429, 513, -129, -516};
Surface(525) = {525};
Curve Loop(526) = {430, 517, -130, -516};
Surface(526) = {526};
Curve Loop(527) = {432, 515, -132, -518};
Surface(527) = {527};
Curve Loop(528) = {433, 517, -133, -518};
Surface(528) = {528};
Curve Loop(529) = {434, 510, -134, -519};
Surface(529) = {529};
Curve Loop(530) = {435, 522, -135, -519};
Surface(530) = {530};
Curve Loop(531) = {436, 520, -136, -519};
Surface(531) = {531};
Curve Loop(532) = {437, 511, -137, -520};
Surface(532) = {532};
Curve Loop(533) = {438, 523, -138, -520};
Surface(533) = {533};
Curve Loop(534) = {439, 512, -139, -521};
Surface(534) = {534};
Curve Loop(535) = {440, 524, -140, -521};
Surface(535) = {535};
Curve Loop(536) = {441, 520, -141, -521};
Surface(536) = {536};
Curve Loop(537) = {442, 513, -142, -522};
Surface(537) = {537};
Curve Loop(538) = {443, 523, -143, -522};
Surface(538) = {538};
Curve Loop(539) = {445, 515, -145, -524};
Surface(539) = {539};
Curve Loop(540) = {446, 523, -146, -524};
Surface(540) = {540};
Curve Loop(541) = {447, 516, -147, -525};
Surface(541) = {541};
Curve Loop(542) = {448, 522, -148, -525};
Surface(542) = {542};
Curve Loop(543) = {449, 526, -149, -525};
Surface(543) = {543};
Curve Loop(544) = {450, 517, -150, -526};
Surface(544) = {544};
Curve Loop(545) = {451, 523, -151, -526};
Surface(545) = {545};
Curve Loop(546) = {452, 518, -152, -527};
Surface(546) = {546};
Curve Loop(547) = {453, 524, -153, -527};
Surface(547) = {547};
Curve Loop(548) = {454, 526, -154, -527};
Surface(548) = {548};

// ---- volumes ---------------------------------------------------------------
// 1-8: the inner block, one sub-block per octant
Surface Loop(1) = {5, 2, 1, 101, 109, 117};  // octant (-,-,-)
Volume(1) = {1};
Surface Loop(2) = {6, 3, 1, 102, 110, 121};  // octant (-,-,+)
Volume(2) = {2};
Surface Loop(3) = {7, 2, 4, 103, 113, 118};  // octant (-,+,-)
Volume(3) = {3};
Surface Loop(4) = {8, 3, 4, 104, 114, 122};  // octant (-,+,+)
Volume(4) = {4};
Surface Loop(5) = {5, 10, 9, 105, 111, 119};  // octant (+,-,-)
Volume(5) = {5};
Surface Loop(6) = {6, 11, 9, 106, 112, 123};  // octant (+,-,+)
Volume(6) = {6};
Surface Loop(7) = {7, 10, 12, 107, 115, 120};  // octant (+,+,-)
Volume(7) = {7};
Surface Loop(8) = {8, 11, 12, 108, 116, 124};  // octant (+,+,+)
Volume(8) = {8};
// 11-34: the six shells (inner block -> Rb), four sub-blocks each
Surface Loop(11) = {101, 401, 302, 310, 305, 303};  // shell -x, quarter at corner (-,-,-)
Volume(11) = {11};
Surface Loop(12) = {102, 402, 307, 312, 305, 308};  // shell -x, quarter at corner (-,-,+)
Volume(12) = {12};
Surface Loop(13) = {103, 403, 314, 310, 317, 315};  // shell -x, quarter at corner (-,+,-)
Volume(13) = {13};
Surface Loop(14) = {104, 404, 319, 312, 317, 320};  // shell -x, quarter at corner (-,+,+)
Volume(14) = {14};
Surface Loop(15) = {105, 405, 330, 338, 333, 331};  // shell +x, quarter at corner (+,-,-)
Volume(15) = {15};
Surface Loop(16) = {106, 406, 335, 340, 333, 336};  // shell +x, quarter at corner (+,-,+)
Volume(16) = {16};
Surface Loop(17) = {107, 407, 342, 338, 345, 343};  // shell +x, quarter at corner (+,+,-)
Volume(17) = {17};
Surface Loop(18) = {108, 408, 347, 340, 345, 348};  // shell +x, quarter at corner (+,+,+)
Volume(18) = {18};
Surface Loop(19) = {109, 409, 301, 322, 304, 303};  // shell -y, quarter at corner (-,-,-)
Volume(19) = {19};
Surface Loop(20) = {110, 410, 306, 324, 304, 308};  // shell -y, quarter at corner (-,-,+)
Volume(20) = {20};
Surface Loop(21) = {111, 411, 329, 322, 332, 331};  // shell -y, quarter at corner (+,-,-)
Volume(21) = {21};
Surface Loop(22) = {112, 412, 334, 324, 332, 336};  // shell -y, quarter at corner (+,-,+)
Volume(22) = {22};
Surface Loop(23) = {113, 413, 313, 326, 316, 315};  // shell +y, quarter at corner (-,+,-)
Volume(23) = {23};
Surface Loop(24) = {114, 414, 318, 328, 316, 320};  // shell +y, quarter at corner (-,+,+)
Volume(24) = {24};
Surface Loop(25) = {115, 415, 341, 326, 344, 343};  // shell +y, quarter at corner (+,+,-)
Volume(25) = {25};
Surface Loop(26) = {116, 416, 346, 328, 344, 348};  // shell +y, quarter at corner (+,+,+)
Volume(26) = {26};
Surface Loop(27) = {117, 417, 301, 321, 309, 302};  // shell -z, quarter at corner (-,-,-)
Volume(27) = {27};
Surface Loop(28) = {118, 418, 313, 325, 309, 314};  // shell -z, quarter at corner (-,+,-)
Volume(28) = {28};
Surface Loop(29) = {119, 419, 329, 321, 337, 330};  // shell -z, quarter at corner (+,-,-)
Volume(29) = {29};
Surface Loop(30) = {120, 420, 341, 325, 337, 342};  // shell -z, quarter at corner (+,+,-)
Volume(30) = {30};
Surface Loop(31) = {121, 421, 306, 323, 311, 307};  // shell +z, quarter at corner (-,-,+)
Volume(31) = {31};
Surface Loop(32) = {122, 422, 318, 327, 311, 319};  // shell +z, quarter at corner (-,+,+)
Volume(32) = {32};
Surface Loop(33) = {123, 423, 334, 323, 339, 335};  // shell +z, quarter at corner (+,-,+)
Volume(33) = {33};
Surface Loop(34) = {124, 424, 346, 327, 339, 347};  // shell +z, quarter at corner (+,+,+)
Volume(34) = {34};
// 41-64: the boundary layer, six concentric shells between Rb and R, four
// sub-blocks each (tag = 30 + tag of the shell block below)
Surface Loop(41) = {401, 201, 502, 510, 505, 503};  // shell -x, quarter at corner (-,-,-)
Volume(41) = {41};
Surface Loop(42) = {402, 202, 507, 512, 505, 508};  // shell -x, quarter at corner (-,-,+)
Volume(42) = {42};
Surface Loop(43) = {403, 203, 514, 510, 517, 515};  // shell -x, quarter at corner (-,+,-)
Volume(43) = {43};
Surface Loop(44) = {404, 204, 519, 512, 517, 520};  // shell -x, quarter at corner (-,+,+)
Volume(44) = {44};
Surface Loop(45) = {405, 205, 530, 538, 533, 531};  // shell +x, quarter at corner (+,-,-)
Volume(45) = {45};
Surface Loop(46) = {406, 206, 535, 540, 533, 536};  // shell +x, quarter at corner (+,-,+)
Volume(46) = {46};
Surface Loop(47) = {407, 207, 542, 538, 545, 543};  // shell +x, quarter at corner (+,+,-)
Volume(47) = {47};
Surface Loop(48) = {408, 208, 547, 540, 545, 548};  // shell +x, quarter at corner (+,+,+)
Volume(48) = {48};
Surface Loop(49) = {409, 209, 501, 522, 504, 503};  // shell -y, quarter at corner (-,-,-)
Volume(49) = {49};
Surface Loop(50) = {410, 210, 506, 524, 504, 508};  // shell -y, quarter at corner (-,-,+)
Volume(50) = {50};
Surface Loop(51) = {411, 211, 529, 522, 532, 531};  // shell -y, quarter at corner (+,-,-)
Volume(51) = {51};
Surface Loop(52) = {412, 212, 534, 524, 532, 536};  // shell -y, quarter at corner (+,-,+)
Volume(52) = {52};
Surface Loop(53) = {413, 213, 513, 526, 516, 515};  // shell +y, quarter at corner (-,+,-)
Volume(53) = {53};
Surface Loop(54) = {414, 214, 518, 528, 516, 520};  // shell +y, quarter at corner (-,+,+)
Volume(54) = {54};
Surface Loop(55) = {415, 215, 541, 526, 544, 543};  // shell +y, quarter at corner (+,+,-)
Volume(55) = {55};
Surface Loop(56) = {416, 216, 546, 528, 544, 548};  // shell +y, quarter at corner (+,+,+)
Volume(56) = {56};
Surface Loop(57) = {417, 217, 501, 521, 509, 502};  // shell -z, quarter at corner (-,-,-)
Volume(57) = {57};
Surface Loop(58) = {418, 218, 513, 525, 509, 514};  // shell -z, quarter at corner (-,+,-)
Volume(58) = {58};
Surface Loop(59) = {419, 219, 529, 521, 537, 530};  // shell -z, quarter at corner (+,-,-)
Volume(59) = {59};
Surface Loop(60) = {420, 220, 541, 525, 537, 542};  // shell -z, quarter at corner (+,+,-)
Volume(60) = {60};
Surface Loop(61) = {421, 221, 506, 523, 511, 507};  // shell +z, quarter at corner (-,-,+)
Volume(61) = {61};
Surface Loop(62) = {422, 222, 518, 527, 511, 519};  // shell +z, quarter at corner (-,+,+)
Volume(62) = {62};
Surface Loop(63) = {423, 223, 534, 523, 539, 535};  // shell +z, quarter at corner (+,-,+)
Volume(63) = {63};
Surface Loop(64) = {424, 224, 546, 527, 539, 547};  // shell +z, quarter at corner (+,+,+)
Volume(64) = {64};


// ---- mesh ------------------------------------------------------------------
// Half arcs and inner-block lines are oriented from a cube edge (|coord| = 1)
// towards a face middle line (coord = 0), so one progression grades them all.
Transfinite Curve{1:54} = n + 1 Using Progression tg;     // inner block
Transfinite Curve{101:110, 112:123, 125:126, 129:130, 132:143, 145:154} = n + 1 Using Progression tg;  // sphere
Transfinite Curve{401:410, 412:423, 425:426, 429:430, 432:443, 445:454} = n + 1 Using Progression tg;  // sphere Rb
Transfinite Curve{201:213, 215:227} = M + 1 Using Progression rp;  // radial, inner block -> Rb
Transfinite Curve{501:513, 515:527} = kb + 1;  // radial, boundary layer: kb cells of tb d
Transfinite Surface{:};
Recombine Surface{:};
Transfinite Volume{:};

Physical Volume("ball", 1) = {1:8, 11:34, 41:64};
Physical Surface("surface", 2) = {201:224};
Physical Surface("south_cap", 3) = {217:220};  // sphere patch of the z- boundary-layer shell

Mesh.MshFileVersion = 4.1;
Mesh.Binary = 0;
Mesh.SaveAll = 0;   // save only the physical groups: all hexes are in "ball"
