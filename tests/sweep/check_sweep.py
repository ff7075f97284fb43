#!/usr/bin/env python3
"""Checks of 'flextrack sweep' (issue 26): check_sweep.py CHECK FLEXTRACK MPIRUN REPO OUT.

The study is the laser robot's (prm/laser_robot_study.prm: 5 drive speeds x 3 numbers of normal
modes of body I), shortened to 0.3 s of the 10 s and without animation frames by --set, so that
a check takes seconds. References: a case is `flextrack run` of the scene with the case's --set
entries (its probes.csv bitwise equal to that of the plain run); a collected quantity is the
statistic of the case's own CSV column recomputed here (exact: both print the same double);
-j 2 and mpirun -np 2 give the same sweep.csv (every column but CPU and wall time).
"""
import csv
import glob
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

CHECK, EXE, MPIRUN, REPO, OUT = sys.argv[1:6]
EXE, REPO, OUT = (os.path.abspath(x) for x in (EXE, REPO, OUT))
STUDY = os.path.join(REPO, "prm", "laser_robot_study.prm")
SHORT = ["--set", "Study/Set=Output/Animation interval=0; Multibody/End time=0.3"]
failures = []


def check(condition, what):
    print(("ok: " if condition else "FAILED: ") + what)
    if not condition:
        failures.append(what)


def flextrack(*args, expect=0, mpi=0):
    cmd = ([MPIRUN, "--allow-run-as-root", "--oversubscribe", "-np", str(mpi)] if mpi else []) + [EXE] + list(args)
    p = subprocess.run(cmd, capture_output=True, text=True)
    print("$ " + " ".join(cmd) + f"  (exit {p.returncode})\n" + p.stdout + p.stderr)
    check(p.returncode == expect, f"{' '.join(args[:2])}: exit {p.returncode}, expected {expect}")
    return p


def rows(folder):
    with open(os.path.join(folder, "sweep.csv")) as f:
        return list(csv.DictReader(f))


def without_times(table):
    return [{k: v for k, v in r.items() if k not in ("cpu_time_s", "wall_time_s")} for r in table]


def fresh(folder):
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    os.chdir(folder)  # the reduced bodies' caches go to ./output/


def column(path, name):
    with open(path) as f:
        r = list(csv.DictReader(f))
    return [float(x["time_s"]) for x in r], [float(x[name]) for x in r]


def agree():
    fresh(OUT)
    flextrack("sweep", STUDY, *SHORT, "-j", "2", "-o", "by_fork")
    a = rows("by_fork")
    check(len(a) == 15 and all(r["status"] == "completed" for r in a), f"15 cases completed with -j 2 ({len(a)} rows)")
    check([(r["drive_speed"], r["modes_of_body_I"]) for r in a[:4]] == [("0.5", "4"), ("0.5", "8"), ("0.5", "16"), ("0.75", "4")],
          "grid order: the first parameter varies slowest; 0.5:0.25:1.5 gives 0.5, 0.75, ...")
    with open("by_fork/sweep.png", "rb") as f:
        check(f.read(8) == b"\x89PNG\r\n\x1a\n", "sweep.png is a PNG")
    flextrack("sweep", STUDY, *SHORT, "-o", "by_mpi", mpi=2)
    b = rows("by_mpi")
    check(without_times(a) == without_times(b), "mpirun -np 2 writes the same sweep.csv as -j 2 (CPU and wall times aside)")
    # Case 8 (drive speed 1 = the scene's own drive, 8 modes) is the scene run with its --set
    # entries: the same probes.csv, bitwise.
    case = a[7]
    check(case["drive_speed"] == "1" and case["modes_of_body_I"] == "8", "case 8 is drive speed 1, 8 modes")
    flextrack("run", os.path.join(REPO, "prm", "laser_robot.prm"), "-o", "plain", "--set", "Output/Animation interval=0",
              "--set", "Multibody/End time=0.3", "--set", "Joint slide/Driver=0.4 + 0.8*((1 - cos(1*pi*t))/2)^2",
              "--set", "Body base:Reduction/Number of normal modes=8")
    with open("plain/probes.csv") as f, open("by_fork/case_0008/probes.csv") as g:
        check(f.read() == g.read(), "case 8's probes.csv equals that of 'flextrack run' with the same --set entries")
    # The collected quantities against the case's own deviation.csv and summary.json.
    t, d = column("by_fork/case_0008/deviation.csv", "head_deviation_m")
    k = max(range(len(d)), key=lambda i: d[i])
    check(abs(float(case["max(head_deviation_m)"]) - d[k]) <= 1e-12 * d[k], "max(head_deviation_m) is the column's maximum (12 digits)")
    check(float(case["time_of_max(head_deviation_m)"]) == t[k], "time_of_max is the time of that maximum")
    with open("by_fork/case_0008/summary.json") as f:
        check(int(case["integrator/steps"]) == json.load(f)["integrator"]["steps"], "integrator/steps from summary.json")
    # A case rerun reuses nothing but its record: a second sweep runs no case.
    p = flextrack("sweep", STUDY, *SHORT, "-j", "2", "-o", "by_fork")
    check("15 cases finished by an earlier run" in p.stdout and "0 to run" in p.stdout and not re.search(r"case \d+/15:", p.stdout),
          "the same study again runs no case")
    check(without_times(rows("by_fork")) == without_times(a), "... and writes the same sweep.csv")
    # Bodies shared by cases are reduced once: 3 bases (4, 8, 16 modes) and arm II, each once.
    logs = "".join(open(x).read() for x in glob.glob("by_fork/case_*/log.txt"))
    check(len(re.findall(r"base: flexible, \d+ modes, [0-9.]+ kg \(body scene [^)]*reduced to", logs)) == 3,
          "the three bases of body I are each reduced once over 15 cases")


def restart():
    fresh(OUT)
    p = subprocess.Popen([EXE, "sweep", STUDY, *SHORT, "-j", "2", "-o", "killed"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    deadline = time.time() + 600
    while len(glob.glob("killed/case_*/case.json")) < 3 and time.time() < deadline and p.poll() is None:
        time.sleep(0.05)
    p.send_signal(signal.SIGKILL)  # no chance to tidy up: the batch system's time limit
    p.wait()
    time.sleep(1)  # its cases get SIGTERM (PR_SET_PDEATHSIG) and end
    finished = len(glob.glob("killed/case_*/case.json"))
    check(3 <= finished < 15, f"killed after {finished} of 15 cases")
    r = flextrack("sweep", STUDY, *SHORT, "-j", "2", "-o", "killed")
    ran = len(re.findall(r"case \d+/15:", r.stdout))
    check(f"{finished} cases finished by an earlier run" in r.stdout and ran == 15 - finished,
          f"restarted, it runs only the {15 - finished} missing cases (ran {ran})")
    t = rows("killed")
    check(len(t) == 15 and all(x["status"] == "completed" for x in t), "sweep.csv has all 15 cases, completed")


def failed_case():
    fresh(OUT)
    # 2000 normal modes of a body of 990 free dofs: that case's reduction refuses it (bad input);
    # the study goes on and records it.
    flextrack("sweep", STUDY, *SHORT, "--set", "Parameter drive_speed/Values=1", "--set",
              "Parameter modes_of_body_I/Values=4, 2000", "-o", "one_fails")
    t = rows("one_fails")
    check(len(t) == 2 and t[0]["status"] == "completed", "the good case completed")
    check(t[1]["status"] == "bad input" and t[1]["exit_status"] == "2" and "modes" in t[1]["message"]
          and t[1]["max(head_deviation_m)"] == "", f"the failing case is a row with its status and message: {t[1]}")


def bad_study():
    fresh(OUT)
    p = flextrack("sweep", STUDY, *SHORT, "--set", "Parameter modes_of_body_I/Entry=Body base:Reduction/Number of nromal modes",
                  "-o", "bad", expect=2)
    check("case 1" in p.stderr and "nromal" in p.stderr and "Number of normal modes" in p.stderr,
          "an unknown entry is refused before any case runs, naming the case, the entry and the nearest name")
    check(not os.path.exists("bad"), "nothing written")
    p = flextrack("sweep", STUDY, *SHORT, "--set", "Study/Collect=largest(head_deviation_m)", "-o", "bad", expect=2)
    check("largest" in p.stderr and "allowed: max, min" in p.stderr, "an unknown statistic names the allowed ones")
    p = flextrack("sweep", STUDY, *SHORT, "--set", "Parameter drive_speed/Values=1:-1:2", "-o", "bad", expect=2)
    check("Parameter drive_speed/Values" in p.stderr and "never reaches" in p.stderr, "a range that never ends is refused")
    p = flextrack("sweep", STUDY, *SHORT, "--set", "Study/Scene=no_such.prm", "-o", "bad", expect=2)
    check("no_such.prm" in p.stderr, "a missing scene is named")
    p = flextrack("run", STUDY, expect=2)
    check("flextrack sweep" in p.stderr, "'run' on a study says to use 'flextrack sweep'")
    check(not os.path.exists("bad"), "nothing written")


{"agree": agree, "restart": restart, "failed_case": failed_case, "bad_study": bad_study}[CHECK]()
if failures:
    sys.exit("FAILED: " + "; ".join(failures))
print("all checks passed")
