#!/usr/bin/env python3
"""Craig-Bampton against free-interface bodies in the same scene (issue 9 acceptance).

The scene (boom_pendulum.prm next to this file) hangs the free block-and-boom body of
boom_body.prm from a revolute joint at its interface 'root' and lets it swing under gravity.
For each reduction method (Craig-Bampton: frame at 'root', fixed-interface modes; free
interface: mean axes, free-free modes and residual attachment modes with inertia relief) and each
number of normal modes this script writes a copy of both files into its own folder (the reduced
body cached there too), runs `flextrack run`, reads the tip probe and prints

  method, normal modes, reduced modes, largest distance of the tip path from the richest run of
  the OTHER method and of the SAME method, steps, wall time.

References: each method's richest basis (a converged run) and the other method's richest basis
(a converged run of a different method). Acceptance (asserted; exit status 1 on failure):

  1. Each method converges: the tip path's distance from its own richest run falls by at least
     --min-factor from the smallest basis to the second richest, and never grows by more than
     --noise between neighbouring bases (the integrator's error, --integrator-check, is the floor).
     Each method's table runs at tolerances whose integrator error is far below its smallest
     basis's error: the scene's for CB, ten times tighter for FI (main() says why).
  2. The two methods converge to the same motion up to an effect of second order in the
     deformation: the distance between the two richest runs, divided by the largest elastic tip
     deflection (distance from the path of the body's rigid twin), is below --max-relative; and
     with every Young's modulus multiplied by --stiffer, that distance falls at least as the
     elastic deflection to the power --min-order (> 1). A basis error or a mistake in either
     method is of first order: it falls like the deflection itself (the 2-mode Craig-Bampton
     basis error does: exponent 1.08 from x1 to x8, doc/validation.md). At --stiffer 8 that is a
     distance ratio of about 12; the bound 1.3 asks for 20; measured: 42 (exponent 1.63). What is
     left is the linear floating-frame model's dependence on its frame (root against mean axes),
     of order u^2 / L.
  3. In the linear range the two methods agree to the basis accuracy: with every Young's modulus
     times --linear (32: the deflection 41 times smaller) and the tolerances / 100, the richest
     runs differ by no more than the larger of the two methods' basis errors with the table's
     second basis (4 modes). Measured: 6.4e-9 m against 9.4e-9 m (CB) and 5.6e-10 m (FI).

Usage: cb_vs_fi.py FLEXTRACK OUTPUT_FOLDER [--modes 2,4,8,16] [--end-time 0.3] [--rtol 1e-9] ...
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
METHODS = [("craig bampton", "CB"), ("free interface", "FI")]


def parse_arguments():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("flextrack")
    p.add_argument("output")
    p.add_argument("--modes", default="2,4,8,16", help="normal-mode counts, ascending (at least three)")
    p.add_argument("--end-time", type=float, default=0.3, help="simulated time [s]")
    p.add_argument("--rtol", type=float, default=1e-9, help="IDA relative tolerance [-]")
    p.add_argument("--atol", type=float, default=1e-11, help="IDA absolute tolerance [m, rad, modal units]")
    p.add_argument("--velocity-tolerance", type=float, default=1e-8,
                   help="IDA absolute tolerance of the velocities [m/s, rad/s, modal units/s]")
    p.add_argument("--min-factor", type=float, default=5.0,
                   help="required fall of a method's distance from its richest run, smallest to second richest basis [-]")
    p.add_argument("--noise", type=float, default=1.5, help="allowed growth between neighbouring bases [-]")
    p.add_argument("--max-relative", type=float, default=0.01,
                   help="bound on the richest runs' distance over the largest elastic tip deflection [-]; "
                        "a judgement for this scene: measured 0.64 %%, growing with the deflection (1.07 %% "
                        "with the moduli halved) as a second-order effect does")
    p.add_argument("--moduli-factor", type=float, default=1.0,
                   help="factor on every Young's modulus of the body in all runs (a study of the order) [-]")
    p.add_argument("--stiffer", type=float, default=8.0,
                   help="factor on the Young's moduli for the order check; 0: no order check [-]")
    p.add_argument("--min-order", type=float, default=1.3,
                   help="required exponent p: distance ratio >= (deflection ratio)^p [-]")
    p.add_argument("--linear", type=float, default=32.0,
                   help="factor on the Young's moduli for the linear-range check (the frame effect, of second "
                        "order, below the basis error); 0: no such check [-]")
    p.add_argument("--integrator-check", action="store_true",
                   help="also run each richest basis at rtol / 10 and report the change (the integrator error)")
    return p.parse_args()


def replace_entry(text, entry, value):
    """The scene text with 'set ENTRY = ...' given VALUE (the entry must occur exactly once)."""
    lines = text.splitlines()
    hits = [i for i, line in enumerate(lines) if line.strip().startswith("set " + entry + " ") or
            line.strip().startswith("set " + entry + "=")]
    if len(hits) != 1:
        raise SystemExit(f"cb_vs_fi.py: entry '{entry}' occurs {len(hits)} times in a template; expected once")
    indent = lines[hits[0]][: len(lines[hits[0]]) - len(lines[hits[0]].lstrip())]
    lines[hits[0]] = f"{indent}set {entry} = {value}"
    return "\n".join(lines) + "\n"


def scaled_moduli(text, factor):
    """The body scene with every Young's modulus multiplied by FACTOR."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        words = line.split()
        if line.strip().startswith("set Young's modulus") and words[3] == "=":
            lines[i] = line.replace(words[4], repr(float(words[4]) * factor), 1)
    return "\n".join(lines) + "\n"


def write_case(folder, method, modes, args, rtol, rigid=False, stiffer=1.0):
    """Writes the body and pendulum scenes of one case into FOLDER; returns the pendulum scene.
    RIGID: the body's rigid twin (same mass, first moment and inertia, no modes); STIFFER: factor
    on the Young's moduli."""
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(HERE, "boom_body.prm")) as f:
        body = f.read()
    body = replace_entry(body, "Method", method)
    body = replace_entry(body, "Number of normal modes", modes)
    if stiffer * args.moduli_factor != 1.0:
        body = scaled_moduli(body, stiffer * args.moduli_factor)
    # The reduced body is cached in the case's own folder, not under the working directory.
    body += f"subsection Output\n  set Directory = {os.path.abspath(os.path.join(folder, 'reduced'))}\nend\n"
    with open(os.path.join(folder, "boom_body.prm"), "w") as f:
        f.write(body)
    with open(os.path.join(HERE, "boom_pendulum.prm")) as f:
        scene = f.read()
    scene = replace_entry(scene, "End time", repr(args.end_time))
    scene = replace_entry(scene, "Relative tolerance", repr(rtol))
    scene = replace_entry(scene, "Absolute tolerance", repr(args.atol))
    scene = replace_entry(scene, "Velocity tolerance", repr(args.velocity_tolerance))
    if rigid:
        scene = replace_entry(scene, "Geometric stiffening", "false\n  set Rigid = true")
    path = os.path.join(folder, "boom_pendulum.prm")
    with open(path, "w") as f:
        f.write(scene)
    return path


def run_case(flextrack, folder, method, modes, args, rtol, rigid=False, stiffer=1.0):
    scene = write_case(folder, method, modes, args, rtol, rigid, stiffer)
    out = os.path.join(folder, "run")
    start = time.monotonic()
    proc = subprocess.run([flextrack, "run", scene, "-o", out], capture_output=True, text=True)
    wall = time.monotonic() - start
    if proc.returncode != 0:
        sys.stdout.write(proc.stdout + proc.stderr)
        raise SystemExit(f"cb_vs_fi.py: flextrack run failed for {method}, {modes} modes (exit {proc.returncode})")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    n_reduced = None
    for line in proc.stdout.splitlines():
        if line.strip().startswith("body boom: flexible,"):
            n_reduced = int(line.split(",")[1].split()[0])
    with open(os.path.join(out, "probes.csv")) as f:
        rows = list(csv.DictReader(f))
    path = [(float(r["time_s"]), float(r["tip_x_m"]), float(r["tip_y_m"]), float(r["tip_z_m"])) for r in rows]
    return {"method": method, "modes": modes, "reduced": n_reduced, "path": path, "wall": wall,
            "integration": summary["wall_time_s"]["time integration"], "steps": summary["integrator"]["steps"],
            "energy": summary["max_over_output_rows"]["relative_energy_balance_error"]}


# Factor on every tolerance of a method's convergence table (main: why FI's is tighter).
TABLE_TOLERANCE_FACTOR = {"CB": 1.0, "FI": 0.1}


def tolerances_times(args, factor):
    """ARGS with rtol, atol and the velocity tolerance times FACTOR (ARGS itself for 1)."""
    if factor == 1.0:
        return args
    scaled = argparse.Namespace(**vars(args))
    scaled.rtol, scaled.atol = args.rtol * factor, args.atol * factor
    scaled.velocity_tolerance = args.velocity_tolerance * factor
    return scaled


def distance(a, b):
    """Largest distance between two tip paths sampled at the same output times [m]."""
    if len(a) != len(b) or any(abs(p[0] - q[0]) > 1e-12 for p, q in zip(a, b)):
        raise SystemExit("cb_vs_fi.py: two runs have different output times")
    return max(math.dist(p[1:], q[1:]) for p, q in zip(a, b))


def richest_pair(args, modes, stiffer, label):
    """The richest run of each method and the rigid twin, Young's moduli times STIFFER: the
    richest runs' distance and the largest elastic tip deflection (from the rigid twin) [m]."""
    runs = {short: run_case(args.flextrack, os.path.join(args.output, f"{label}{short}_{modes[-1]}"), method,
                            modes[-1], args, args.rtol, stiffer=stiffer) for method, short in METHODS}
    rigid = run_case(args.flextrack, os.path.join(args.output, f"{label}rigid"), METHODS[0][0], modes[0], args,
                     args.rtol, rigid=True, stiffer=stiffer)
    return runs, distance(runs["CB"]["path"], runs["FI"]["path"]), distance(runs["CB"]["path"], rigid["path"])


def main():
    args = parse_arguments()
    modes = [int(m) for m in args.modes.split(",")]
    if modes != sorted(modes) or len(modes) < 3:
        raise SystemExit("cb_vs_fi.py: --modes needs at least three ascending counts")
    richest, agreement, elastic = richest_pair(args, modes, 1.0, "")
    # The convergence table of each method runs at tolerances whose integrator error lies well
    # below that method's smallest-basis error, else assertion 1 measures the integrator. At the
    # scene's tolerances (rtol 1e-9) the error is about 1e-8 m (CB) and 4e-8 m (FI; each richest
    # run against itself at rtol / 10, doc/validation.md): CB's 2-mode distance, 1.2e-6 m, is 100
    # times above it, FI's, 2.2-2.5e-7 m, only about 5 times, so FI's table plateaued at 5e-8 m
    # from 4 modes on and its fall from 2 to 8 modes (4.4-30) depended on rounding. FI's table
    # runs with every tolerance / 10.
    table_args = {short: tolerances_times(args, TABLE_TOLERANCE_FACTOR[short]) for _, short in METHODS}
    runs = {}
    for method, short in METHODS:
        table = table_args[short]
        runs[(short, modes[-1])] = (richest[short] if table is args else
                                    run_case(args.flextrack, os.path.join(args.output, f"{short}_{modes[-1]}_table"),
                                             method, modes[-1], table, table.rtol))
        for m in modes[:-1]:
            runs[(short, m)] = run_case(args.flextrack, os.path.join(args.output, f"{short}_{m}"), method, m, table,
                                        table.rtol)
    other = {"CB": "FI", "FI": "CB"}

    print(f"tip of the boom, {args.end_time} s, rtol {args.rtol:g}, atol {args.atol:g}, velocity tolerance "
          f"{args.velocity_tolerance:g}; largest elastic tip deflection (from the rigid twin's path) {elastic:.3e} m")
    print("convergence tables' tolerances: " + ", ".join(f"{short} rtol {table_args[short].rtol:g}" for _, short in METHODS)
          + " (the 'other' column compares with the other method's richest run at the scene's tolerances)")
    print("| method | normal modes | reduced modes | diff. from richest of the other method [m] | "
          "diff. from richest of the same method [m] | steps | integration [s] | wall [s] |")
    print("|---|---|---|---|---|---|---|---|")
    for _, short in METHODS:
        for m in modes:
            r = runs[(short, m)]
            r["d_other"] = distance(r["path"], richest[other[short]]["path"])
            r["d_same"] = distance(r["path"], runs[(short, modes[-1])]["path"])
            print(f"| {short} | {m} | {r['reduced']} | {r['d_other']:.3e} | {r['d_same']:.3e} | {r['steps']} | "
                  f"{r['integration']:.2f} | {r['wall']:.2f} |")

    if args.integrator_check:
        for method, short in METHODS:
            table = table_args[short]
            tight = run_case(args.flextrack, os.path.join(args.output, f"{short}_{modes[-1]}_tight"), method,
                             modes[-1], table, table.rtol / 10)
            print(f"integrator: {short} {modes[-1]} modes, rtol {table.rtol:g} against {table.rtol / 10:g}: "
                  f"{distance(tight['path'], runs[(short, modes[-1])]['path']):.3e} m ({tight['steps']} steps, "
                  f"{tight['wall']:.2f} s)")

    failures = []
    # 1. Each method converges towards its own richest basis (reference: that converged run).
    for _, short in METHODS:
        d = [runs[(short, m)]["d_same"] for m in modes[:-1]]
        fall = d[0] / d[-1] if d[-1] > 0 else math.inf
        print(f"{short}: distance from its richest basis falls by {fall:.3g} from {modes[0]} to {modes[-2]} modes")
        if not fall >= args.min_factor:
            failures.append(f"{short}: the distance from its richest basis falls by only {fall:.3g} from {modes[0]} "
                            f"to {modes[-2]} modes (required {args.min_factor:g})")
        for i in range(1, len(d)):
            if d[i] > args.noise * d[i - 1]:
                failures.append(f"{short}: the distance from its richest basis grows from {d[i - 1]:.3e} m "
                                f"({modes[i - 1]} modes) to {d[i]:.3e} m ({modes[i]} modes), more than x{args.noise:g}")
    # 2. The two richest bases agree (reference: the converged run of the other method) up to the
    #    frame dependence of the linear floating-frame model, which is of second order in u.
    relative = agreement / elastic
    print(f"richest bases ({modes[-1]} normal modes): CB against FI {agreement:.3e} m = {relative:.3e} of the "
          f"elastic deflection (bound {args.max_relative:g})")
    if not relative < args.max_relative:
        failures.append(f"the richest CB and FI runs differ by {relative:.3e} of the elastic deflection, more than "
                        f"{args.max_relative:g}")
    if args.stiffer > 0:
        _, agreement_2, elastic_2 = richest_pair(args, modes, args.stiffer, "stiffer_")
        deflection_ratio, distance_ratio = elastic / elastic_2, agreement / agreement_2
        order = math.log(distance_ratio) / math.log(deflection_ratio)
        print(f"Young's moduli x {args.stiffer:g}: elastic deflection {elastic_2:.3e} m, CB against FI "
              f"{agreement_2:.3e} m; the distance falls as the deflection to the power {order:.3g} "
              f"(required >= {args.min_order:g})")
        if not order >= args.min_order:
            failures.append(f"the CB-FI distance falls as the deflection to the power {order:.3g} only, a first-order "
                            f"effect (required >= {args.min_order:g}): a basis error or a mistake in either method")
    # 3. In the linear range the two methods agree to the basis accuracy. With the moduli times
    #    --linear the elastic deflection is that much smaller; a basis error falls like it, the frame
    #    effect (2.) like its square. Reference: the richest run of each method; 'basis accuracy':
    #    the larger of the two methods' distances from their own richest run with modes[1] normal
    #    modes (the second basis of the table), measured in the same stiff scene.
    #    The deflection is 32 times smaller, so the tolerances are 100 times tighter (at the
    #    scene's own, the integrator's error, about 2e-8 m, hides the comparison).
    if args.linear > 0:
        tight = tolerances_times(args, 0.01)
        stiff, agreement_3, elastic_3 = richest_pair(tight, modes, args.linear, "linear_")
        basis = {}
        for method, short in METHODS:
            coarse = run_case(args.flextrack, os.path.join(args.output, f"linear_{short}_{modes[1]}"), method,
                              modes[1], tight, tight.rtol, stiffer=args.linear)
            basis[short] = distance(coarse["path"], stiff[short]["path"])
        accuracy = max(basis.values())
        print(f"Young's moduli x {args.linear:g} (linear range), rtol {tight.rtol:g}: elastic deflection {elastic_3:.3e} m, CB against FI "
              f"{agreement_3:.3e} m; basis error with {modes[1]} modes: CB {basis['CB']:.3e} m, FI "
              f"{basis['FI']:.3e} m (the basis accuracy: {accuracy:.3e} m)")
        if not agreement_3 <= accuracy:
            failures.append(f"in the linear range (moduli x {args.linear:g}) the richest CB and FI runs differ by "
                            f"{agreement_3:.3e} m, more than the {modes[1]}-mode basis error {accuracy:.3e} m")
    for f in failures:
        print("FAILED: " + f)
    if not failures:
        print("passed: both methods converge, to the same motion up to a second-order frame effect, and agree to the "
              "basis accuracy in the linear range")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
