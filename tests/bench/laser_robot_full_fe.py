#!/usr/bin/env python3
"""Benchmark (ctest label bench): the laser robot with its full FE bases against its reduced
bases, at equal error (issue 24: "runs to the end of at least 1 s, and the speed-up of the reduced
model at equal error is measured, not extrapolated").

Full bases: body I (the hex20 block with arm I, 990 free dofs) reduced with 983 normal modes plus
its 6 interface modes (989 of 990 dofs; Lanczos needs fewer than all) and no track modes (the full
basis holds the static responses already), arm II with 137 normal modes plus 12 interface modes
(149 of its 150 free dofs): 2334 unknowns. Reduced bases: the scene's (8 modes and 8 track
stations on body I, 6 on arm II). Runs, 1 s each, prm/laser_robot.prm otherwise as it is:
  full FE at the scene's tolerances (rtol 1e-6, atol 1e-8) and at rtol 1e-7, atol 1e-9;
  reduced at the scene's tolerances (3 times, median CPU) and at rtol 1e-7, atol 1e-9.
The reference is the full model at rtol 1e-7. Printed per run: CPU (user + system of the whole
process: start-up, reduction or cache, static equilibrium, rigid reference, output), integration
and initial-condition wall times, steps, Jacobians, peak memory, and the largest distance of the
laser head from the reference's at the 101 output times [m].

  laser_robot_full_fe.py FLEXTRACK_EXE REPO WORKDIR
"""
import csv
import json
import math
import os
import re
import statistics
import subprocess
import sys

FULL = ["--set", "Body base:Reduction/Number of normal modes=983", "--set", "Body base:Reduction/Track arms=",
        "--set", "Body arm2:Reduction/Number of normal modes=137"]
TIGHT = ["--set", "Multibody/Integrator/Relative tolerance=1e-7", "--set", "Multibody/Integrator/Absolute tolerance=1e-9"]


def run(exe, scene, out, extra):
    log = out + ".time"
    with open(log, "w") as f:
        status = subprocess.run(["/usr/bin/time", "-v", exe, "run", scene, "-o", out, "--set", "Multibody/End time=1"]
                                + extra, stdout=f, stderr=subprocess.STDOUT).returncode
    text = open(log).read()
    if status != 0:
        print(f"benchmark failed: {out}: exit {status}; see {log}")
        sys.exit(1)
    cpu = float(re.search(r"User time \(seconds\): ([\d.]+)", text).group(1)) + \
        float(re.search(r"System time \(seconds\): ([\d.]+)", text).group(1))
    memory = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1)) / 1024
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    return dict(cpu=cpu, memory=memory, summary=summary, probes=os.path.join(out, "probes.csv"))


def head_path(path):
    with open(path) as f:
        return {round(float(r["time_s"]), 6): (float(r["head_x_m"]), float(r["head_y_m"]), float(r["head_z_m"]))
                for r in csv.DictReader(f)}


def main():
    exe, repo, work = (os.path.abspath(a) for a in sys.argv[1:4])
    os.makedirs(work, exist_ok=True)
    os.chdir(work)
    scene = os.path.join(repo, "prm", "laser_robot.prm")
    runs = {}
    run(exe, scene, "warm_up_reduced", [])  # the reduced bodies into the cache, not timed
    runs["full FE, rtol 1e-7 (reference)"] = run(exe, scene, "full_tight", FULL + TIGHT)
    runs["full FE, rtol 1e-6"] = run(exe, scene, "full", FULL)
    reduced = [run(exe, scene, f"reduced_{i}", []) for i in range(3)]
    cpus = [r["cpu"] for r in reduced]
    median = reduced[cpus.index(statistics.median(cpus))]
    runs["reduced, rtol 1e-6 (median of 3)"] = median
    runs["reduced, rtol 1e-7"] = run(exe, scene, "reduced_tight", TIGHT)
    reference = head_path(runs["full FE, rtol 1e-7 (reference)"]["probes"])
    start = reference[min(reference)]
    extent = max(math.dist(start, p) for p in reference.values())
    print(f"laser head path: extent {extent:.4f} m over 1 s; reference: the full FE model at rtol 1e-7")
    print(f"{'run':36} {'CPU [s]':>8} {'init [s]':>8} {'integr. [s]':>11} {'steps':>6} {'Jacobians':>9} "
          f"{'memory [MiB]':>12} {'head error [m]':>14}")
    for name, r in runs.items():
        path = head_path(r["probes"])
        error = max(math.dist(path[t], reference[t]) for t in reference if t in path)
        r["error"] = error
        wall, integrator = r["summary"]["wall_time_s"], r["summary"]["integrator"]
        print(f"{name:36} {r['cpu']:8.2f} {wall.get('initial conditions', 0):8.2f} {wall['time integration']:11.2f} "
              f"{integrator['steps']:6d} {integrator['jacobian_evaluations']:9d} {r['memory']:12.0f} {error:14.2e}")
    full, red = runs["full FE, rtol 1e-6"], runs["reduced, rtol 1e-6 (median of 3)"]
    print(f"speed-up of the reduced model at the scene's tolerances: {full['cpu'] / red['cpu']:.0f} x "
          f"(head errors {red['error']:.2e} m reduced, {full['error']:.2e} m full FE)")
    tight = runs["full FE, rtol 1e-7 (reference)"]
    print(f"against the full model at rtol 1e-7 (the reference itself, error 0): {tight['cpu'] / red['cpu']:.0f} x")


if __name__ == "__main__":
    main()
