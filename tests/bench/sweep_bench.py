#!/usr/bin/env python3
"""Benchmark of 'flextrack sweep' (issue 26): sweep_bench.py FLEXTRACK MPIRUN REPO OUT [--quick | --machinery-only].

1. Cost of the sweep machinery per case. The study prm/laser_robot_study.prm cut to one basis and
   N cases of about 1 s (--set: End time, no animation), run with -j 1, against the same N runs
   started one by one as `flextrack run SCENE --set ...` processes (what a script does without a
   sweep). Per case: the study's wall time minus the cases' own run time (each case's
   summary.json total_wall_time_s, the run as flextrack measures it), divided by N; the same for
   the script loop (its surplus is mostly the program's start-up). Median of 3 repetitions.
2. Scaling: the full study (15 cases of the 10 s) with -j 1, -j 2, mpirun -np 1 and mpirun -np 2;
   wall time and the speed-up over one process. The reduced bodies are made before the first
   timing (every configuration then finds them in the cache).
Prints the tables; wall times by time.perf_counter around each command.
"""
import csv
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import time

EXE, MPIRUN, REPO, OUT = (os.path.abspath(x) if i != 1 else x for i, x in enumerate(sys.argv[1:5]))
QUICK = "--quick" in sys.argv
MACHINERY_ONLY = "--machinery-only" in sys.argv
STUDY = os.path.join(REPO, "prm", "laser_robot_study.prm")
SCENE = os.path.join(REPO, "prm", "laser_robot.prm")
END = "2"  # s simulated: a case of about 1 s
N = 4 if QUICK else 10


last_log = ""


def timed(cmd):
    global last_log
    t = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t
    if p.returncode != 0:
        sys.exit(f"sweep_bench: {' '.join(cmd)} failed (exit {p.returncode}):\n{p.stdout[-2000:]}{p.stderr[-2000:]}")
    last_log = p.stdout
    return wall


def case_run_times(folder):
    times = []
    for name in sorted(os.listdir(folder)):
        if name.startswith("case_"):
            with open(os.path.join(folder, name, "summary.json")) as f:
                times.append(json.load(f)["total_wall_time_s"])
    return times


shutil.rmtree(OUT, ignore_errors=True)
os.makedirs(OUT)
os.chdir(OUT)
speeds = [f"{0.5 + i * 1.0 / (N - 1):.12g}" for i in range(N)]
one_basis = ["--set", "Study/Set=Output/Animation interval=0; Multibody/End time=" + END,
             "--set", "Parameter modes_of_body_I/Values=8", "--set", "Parameter drive_speed/Values=" + ", ".join(speeds)]
timed([EXE, "sweep", STUDY, *one_basis, "-o", "warm"])  # reduced bodies into ./output/

rows = []
for repetition in range(1 if QUICK else 3):
    folder = f"machinery_{repetition}"
    wall = timed([EXE, "sweep", STUDY, *one_basis, "-j", "1", "-o", folder])
    own = float(re.search(r"the sweep's own work per case: ([0-9.e+-]+) ms", last_log).group(1))
    inside = case_run_times(folder)
    loop = 0.0
    loop_inside = []
    for k, speed in enumerate(speeds):
        run_folder = f"loop_{repetition}_{k}"
        loop += timed([EXE, "run", SCENE, "-o", run_folder, "--set", "Output/Animation interval=0", "--set",
                       "Multibody/End time=" + END, "--set", "Joint slide/Driver=0.4 + 0.8*((1 - cos(%s*pi*t))/2)^2" % speed,
                       "--set", "Body base:Reduction/Number of normal modes=8"])
        with open(os.path.join(run_folder, "summary.json")) as f:
            loop_inside.append(json.load(f)["total_wall_time_s"])
    rows.append((wall, sum(inside), (wall - sum(inside)) / N, loop, sum(loop_inside), (loop - sum(loop_inside)) / N, own))
    with open(os.path.join(folder, "sweep.csv")) as f:
        a = [r["max(head_deviation_m)"] for r in csv.DictReader(f)]
    b = []
    for k in range(N):
        with open(os.path.join(f"loop_{repetition}_{k}", "deviation.csv")) as f:
            b.append(max(float(r["head_deviation_m"]) for r in csv.DictReader(f)))
    if any(abs(float(x) - y) > 1e-12 * y for x, y in zip(a, b)):
        sys.exit("sweep_bench: the study's deviations differ from those of the plain runs")

print(f"\n1. Machinery: {N} cases of {END} s of the laser robot (one basis), -j 1, against {N} 'flextrack run' processes")
print("| | wall [s] | cases' own run time [s] | outside the cases, per case [ms] | share of a case |")
print("|---|---|---|---|---|")
med = lambda k: statistics.median(r[k] for r in rows)
per_case = med(1) / N
print(f"| flextrack sweep -j 1 | {med(0):.2f} | {med(1):.2f} | {1e3 * med(2):.0f} (start-up and checks shared by {N} cases) | {100 * med(2) / per_case:.1f} % |")
print(f"| ... its own work per case (its log) | | | {med(6):.1f} (hand-out, collecting, case.json, sweep.csv) | {0.1 * med(6) / per_case:.2f} % |")
print(f"| a loop of flextrack run | {med(3):.2f} | {med(4):.2f} | {1e3 * med(5):.0f} (a program start each) | {100 * med(5) / (med(4) / N):.1f} % |")
print(f"(median of {len(rows)}; a case runs {per_case:.2f} s inside the program; the same deviations, to 12 digits)")

if not QUICK and not MACHINERY_ONLY:
    print("\n2. Scaling: prm/laser_robot_study.prm, 15 cases of the 10 s, without animation frames")
    print("| how | wall [s] | speed-up |")
    print("|---|---|---|")
    full = ["--set", "Study/Set=Output/Animation interval=0"]
    timed([EXE, "sweep", STUDY, *full, "-j", "2", "-o", "full_warm"])  # the three bases into the cache
    base = None
    for label, cmd in [("-j 1", [EXE, "sweep", STUDY, *full, "-j", "1", "-o", "full_j1"]),
                       ("-j 2", [EXE, "sweep", STUDY, *full, "-j", "2", "-o", "full_j2"]),
                       ("mpirun -np 1", [MPIRUN, "--allow-run-as-root", "--oversubscribe", "-np", "1", EXE, "sweep", STUDY, *full, "-o", "full_mpi1"]),
                       ("mpirun -np 2", [MPIRUN, "--allow-run-as-root", "--oversubscribe", "-np", "2", EXE, "sweep", STUDY, *full, "-o", "full_mpi2"])]:
        wall = timed(cmd)
        base = base or wall
        print(f"| {label} | {wall:.1f} | {base / wall:.2f} |")
    cases = case_run_times("full_j1")
    print(f"(case run times in the -j 1 study: {min(cases):.2f} to {max(cases):.2f} s, median {statistics.median(cases):.2f} s)")
