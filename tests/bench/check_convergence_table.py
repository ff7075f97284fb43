#!/usr/bin/env python3
"""The laser robot's convergence table of doc/validation.md reproduced by its study (issue 26,
item 3): check_convergence_table.py FLEXTRACK REPO OUT.

Runs `flextrack sweep prm/laser_robot_convergence.prm -j 2` and compares every row of the table
under "Laser robot: convergence with the basis of body I" with sweep.csv, to the digits printed
there: reduced modes and steps exactly, the deviation in mm to 4 decimals, its time to the
printed 0.01 s, the difference from the richest case to its 3 significant digits. The
integration wall times are measurements and are not compared.
"""
import csv
import os
import re
import shutil
import subprocess
import sys

EXE, REPO, OUT = (os.path.abspath(x) for x in sys.argv[1:4])
shutil.rmtree(OUT, ignore_errors=True)
os.makedirs(OUT)
p = subprocess.run([EXE, "sweep", os.path.join(REPO, "prm", "laser_robot_convergence.prm"), "-j", "2", "-o", "study"],
                   cwd=OUT, capture_output=True, text=True)
print(p.stdout, p.stderr)
if p.returncode != 0:
    sys.exit(f"the study failed (exit {p.returncode})")
with open(os.path.join(OUT, "study", "sweep.csv")) as f:
    rows = list(csv.DictReader(f))
with open(os.path.join(REPO, "doc", "validation.md")) as f:
    text = f.read()
section = text[text.index("## Laser robot: convergence with the basis of body I"):]
section = section[:section.index("\n## ", 5)]
table = [[c.strip() for c in line.strip("|").split("|")] for line in section.splitlines()
         if re.match(r"\|\s*\d", line)]
failures = []
if len(table) != len(rows):
    failures.append(f"{len(table)} table rows, {len(rows)} cases")
for printed, row in zip(table, rows):
    modes, stations, reduced, deviation_mm, at, diff, steps = printed[:7]
    case = f"{row['normal_modes']} modes, {row['track_stations']} stations"
    d = float(row["difference(head)"])
    got = [row["normal_modes"], row["track_stations"], row["modes_per_body/base"],
           f"{1e3 * float(row['max(head_deviation_m)']):.4f}", f"{float(row['time_of_max(head_deviation_m)']):g}",
           "0" if d == 0 else f"{d:.2e}", row["integrator/steps"]]
    want = [modes.split()[0], stations.split()[0], reduced, deviation_mm, at, diff, steps]
    status = "ok" if got == want else "DIFFERS"
    print(f"{status}: {case}: table {want[2:]}, study {got[2:]}")
    if got != want:
        failures.append(case)
if failures:
    sys.exit("FAILED: " + "; ".join(failures))
print("the study reproduces the table to the digits printed")
