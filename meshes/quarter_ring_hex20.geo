// Quarter annulus, radii 0.2 and 0.3 m, 0.05 m thick: 20-node hexahedra (FlexTrack test mesh)
r1 = 0.2; r2 = 0.3; t = 0.05;
Point(1) = {0, 0, 0}; Point(2) = {r1, 0, 0}; Point(3) = {r2, 0, 0};
Point(4) = {0, r1, 0}; Point(5) = {0, r2, 0};
Line(1) = {2, 3}; Circle(2) = {3, 1, 5}; Line(3) = {5, 4}; Circle(4) = {4, 1, 2};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 3} = 3; Transfinite Curve{2, 4} = 7;
Transfinite Surface{1}; Recombine Surface{1};
out[] = Extrude {0, 0, t} { Surface{1}; Layers{1}; Recombine; };
Physical Surface("FIX") = {out[2]};
Physical Volume("BODY") = {out[1]};
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Mesh.SaveGroupsOfNodes = 1;
