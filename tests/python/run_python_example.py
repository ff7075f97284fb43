#!/usr/bin/env python3
"""Runs the example of doc/python.md as written (issue 26, item 4) and checks it:
run_python_example.py FLEXTRACK REPO WORK.

The example's python block is run in a copy of the repository's prm/ under WORK (its relative
paths: prm/, src/python/, output/), with FLEXTRACK naming the program under test. Checked
against the program's own files: the printed deviations are sweep.csv's, which are the maxima of
each case's deviation.csv column (recomputed here); the front end's other readers against the
files they read (probes.csv, summary.json, results.h5 by h5py directly); the plot is a PNG.
"""
import csv
import os
import re
import shutil
import subprocess
import sys

EXE, REPO, WORK = (os.path.abspath(x) for x in sys.argv[1:4])
failures = []


def check(condition, what):
    print(("ok: " if condition else "FAILED: ") + what)
    if not condition:
        failures.append(what)


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
shutil.copytree(os.path.join(REPO, "prm"), os.path.join(WORK, "prm"))
os.makedirs(os.path.join(WORK, "src"))
os.symlink(os.path.join(REPO, "src", "python"), os.path.join(WORK, "src", "python"))
with open(os.path.join(REPO, "doc", "python.md")) as f:
    code = re.findall(r"^```python\n(.*?)^```", f.read(), re.S | re.M)
check(len(code) == 1, "doc/python.md has one python block")
env = dict(os.environ, FLEXTRACK=EXE)
p = subprocess.run([sys.executable, "-c", code[0]], cwd=WORK, env=env, capture_output=True, text=True)
print(p.stdout, p.stderr)
check(p.returncode == 0, f"the example ran (exit {p.returncode})")

out = os.path.join(WORK, "output", "python_example")
with open(os.path.join(out, "sweep.csv")) as f:
    table = list(csv.DictReader(f))
printed = re.findall(r"k = (\S+): largest deviation (\S+) mm \((\w+)\)", p.stdout)
check(len(printed) == 5 == len(table), f"five cases printed and in sweep.csv ({len(printed)}, {len(table)})")
for (k, d, status), row in zip(printed, table):
    with open(os.path.join(out, "case_%04d" % int(row["case"]), "deviation.csv")) as f:
        largest = max(float(r["head_deviation_m"]) for r in csv.DictReader(f))
    check(status == "completed" and abs(float(k) - float(row["drive_speed"])) < 1e-12
          and abs(float(d) - 1e3 * largest) <= 5e-5 + 1e-4 * 1e3 * largest,
          f"k = {k}: printed {d} mm is the case's largest deviation.csv value {1e3 * largest:.6f} mm (4 decimals)")
with open(os.path.join(out, "deviation_against_speed.png"), "rb") as f:
    check(f.read(8) == b"\x89PNG\r\n\x1a\n", "the plot is written, a PNG")

# The readers of the front end against the files (h5py and csv directly).
sys.path.insert(0, os.path.join(REPO, "src", "python"))
os.environ["FLEXTRACK"] = EXE
import flextrack  # noqa: E402
import h5py  # noqa: E402
import numpy as np  # noqa: E402

run = flextrack.read_run(os.path.join(out, "case_0003"))
with open(os.path.join(out, "case_0003", "probes.csv")) as f:
    rows = list(csv.DictReader(f))
check(np.array_equal(run.probes["head_x_m"], np.array([float(r["head_x_m"]) for r in rows])), "probes as numpy arrays")
with h5py.File(os.path.join(out, "case_0003", "results.h5"), "r") as f:
    check(np.array_equal(run.results["coordinates"], f["coordinates"][()]), "results.h5 coordinates")
    check(run.results.names["coordinates"] == [n.decode() if isinstance(n, bytes) else n for n in f["coordinates"].attrs["names"]], "column names of coordinates")
check(run.summary["status"] == "completed" and run.status == "completed", "summary.json as a dict")
try:
    flextrack.run(os.path.join(WORK, "prm", "laser_robot.prm"), set={"Multibody/End time": -1}, output=os.path.join(WORK, "bad"))
    check(False, "bad input raises FlexTrackError")
except flextrack.FlexTrackError as e:
    check(e.status == 2 and "End time" in e.message, f"bad input raises FlexTrackError, status 2, naming the entry: {e.message}")
if failures:
    sys.exit("FAILED: " + "; ".join(failures))
print("all checks passed")
