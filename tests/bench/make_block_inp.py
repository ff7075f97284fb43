#!/usr/bin/python3
"""Writes a C3D20 cantilever block L x B x H [m] with nx x ny x nz elements as a complete CalculiX
input (steel, node set FIX = the face x = 0 clamped, *FREQUENCY step for 10 modes, or N with
--modes N) to stdout.
With --static FX FY FZ: also node set TIP (the face x = L) and, instead of the *FREQUENCY step, a
*STATIC step with the total force (FX, FY, FZ) [N] on the tip face as a uniform traction, given
as its consistent nodal loads (*CLOAD; per hex20 face -1/12 of the face's force at each corner,
1/3 at each mid-side node, summed over the faces) and *NODE PRINT of U on TIP (to the .dat file).
Usage: make_block_inp.py nx ny nz [L B H] [--static FX FY FZ] [--modes N]"""
import sys
from fractions import Fraction

args = sys.argv[1:]
tip_force = None
if "--static" in args:
    i = args.index("--static")
    tip_force = [float(v) for v in args[i + 1:i + 4]]
    if len(tip_force) != 3:
        sys.exit("--static needs three force components FX FY FZ")
    del args[i:i + 4]
modes = 10
if "--modes" in args:
    i = args.index("--modes")
    modes = int(args[i + 1])
    del args[i:i + 2]
nx, ny, nz = (int(v) for v in args[0:3])
L, B, H = (float(v) for v in args[3:6]) if len(args) > 5 else (1.0, 0.1, 0.1)
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
if tip_force is not None:
    i = NX - 1
    out("*NSET, NSET=TIP\n")
    tip = [node_id(i, j, k) for k in range(NZ) for j in range(NY) if j % 2 + k % 2 <= 1]
    for s in range(0, len(tip), 8):
        out(", ".join(str(v) for v in tip[s:s + 8]) + ",\n")
    # Share of the total force per node, exact: every face carries 1 / (ny nz) of it.
    share = {}
    for c in range(nz):
        for b in range(ny):
            for dj in range(3):
                for dk in range(3):
                    if dj == 1 and dk == 1:
                        continue  # no face-centre node in hex20
                    w = Fraction(-1, 12) if dj != 1 and dk != 1 else Fraction(1, 3)
                    n = node_id(i, 2 * b + dj, 2 * c + dk)
                    share[n] = share.get(n, 0) + w / (ny * nz)
out("*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850.\n")
if tip_force is None:
    out(f"*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*BOUNDARY\nFIX, 1, 3\n*STEP\n*FREQUENCY\n{modes}\n*END STEP\n")
else:
    out("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*BOUNDARY\nFIX, 1, 3\n*STEP\n*STATIC\n*CLOAD\n")
    for n in sorted(share):
        for d, f in enumerate(tip_force):
            if f != 0.0 and share[n] != 0:
                out(f"{n}, {d + 1}, {float(share[n]) * f!r}\n")
    out("*NODE PRINT, NSET=TIP\nU\n*END STEP\n")
