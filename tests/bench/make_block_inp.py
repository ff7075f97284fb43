#!/usr/bin/python3
"""Writes a C3D20 cantilever block L x B x H [m] with nx x ny x nz elements as a complete CalculiX
input (steel, node set FIX = the face x = 0 clamped, *FREQUENCY step for 10 modes) to stdout.
Usage: make_block_inp.py nx ny nz [L B H]"""
import sys

nx, ny, nz = (int(v) for v in sys.argv[1:4])
L, B, H = (float(v) for v in sys.argv[4:7]) if len(sys.argv) > 6 else (1.0, 0.1, 0.1)
NX, NY, NZ = 2 * nx + 1, 2 * ny + 1, 2 * nz + 1
out = sys.stdout.write


def node_id(i, j, k):
    return 1 + i + NX * (j + NY * k)


out("** block written by tests/bench/make_block_inp.py (FlexTrack)\n*NODE, NSET=NALL\n")
for k in range(NZ):
    for j in range(NY):
        for i in range(NX):
            if i % 2 + j % 2 + k % 2 <= 1:
                out(f"{node_id(i, j, k)}, {L * i / (NX - 1):.15g}, {B * j / (NY - 1):.15g}, {H * k / (NZ - 1):.15g}\n")
local = [(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2),
         (1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0), (1, 0, 2), (2, 1, 2), (1, 2, 2), (0, 1, 2),
         (0, 0, 1), (2, 0, 1), (2, 2, 1), (0, 2, 1)]
out("*ELEMENT, TYPE=C3D20, ELSET=EALL\n")
e = 1
for c in range(nz):
    for b in range(ny):
        for a in range(nx):
            ids = [node_id(2 * a + l[0], 2 * b + l[1], 2 * c + l[2]) for l in local]
            out(", ".join(str(v) for v in [e] + ids[:15]) + ",\n" + ", ".join(str(v) for v in ids[15:]) + "\n")
            e += 1
out("*NSET, NSET=FIX\n")
fixed = [node_id(0, j, k) for k in range(NZ) for j in range(NY) if j % 2 + k % 2 <= 1]
for s in range(0, len(fixed), 8):
    out(", ".join(str(v) for v in fixed[s:s + 8]) + ",\n")
out("*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850.\n")
out("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*BOUNDARY\nFIX, 1, 3\n*STEP\n*FREQUENCY\n10\n*END STEP\n")
