#!/usr/bin/python3
"""Writes curved_bracket.inp: a quarter annulus (radii 0.2 and 0.3 m, 0.05 m thick along z) of
6 x 2 x 1 C3D20 elements whose mid-side nodes lie on the arcs (curved edges), clamped on the face
theta = 0 (node set FIX), steel, with a CalculiX *FREQUENCY step for 10 modes. Run: python3
make_curved_bracket.py > curved_bracket.inp"""
import math

nx, ny, nz = 6, 2, 1
NX, NY, NZ = 2 * nx + 1, 2 * ny + 1, 2 * nz + 1


def node_id(i, j, k):
    return 1 + i + NX * (j + NY * k)


def position(xi, eta, zeta):
    theta, r = 0.5 * math.pi * xi, 0.3 - 0.1 * eta  # (theta, -r, z) is right-handed
    return r * math.cos(theta), r * math.sin(theta), 0.05 * zeta


print("** curved_bracket.inp - written by meshes/make_curved_bracket.py (FlexTrack)")
print("*NODE, NSET=NALL")
for k in range(NZ):
    for j in range(NY):
        for i in range(NX):
            if i % 2 + j % 2 + k % 2 <= 1:
                x, y, z = position(i / (NX - 1), j / (NY - 1), k / (NZ - 1))
                print(f"{node_id(i, j, k)}, {x:.15g}, {y:.15g}, {z:.15g}")  # CalculiX fields: <= 20 characters
local = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2),
         (1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0), (1, 0, 2), (2, 1, 2), (1, 2, 2), (0, 1, 2),
         (0, 0, 1), (2, 0, 1), (2, 2, 1), (0, 2, 1)]
print("*ELEMENT, TYPE=C3D20, ELSET=EALL")
e = 1
for c in range(nz):
    for b in range(ny):
        for a in range(nx):
            ids = [node_id(2 * a + l[0], 2 * b + l[1], 2 * c + l[2]) for l in local]
            print(", ".join(str(v) for v in [e] + ids[:15]) + ",")
            print(", ".join(str(v) for v in ids[15:]))
            e += 1
print("*NSET, NSET=FIX")
fixed = [node_id(0, j, k) for k in range(NZ) for j in range(NY) if j % 2 + k % 2 <= 1]
for start in range(0, len(fixed), 8):  # CalculiX reads at most 16 entries per line
    print(", ".join(str(v) for v in fixed[start:start + 8]) + ",")
print("*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850.")
print("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*BOUNDARY\nFIX, 1, 3")
print("*STEP\n*FREQUENCY\n10\n*END STEP")
