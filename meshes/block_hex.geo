// block_hex.geo -- a 1 x 1 x 0.5 m box of hex8 elements, spacing 0.1 m.
// x, y in [-0.5, 0.5], z in [0, 0.5]: the bottom face lies on the plane z = 0.
// Regenerate with tools/regenerate_meshes.sh (gmsh 4.15.2, built-in kernel).
DefineConstant[ h = 0.1, Lx = 1.0, Ly = 1.0, Lz = 0.5 ];
nx = Round(Lx/h); ny = Round(Ly/h); nz = Round(Lz/h);

Point(1) = {-Lx/2, -Ly/2, 0};
ex[] = Extrude {Lx, 0, 0} { Point{1}; Layers{nx}; };
ey[] = Extrude {0, Ly, 0} { Curve{ex[1]}; Layers{ny}; Recombine; };
ez[] = Extrude {0, 0, Lz} { Surface{ey[1]}; Layers{nz}; Recombine; };
// ey[1]: bottom face (z = 0); ez[0]: top face (z = Lz); ez[1]: the volume

Physical Volume("block", 1) = {ez[1]};
Physical Surface("top", 2) = {ez[0]};
Physical Surface("bottom", 3) = {ey[1]};

Mesh.MshFileVersion = 4.1;
Mesh.SaveAll = 0;
Mesh.Binary = 0;
