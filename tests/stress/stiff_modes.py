#!/usr/bin/env python3
"""Stress test (issue 11 item 4, label stress): an undamped 1e5 Hz mode next to slow rigid motion
(tests/stress/stiff_mode.prm: a large-amplitude pendulum carrying a 10 g sensor on a stiff spring,
started with a 1 nm stretch, below the tolerances). Runs IDA with maximum order 1 ... 5 and
generalised-alpha with rho_inf 0, 0.5, 0.8, 1 (step 1 ms), and prints per setting the steps, wall
time, the largest relative energy-balance error over the run (the scene has no damping and no
applied work: the exact energy is constant) and the stiff mode's amplitude (the sensor's distance
from its initial place on the bob) over the first 10 ms and the last 100 ms.
Asserted (reference: conservation of energy of the undamped scene; the stiff mode's initial
amplitude):
  - every run completes, with finite results;
  - generalised-alpha with rho_inf <= 0.8 (numerical damping of modes far above 1 / step) keeps the
    energy balance within 1e-4 and does not amplify the stiff mode (last amplitude below 1e-8 m,
    ten times its start);
IDA's and rho_inf = 1's rows are measured and printed, not asserted: see doc/benchmarks.md
("Numerical stability") for what they show.
Usage: stiff_modes.py FLEXTRACK OUTPUT_DIR"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import time

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "stiff_mode.prm")
SETTINGS = [(f"ida, maximum order {k}", [f"Maximum order = {k}"]) for k in range(1, 6)] + \
           [(f"generalised-alpha, rho_inf {r}", ["Method = generalized_alpha", "Step = 1e-3",
                                                 f"Spectral radius at infinity = {r}"]) for r in (0, 0.5, 0.8, 1)]


def stiff_amplitude(probes, t0, t1):
    with open(probes) as f:
        rows = list(csv.reader(f))
    h = rows[0]
    ix, iy = h.index("sensor_on_bob_x_m"), h.index("sensor_on_bob_y_m")
    x0, y0 = float(rows[1][ix]), float(rows[1][iy])
    values = [math.hypot(float(r[ix]) - x0, float(r[iy]) - y0) for r in rows[1:] if t0 <= float(r[0]) <= t1]
    if any(not math.isfinite(float(v)) for r in rows[1:] for v in r):
        raise AssertionError(f"{probes}: non-finite values")
    return max(values)


def main():
    exe, out = sys.argv[1], sys.argv[2]
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    failures = []
    print(f"{'setting':34} {'steps':>6} {'wall [s]':>8} {'energy balance':>14} {'amplitude 0-10 ms':>17} {'last 100 ms':>11}")
    for label, entries in SETTINGS:
        name = label.replace(", ", "_").replace(" ", "_")
        prm = os.path.join(out, name + ".prm")
        with open(prm, "w") as f:
            f.write(f"include {SCENE}\nsubsection Multibody\n  subsection Integrator\n")
            f.write("".join(f"    set {e}\n" for e in entries))
            f.write("  end\nend\n")
        start = time.monotonic()
        proc = subprocess.run([exe, "run", prm, "-o", os.path.join(out, name)], capture_output=True, text=True)
        wall = time.monotonic() - start
        if proc.returncode != 0:
            failures.append(f"{label}: exit {proc.returncode}: {proc.stderr.strip()[-300:]}")
            continue
        with open(os.path.join(out, name, "summary.json")) as f:
            summary = json.load(f)
        energy = summary["max_over_output_rows"]["relative_energy_balance_error"]
        steps = summary["integrator"]["steps"]
        probes = os.path.join(out, name, "probes.csv")
        first, last = stiff_amplitude(probes, 0, 0.01), stiff_amplitude(probes, 1.9, 2.0)
        print(f"{label:34} {steps:6.0f} {wall:8.2f} {energy:14.2e} {first:17.2e} {last:11.2e}")
        if energy is None or not math.isfinite(energy):
            failures.append(f"{label}: energy balance not finite")
        if label.startswith("generalised-alpha") and not label.endswith(" 1"):
            if abs(energy) > 1e-4:
                failures.append(f"{label}: energy balance {energy:.2e} > 1e-4")
            if last > 1e-8:
                failures.append(f"{label}: stiff amplitude {last:.2e} m > 1e-8 m (started at 1e-9 m)")
    for f in failures:
        print("FAILED:", f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
