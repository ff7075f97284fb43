#!/usr/bin/env python3
"""Checks the output folder of `flextrack bench` (issue 11): bench.csv with the reference settings
and the error definition in its header, one row per setting of both sweeps (IDA rtol 1e-3 ... 1e-10,
generalised-alpha at 8 steps), bench.png and summary.json. Then the numbers that a correct study
must show, against references that are properties of the methods, not of this code:
  - generalised-alpha is second order (Arnold & Bruls 2007): the observed order of the error
    between two halvings of the step in the asymptotic range is 2 +- 0.3;
  - IDA's error falls with its tolerance: the row at rtol 1e-10 is at least 1e3 times more
    accurate than the one at rtol 1e-4 (BDF's error is proportional to the tolerance).
Usage: check_bench.py OUTPUT_DIR [--run FLEXTRACK SCENE] [--order-rows I J]
  --run: first runs `FLEXTRACK bench SCENE -o OUTPUT_DIR` (the folder is emptied first)
  I, J: generalised-alpha rows (0-based) whose steps differ by a factor 2, in the asymptotic range"""
import csv
import math
import os
import shutil
import re
import subprocess
import sys


def main():
    folder = sys.argv[1]
    i, j = 3, 4
    if "--order-rows" in sys.argv:
        k = sys.argv.index("--order-rows")
        i, j = int(sys.argv[k + 1]), int(sys.argv[k + 2])
    if "--run" in sys.argv:
        k = sys.argv.index("--run")
        shutil.rmtree(folder, ignore_errors=True)
        subprocess.run([sys.argv[k + 1], "bench", sys.argv[k + 2], "-o", folder], check=True)
    with open(os.path.join(folder, "bench.csv")) as f:
        lines = f.read().splitlines()
    header = [l for l in lines if l.startswith("#")]
    assert any(re.search(r"reference: (Radau IIA|IDA) rtol", l) for l in header), "bench.csv: no reference line in the header"
    assert any("error_" in l and "largest distance" in l for l in header), "bench.csv: no error definition in the header"
    rows = list(csv.DictReader(l for l in lines if not l.startswith("#")))
    ida = [r for r in rows if r["method"] == "ida"]
    radau = [r for r in rows if r["method"] == "radau"]
    ga = [r for r in rows if r["method"] == "generalized_alpha"]
    assert len(ida) == 8 and len(radau) == 8 and len(ga) == 8, \
        f"expected 8 + 8 + 8 rows, found {len(ida)} + {len(radau)} + {len(ga)}"
    for name in ("bench.png", "summary.json"):
        assert os.path.getsize(os.path.join(folder, name)) > 0, f"{name} missing or empty"
    print(f"{'method':18} {'setting':18} {'rel. error':>10} {'wall [s]':>9} {'steps':>7}")
    for r in rows:
        print(f"{r['method']:18} {r['setting']:18} {float(r['max_relative_error']):10.2e} "
              f"{float(r['wall_time_s']):9.4f} {r['steps']:>7}")
    e_i, e_j = float(ga[i]["max_relative_error"]), float(ga[j]["max_relative_error"])
    h_i, h_j = float(ga[i]["value"]), float(ga[j]["value"])
    order = math.log(e_i / e_j) / math.log(h_i / h_j)
    print(f"generalised-alpha observed order between steps {h_i:g} and {h_j:g} s: {order:.3f} (expected 2 +- 0.3)")
    assert abs(order - 2) <= 0.3, "generalised-alpha is not second order here"
    for name, runs in (("IDA", ida), ("Radau IIA", radau)):
        e4 = float(next(r for r in runs if r["setting"] == "rtol 1e-04")["max_relative_error"])
        e10 = float(next(r for r in runs if r["setting"] == "rtol 1e-10")["max_relative_error"])
        print(f"{name}: relative error {e4:.2e} at rtol 1e-4, {e10:.2e} at rtol 1e-10 (expected a ratio >= 1e3)")
        assert e4 / e10 >= 1e3, f"{name}'s error does not fall with its tolerance"
    print("bench output checked")


if __name__ == "__main__":
    try:
        main()
    except (AssertionError, OSError, KeyError, ValueError, StopIteration, subprocess.CalledProcessError) as e:
        print(f"check_bench: FAILED: {e}")
        sys.exit(1)
