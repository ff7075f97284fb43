#!/usr/bin/python3
"""Pressure loads, support displacements and the fields of 'flextrack static' (issue 12) against
closed forms. Runs `flextrack static` on two scenes and reads what a user reads: static.csv,
summary.json, section_forces.csv and the VTU files (with meshio, as ParaView users' scripts do).

usage: check_static_loads.py FLEXTRACK SCENE_DIR WORK_DIR
"""
import csv
import json
import math
import os
import subprocess
import sys

import meshio

exe, scenes, work = sys.argv[1:4]
failures = []


def check(what, value, reference, tolerance, source):
    """|value - reference| <= tolerance (absolute), with the reference's source in the report."""
    error = abs(value - reference)
    ok = error <= tolerance
    print(f"{'ok  ' if ok else 'FAIL'} {what}: {value:.12g} against {reference:.12g} ({source}); "
          f"error {error:.3g}, tolerance {tolerance:.3g}")
    if not ok:
        failures.append(what)


def run(scene, solver=None):
    """flextrack static on SCENE.prm, or on a copy of it with 'Static/Linear solver = SOLVER'."""
    name = scene if solver is None else f"{scene}_{solver}"
    out = os.path.join(work, name)
    prm = os.path.join(scenes, scene + ".prm")
    if solver is not None:
        os.makedirs(work, exist_ok=True)
        with open(prm) as f:
            text = f.read().replace("subsection Static\n", f"subsection Static\n  set Linear solver = {solver}\n", 1)
        prm = os.path.join(work, name + ".prm")
        with open(prm, "w") as f:
            f.write(text)
    result = subprocess.run([exe, "static", prm, "-o", out], capture_output=True, text=True)
    print(result.stdout)
    if result.returncode != 0:
        sys.exit(f"flextrack static {scene} failed (exit {result.returncode}):\n{result.stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out, "static.csv")) as f:
        rows = list(csv.DictReader(f))
    return out, summary, rows


# --- Propped cantilever, the pin sinks by delta (tests/static_input/settlement_arm.prm) -------
E, nu, d, L, delta = 2.1e11, 0.3, 0.05, 2.0, -0.001  # FlexTrack's default steel; scene values
G = E / (2 * (1 + nu))
A, I = math.pi * d**2 / 4, math.pi * d**4 / 64
k = 6 * (1 + nu) / (7 + 6 * nu)  # Cowper's shear coefficient of a circle (the arm model's)
c = L**3 / (3 * E * I) + L / (k * G * A)  # tip compliance of a Timoshenko cantilever
P = delta / c
out, summary, rows = run("settlement_arm")
tip = rows[0]
# Cubic Timoshenko elements hold the exact solution of end loads: round-off only (1e-9 relative).
check("arm: settled end u_y [m]", float(tip["uy_m"]), delta, 1e-12, "prescribed")
check("arm: end rotation theta_z [rad]", float(tip["theta_z_rad"]), P * L**2 / (2 * E * I),
      1e-9 * abs(P * L**2 / (2 * E * I)), "theta = P L^2 / (2 EI), Timoshenko cantilever")
U = summary["load_cases"][0]["strain_energy_J"]
check("arm: strain energy [J]", U, delta**2 / (2 * c), 1e-9 * delta**2 / (2 * c), "U = delta^2 / (2 c)")
check("arm: force imbalance [N]", summary["load_cases"][0]["force_imbalance_N"], 0, 1e-9 * abs(P),
      "no applied load: the reactions balance each other")
with open(os.path.join(out, "section_forces.csv")) as f:
    forces = list(csv.DictReader(f))
# Section frame of the arm (default: rotation minimising from the reference vector (0, 0, 1)):
# t = x, y = global z, z = t x y = -global y. A tip force P along global y is the shear force
# Q_z = -P and the bending moment about global z, M_y = P (L - s), in that frame.
worst_Q = max(abs(float(r["Q_z_N"]) + P) for r in forces)
worst_M = max(abs(float(r["M_y_Nm"]) - P * (L - float(r["s_m"]))) for r in forces)
worst_other = max(abs(float(r[n])) for r in forces for n in ("N_N", "Q_y_N", "T_Nm", "M_z_Nm"))
check("arm: shear force Q_z, largest error along s [N]", worst_Q, 0, 1e-8 * abs(P), f"Q_z = -P = {-P:.6g} N")
check("arm: bending moment M_y, largest error along s [N m]", worst_M, 0, 1e-8 * abs(P) * L, "M_y = P (L - s)")
check("arm: N, Q_y, T, M_z, largest [N, N m]", worst_other, 0, 1e-8 * abs(P) * L, "0 in a plane problem")
# The VTU files hold 32-bit floats (deal.II's writer): 6e-8 relative, so 2e-7 there.
vtu = meshio.read(os.path.join(out, "static_settle.vtu"))
check("arm VTU: M_y at s = 0 [N m]", max(vtu.point_data["M_y"].flat, key=abs), P * L, 2e-7 * abs(P) * L,
      "M_y(0) = P L, the clamp's moment")
check("arm VTU: largest |u_y| [m]", max(abs(v) for v in vtu.point_data["displacement"][:, 1]), abs(delta),
      2e-7 * abs(delta), "the settled end moves most")

# --- Block on rollers under a pressure (tests/static_input/pressure_block.prm) ----------------
E, nu, p, size = 1e9, 0.3, 1e6, (2.0, 1.0, 1.0)
V = size[0] * size[1] * size[2]
# Both linear solvers: the Cholesky factor (round-off) and CG with algebraic multigrid (its
# relative residual 1e-10, so the displacements to 1e-9 of their scale there).
for solver, u_tolerance in (("direct", 1e-10), ("iterative", 1e-9)):
    out, summary, rows = run("pressure_block", solver)
    expected_solver = "direct (CHOLMOD)" if solver == "direct" else "iterative (CG + algebraic multigrid)"
    if summary["linear_solver"] != expected_solver:
        failures.append(f"linear solver {summary['linear_solver']!r}, expected {expected_solver!r}")
    for case, shift in (("push", 0.0), ("stretch", -0.002)):
        name = f"block {case} ({solver})"
        row = next(r for r in rows if r["load_case"] == case and r["node_set"] == "XMAX")
        # Mean over the face's nodes of u = (-p x / E + shift, nu p y / E, nu p z / E); the nodes
        # of the 2 x 2 hex20 face are symmetric about y = z = 0.5, so the means are at y = z = 0.5.
        scale = p * size[0] / E
        check(f"{name}: mean u_x on x = 2 [m]", float(row["mean_ux_m"]), -p * size[0] / E + shift,
              u_tolerance * scale, "uniaxial stress, u_x = -p x / E")
        check(f"{name}: mean u_y on x = 2 [m]", float(row["mean_uy_m"]), nu * p * 0.5 / E, u_tolerance * scale,
              "u_y = nu p y / E")
        entry = next(c for c in summary["load_cases"] if c["name"] == case)
        check(f"{name}: strain energy [J]", entry["strain_energy_J"], p**2 * V / (2 * E), 1e-9 * p**2 * V / (2 * E),
              "U = p^2 V / (2 E)")
        check(f"{name}: applied force x [N]", entry["applied_force_N"][0], -p * size[1] * size[2], 1e-9 * p,
              "-p times the face's area")
        check(f"{name}: force imbalance [N]", entry["force_imbalance_N"], 0, 1e-9 * p, "equilibrium")
        data = meshio.read(os.path.join(out, f"static_{case}.vtu")).point_data
        check(f"{name} VTU: largest |stress_xx + p| [Pa]", max(abs(v + p) for v in data["stress_xx"]), 0, 2e-7 * p,
              "sigma_xx = -p")
        check(f"{name} VTU: largest |von_mises - p| [Pa]", max(abs(v - p) for v in data["von_mises"]), 0, 2e-7 * p,
              "von Mises = p")
        check(f"{name} VTU: largest |principal_3 + p| [Pa]", max(abs(v + p) for v in data["principal_3"]), 0,
              2e-7 * p, "principal stresses 0, 0, -p")
        others = max(abs(v) for n in ("stress_yy", "stress_zz", "stress_xy", "stress_yz", "stress_xz", "principal_1")
                     for v in data[n])
        check(f"{name} VTU: largest other stress [Pa]", others, 0, 2e-7 * p, "0")
    entry = next(c for c in summary["load_cases"] if c["name"] == "nodes")
    check(f"block nodes ({solver}): applied force x [N]", entry["applied_force_N"][0], -21 * 1000.0, 1e-12 * 21000,
          "1 kN on each of the 21 nodes of a 2 x 2 hex20 face")
    check(f"block nodes ({solver}): force imbalance [N]", entry["force_imbalance_N"], 0, 1e-9 * 21000, "equilibrium")

if failures:
    sys.exit(f"{len(failures)} check(s) failed: {', '.join(failures)}")
print("all checks passed")
