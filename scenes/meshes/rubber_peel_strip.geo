// The rubber strip of scenes/rubber_peel.toml, in millimetres (the scene reads it with
// scale = 0.001): a 2 mm thick, 10 mm wide strip moulded on the outside of a cylinder of radius
// 30 mm whose axis is the y axis, over the polar angles 40° to 140° (from +x towards +z), so
// that its inner face lies on the cylinder. Meshed into 4-node tetrahedra by
// scripts/mesh_rubber_peel.py (gmsh 4.15 from PyPI).
//
// Physical groups: "bond" (the inner face, r = 30 mm, glued to the mould), "grip" (the end face
// at 40°, pulled), "strip" (the volume, so that Gmsh writes its tetrahedra).
SetFactory("Built-in");
R = 30;          // mm: the mould's radius
t = 2;           // mm: thickness
b = 10;          // mm: width, along y
a0 = 40 * Pi / 180;
a1 = 140 * Pi / 180;
h = 1.5;         // mm: element size

Point(1) = {0, 0, 0, h};
Point(2) = {R * Cos(a0), 0, R * Sin(a0), h};
Point(3) = {(R + t) * Cos(a0), 0, (R + t) * Sin(a0), h};
Point(4) = {(R + t) * Cos(a1), 0, (R + t) * Sin(a1), h};
Point(5) = {R * Cos(a1), 0, R * Sin(a1), h};
Circle(1) = {2, 1, 5};
Line(2) = {5, 4};
Circle(3) = {4, 1, 3};
Line(4) = {3, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
out[] = Extrude {0, b, 0} { Surface{1}; };
// out[0]: the face y = b, out[1]: the volume, out[2..5]: the faces swept by curves 1..4.
Physical Surface("bond") = {out[2]};
Physical Surface("grip") = {out[5]};
Physical Volume("strip") = {out[1]};
Mesh.MshFileVersion = 4.1;
Mesh.CharacteristicLengthMax = h;
