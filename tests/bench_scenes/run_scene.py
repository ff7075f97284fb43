"""Runs a scene of prm/bench with 'flextrack run' and checks what it wrote (tests/bench_scenes.cmake).

Usage: run_scene.py EXE SCENE OUT [--end T] [--alpha-step H] [--extreme COLUMN min|max VALUE REL
                    TIME TIME_TOL] [--bounded-after COLUMN T BOUND]

The scene is run through a wrapper file written into OUT's parent folder: it includes the scene
(by its absolute path), sets 'Multibody/End time' to T when --end is given, and gives every
flexible body's 'Body scene' again as an absolute path, because flextrack resolves a body scene
against the folder of the scene it runs (the wrapper's), not of the file that names it. With
--alpha-step the scene runs a second time with generalised-alpha at that fixed step [s].
Every run must complete (exit 0, summary.json status 'completed', end time reached) and write
finite probe values at every output row. --extreme: the smallest (min) or largest (max) value of
a probes.csv column, refined by a parabola through the three samples around it, must lie within
REL (relative) of VALUE, at a time within TIME_TOL [s] of TIME (may be given more than once). --bounded-after: |COLUMN| < BOUND
after time T [s]. The references and their tolerances are given by the caller, next to the test.
"""
import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys

# The scene-file helpers of the stress tests (include expansion, the body scenes of a scene).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "stress"))
from stress_runs import body_scenes  # noqa: E402


def check(condition, message):
    print(("ok:   " if condition else "FAIL: ") + message)
    if not condition:
        sys.exit(1)


def wrapper(scene, path, end, alpha_step):
    text = [f"# Written by tests/bench_scenes/run_scene.py: {os.path.basename(scene)} as it stands, except:",
            f"include {scene}"]
    if end is not None:
        text += ["subsection Multibody", f"  set End time = {end!r}", "end"]
    if alpha_step is not None:
        text += ["subsection Multibody", "  subsection Integrator", "    set Method = generalized_alpha",
                 f"    set Step = {alpha_step!r}", "    set Maximum Newton iterations = 10", "  end", "end"]
    for body, body_scene in body_scenes(scene).items():
        text += [f"subsection Body {body}", f"  set Body scene = {body_scene}", "end"]
    with open(path, "w") as f:
        f.write("\n".join(text) + "\n")


def run(exe, scene, out, end, alpha_step, label):
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    prm = out + ".prm"
    wrapper(scene, prm, end, alpha_step)
    p = subprocess.run([exe, "run", prm, "-o", out], capture_output=True, text=True)
    print(p.stdout[-2000:])
    print(p.stderr[-2000:], file=sys.stderr)
    check(p.returncode == 0, f"{label}: exit status {p.returncode} (0 expected)")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    check(summary["status"] == "completed", f"{label}: summary.json status '{summary['status']}'")
    check(abs(summary["time_reached_s"] - summary["end_time_s"]) <= 1e-9 * max(1.0, abs(summary["end_time_s"])),
          f"{label}: reached t = {summary['time_reached_s']} s of {summary['end_time_s']} s")
    with open(os.path.join(out, "probes.csv")) as f:
        rows = list(csv.DictReader(f))
    check(len(rows) >= 2, f"{label}: probes.csv has {len(rows)} rows")
    bad = [(r["time_s"], k) for r in rows for k, v in r.items() if not math.isfinite(float(v))]
    check(not bad, f"{label}: every probe value finite" + (f" (first bad: t = {bad[0][0]} s, {bad[0][1]})" if bad else ""))
    print(f"      {label}: {summary['integrator']['steps']} steps, integration "
          f"{summary['wall_time_s'].get('time integration', float('nan')):.3f} s wall")
    return rows


def extreme(rows, column, kind):
    """(value, time) of the smallest or largest sample of @p column, refined by the parabola
    through it and its two neighbours."""
    t = [float(r["time_s"]) for r in rows]
    y = [float(r[column]) for r in rows]
    pick = min if kind == "min" else max
    i = pick(range(len(y)), key=lambda k: y[k])
    if i == 0 or i == len(y) - 1:
        return y[i], t[i]
    a, b, c = y[i - 1], y[i], y[i + 1]
    curvature = a - 2 * b + c
    shift = 0.5 * (a - c) / curvature if curvature != 0 else 0.0
    return b - 0.25 * (a - c) * shift, t[i] + shift * (t[i + 1] - t[i])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe")
    ap.add_argument("scene")
    ap.add_argument("out")
    ap.add_argument("--end", type=float)
    ap.add_argument("--alpha-step", type=float)
    ap.add_argument("--extreme", nargs=6, action="append", default=[],
                    metavar=("COLUMN", "KIND", "VALUE", "REL", "TIME", "TIME_TOL"))
    ap.add_argument("--bounded-after", nargs=3, metavar=("COLUMN", "T", "BOUND"))
    a = ap.parse_args()
    scene = os.path.abspath(a.scene)
    rows = run(a.exe, scene, a.out, a.end, None, "IDA")
    if a.alpha_step is not None:
        run(a.exe, scene, a.out + "_alpha", a.end, a.alpha_step, f"generalised-alpha, step {a.alpha_step} s")
    for e in a.extreme:
        column, kind = e[0], e[1]
        value, rel, time, time_tol = (float(x) for x in e[2:])
        v, t = extreme(rows, column, kind)
        check(abs(v - value) <= rel * abs(value),
              f"{kind} of {column}: {v:.7g} (reference {value:.7g}, relative difference {v / value - 1:.2e}, tolerance {rel:g})")
        check(abs(t - time) <= time_tol, f"... at t = {t:.4f} s (reference {time} s, tolerance {time_tol} s)")
    if a.bounded_after:
        column, after, bound = a.bounded_after[0], float(a.bounded_after[1]), float(a.bounded_after[2])
        largest = max(abs(float(r[column])) for r in rows if float(r["time_s"]) > after)
        check(largest < bound, f"max |{column}| after t = {after} s: {largest:.3g} (bound {bound})")


if __name__ == "__main__":
    main()
