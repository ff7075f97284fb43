#!/usr/bin/python3
"""Reruns are bitwise identical (issue 11, item 4; doc/testing.md).

The same command on the same input, run twice from scratch, must write the same numbers: every
CSV byte for byte, and every dataset and attribute of every HDF5 file with the same type, shape
and bytes. Files that hold wall times or peak memory (summary.json) and the human-readable logs are
not compared. The reference is the first run itself: determinism needs no other.

Cases (short, so the test costs seconds):
  slider_crank      'flextrack run' of prm/slider_crank.prm (rigid, closed loop), End time 0.5 s
  flexible_pendulum 'flextrack run' of prm/flexible_pendulum.prm (a reduced flexible body on a
                    revolute joint), End time 0.2 s; each run reduces its body afresh (no cache)
  reduce            'flextrack reduce' of prm/curved_boom_body.prm into two folders (both reduce)

usage: expect_identical_reruns.py FLEXTRACK SOURCE_DIR WORK_DIR
"""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

exe, source, work = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


def wrapper(name, scene, overrides):
    """A scene that includes SOURCE/prm/SCENE and changes some entries (absolute paths, so that
    the included scene's relative file names are not needed)."""
    path = os.path.join(work, name + ".prm")
    with open(path, "w") as f:
        f.write(f"include {os.path.join(source, 'prm', scene)}\n{overrides}")
    return path


def run(args, cwd):
    p = subprocess.run([exe] + args, cwd=cwd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"FAILED: flextrack {' '.join(args)} exited with {p.returncode}: {p.stderr.strip()}")


def h5_items(path):
    """name -> (kind, dtype, shape, bytes) of every dataset and attribute of an HDF5 file."""
    items = {}

    def attributes(name, obj):
        for key, value in obj.attrs.items():
            a = np.asarray(value)
            items[f"{name}@{key}"] = ("attribute", str(a.dtype), a.shape, a.tobytes())

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset):
            d = obj[()]
            a = np.asarray(d)
            items[name] = ("dataset", str(a.dtype), a.shape, a.tobytes())
        attributes(name, obj)

    with h5py.File(path, "r") as f:
        attributes("/", f)
        f.visititems(visit)
    return items


def compare(case, first, second):
    files = sorted(f for f in os.listdir(first) if f.endswith((".csv", ".h5")))
    if not files:
        failures.append(f"{case}: no CSV or HDF5 results in {first}")
        return
    for name in files:
        a, b = os.path.join(first, name), os.path.join(second, name)
        if not os.path.exists(b):
            failures.append(f"{case}: {name} missing from the second run")
        elif name.endswith(".csv"):
            with open(a, "rb") as fa, open(b, "rb") as fb:
                da, db = fa.read(), fb.read()
            if da != db:
                rows = [i for i, (x, y) in enumerate(zip(da.split(b"\n"), db.split(b"\n"))) if x != y]
                failures.append(f"{case}: {name} differs (first differing row {rows[0] if rows else 'at the end'})")
            else:
                rows = da.count(b"\n")
                print(f"{case}: {name} identical ({rows} rows)")
        else:
            ia, ib = h5_items(a), h5_items(b)
            differing = sorted(k for k in ia.keys() | ib.keys() if ia.get(k) != ib.get(k))
            values = sum(int(np.prod(v[2])) for v in ia.values())
            if differing:
                failures.append(f"{case}: {name}: {len(differing)} of {len(ia)} datasets/attributes differ, e.g. "
                                + ", ".join(differing[:5]))
            else:
                print(f"{case}: {name} identical ({len(ia)} datasets and attributes, {values} values)")


# 1. A rigid closed-loop mechanism.
scene = wrapper("slider_crank", "slider_crank.prm", "subsection Multibody\n  set End time = 0.5\nend\n")
for k in (1, 2):
    run(["run", scene, "-o", os.path.join(work, f"slider_crank_{k}")], work)
compare("slider_crank", os.path.join(work, "slider_crank_1"), os.path.join(work, "slider_crank_2"))

# 2. A flexible body, reduced afresh by each run: its reduced-body cache (output/curved_boom_body
#    under the working folder) is removed before each.
scene = wrapper("flexible_pendulum", "flexible_pendulum.prm",
                "subsection Multibody\n  set End time = 0.2\nend\n"
                f"subsection Body boom\n  set Body scene = {os.path.join(source, 'prm', 'curved_boom_body.prm')}\nend\n")
for k in (1, 2):
    shutil.rmtree(os.path.join(work, "output"), ignore_errors=True)
    run(["run", scene, "-o", os.path.join(work, f"flexible_pendulum_{k}")], work)
    shutil.copy(os.path.join(work, "output", "curved_boom_body", "reduced_body.h5"),
                os.path.join(work, f"flexible_pendulum_{k}", "reduced_body.h5"))
compare("flexible_pendulum", os.path.join(work, "flexible_pendulum_1"), os.path.join(work, "flexible_pendulum_2"))

# 3. The reduction alone, into two folders (the cache of one is not seen by the other).
for k in (1, 2):
    run(["reduce", os.path.join(source, "prm", "curved_boom_body.prm"), "-o", os.path.join(work, f"reduce_{k}")], work)
compare("reduce", os.path.join(work, "reduce_1"), os.path.join(work, "reduce_2"))

if failures:
    print("\n".join("FAILED: " + f for f in failures))
    sys.exit(1)
print("all reruns bitwise identical")
