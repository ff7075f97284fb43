#!/usr/bin/env python3
"""Convergence of the laser robot's head deviation with the basis of body I (issue 10 item 5).

For every pair (number of normal modes, number of track stations) of body I (the base with arm
I, prm/laser_robot_base.prm) this script copies the three scene files of the laser robot
(prm/laser_robot.prm, prm/laser_robot_base.prm, prm/laser_robot_arm2.prm) into a folder of its
own under OUT, with

  - body I's 'Reduction/Number of normal modes' and 'Reduction/Track stations' changed,
  - the main scene's 'Multibody/End time' set to --end-time, 'Rigid reference = true' and
    'Output/Animation interval = 0' (no VTU frames),
  - the body scenes' 'Output/Directory' set inside OUT (body I: one cache per case, reduced afresh
    on every study; arm II: one cache shared by all cases, reduced once before the first case),
    so that the study never touches the caches of prm/laser_robot.prm in ./output/,

reduces body I ('flextrack reduce', its summary.json gives the number of reduced modes and the
reduction wall time), runs the scene ('flextrack run', the body taken from the cache) and writes
OUT/convergence.csv, one row per case:

  normal_modes, track_stations, reduced_modes   body I's basis (reduced_modes: normal + interface
                                                 constraint + track load modes kept)
  max_deviation_m, at_time_s                    the laser head's largest distance from the path of
                                                 the all-rigid scene (deviation.csv)
  max_diff_from_richest_m                       max over the output times of |r - r_richest|, the
                                                 head's distance from its position in the run with
                                                 the most modes and stations (same times)
  reduction_s                                   total wall time of 'flextrack reduce' of body I
                                                 (its summary.json; process start-up excluded)
  integration_s, steps                          'time integration' wall time and IDA steps of the
                                                 flexible run (summary.json; the rigid reference
                                                 run is not included)

The integrator settings are those of prm/laser_robot.prm. Run from the repository root:

  nice python3 tests/bench/laser_robot_convergence.py --end-time 4

(defaults: ./build/flextrack, prm/, OUT = output/laser_robot_convergence, modes 4,8,16,24,
stations 4,8,16).
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

SCENE = "laser_robot.prm"
BASE = "laser_robot_base.prm"
ARM2 = "laser_robot_arm2.prm"


def set_entry(text, entry, value, path):
    """Replace the value of 'set ENTRY = ...' (exactly one occurrence) keeping a trailing comment."""
    pattern = re.compile(r"^(\s*set\s+" + re.escape(entry) + r"\s*=\s*)([^#\n]*?)(\s*(#.*)?)$",
                         re.MULTILINE)
    matches = pattern.findall(text)
    if len(matches) != 1:
        sys.exit("laser_robot_convergence: %s: expected one 'set %s = ...', found %d"
                 % (path, entry, len(matches)))
    return pattern.sub(lambda m: m.group(1) + value + m.group(3), text)


def with_output_directory(text, directory, path):
    if re.search(r"^\s*subsection\s+Output\s*$", text, re.MULTILINE):
        sys.exit("laser_robot_convergence: %s already has an Output subsection" % path)
    return text.rstrip("\n") + "\nsubsection Output\n  set Directory = %s\nend\n" % directory


def run(cmd, log):
    with open(log, "w") as f:
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        sys.stdout.write(open(log).read()[-3000:])
        sys.exit("laser_robot_convergence: '%s' failed (exit %d), log %s"
                 % (" ".join(cmd), r.returncode, log))


def read_head(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [(float(r["time_s"]), (float(r["head_x_m"]), float(r["head_y_m"]), float(r["head_z_m"])))
            for r in rows]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--flextrack", default="build/flextrack")
    ap.add_argument("--scenes", default="prm", help="folder with the three laser robot scenes")
    ap.add_argument("--out", default="output/laser_robot_convergence")
    ap.add_argument("--modes", default="4,8,16,24")
    ap.add_argument("--stations", default="4,8,16")
    ap.add_argument("--end-time", type=float, default=10.0, help="simulated time [s]")
    a = ap.parse_args()
    exe = os.path.abspath(a.flextrack)
    out = os.path.abspath(a.out)
    modes = [int(x) for x in a.modes.split(",")]
    stations = [int(x) for x in a.stations.split(",")]
    src = {n: open(os.path.join(a.scenes, n)).read() for n in (SCENE, BASE, ARM2)}
    os.makedirs(out, exist_ok=True)

    scene = src[SCENE]
    scene = set_entry(scene, "End time", repr(a.end_time), SCENE)
    scene = set_entry(scene, "Rigid reference", "true", SCENE)
    scene = set_entry(scene, "Animation interval", "0", SCENE)
    arm2 = with_output_directory(src[ARM2], os.path.join(out, "cache_arm2"), ARM2)

    started = time.time()
    cases = []
    for m in modes:
        for s in stations:
            tag = "m%d_s%d" % (m, s)
            d = os.path.join(out, tag)
            shutil.rmtree(d, ignore_errors=True)
            os.makedirs(d)
            base = set_entry(src[BASE], "Number of normal modes", str(m), BASE)
            base = set_entry(base, "Track stations", str(s), BASE)
            base = with_output_directory(base, os.path.join(d, "cache_base"), BASE)
            for name, text in ((SCENE, scene), (BASE, base), (ARM2, arm2)):
                with open(os.path.join(d, name), "w") as f:
                    f.write(text)
            # Body I reduced on its own (timed); arm II reduced by the first case, then cached.
            run([exe, "reduce", os.path.join(d, BASE)], os.path.join(d, "reduce.log"))
            red = json.load(open(os.path.join(d, "cache_base", "summary.json")))
            if red.get("loaded_from_cache"):
                sys.exit("laser_robot_convergence: %s: body I came from a cache" % tag)
            run([exe, "run", os.path.join(d, SCENE), "-o", os.path.join(d, "run")],
                os.path.join(d, "run.log"))
            summ = json.load(open(os.path.join(d, "run", "summary.json")))
            if summ["status"] != "completed":
                sys.exit("laser_robot_convergence: %s: run %s" % (tag, summ["status"]))
            dev = summ["rigid_reference"]["largest_deviation"][0]
            cases.append(dict(
                normal_modes=m, track_stations=s, reduced_modes=red["modes"],
                max_deviation_m=dev["max_deviation_m"], at_time_s=dev["at_time_s"],
                reduction_s=red["total_wall_time_s"],
                integration_s=summ["wall_time_s"]["time integration"],
                steps=summ["integrator"]["steps"],
                head=read_head(os.path.join(d, "run", "probes.csv"))))
            c = cases[-1]
            print("%3d modes %3d stations: %3d reduced modes, max deviation %.6e m at %.2f s, "
                  "reduction %.2f s, integration %.2f s (%d steps)"
                  % (m, s, c["reduced_modes"], c["max_deviation_m"], c["at_time_s"],
                     c["reduction_s"], c["integration_s"], c["steps"]), flush=True)

    richest = max(cases, key=lambda c: (c["normal_modes"], c["track_stations"]))
    fields = ["normal_modes", "track_stations", "reduced_modes", "max_deviation_m", "at_time_s",
              "max_diff_from_richest_m", "reduction_s", "integration_s", "steps"]
    with open(os.path.join(out, "convergence.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(fields)
        for c in cases:
            if [t for t, _ in c["head"]] != [t for t, _ in richest["head"]]:
                sys.exit("laser_robot_convergence: output times differ between runs")
            c["max_diff_from_richest_m"] = max(
                math.dist(p, q) for (_, p), (_, q) in zip(c["head"], richest["head"]))
            w.writerow([c["normal_modes"], c["track_stations"], c["reduced_modes"],
                        "%.6e" % c["max_deviation_m"], "%.2f" % c["at_time_s"],
                        "%.3e" % c["max_diff_from_richest_m"], "%.3f" % c["reduction_s"],
                        "%.2f" % c["integration_s"], c["steps"]])
    print("\n| normal modes | track stations | reduced modes | max deviation [mm] | at [s] "
          "| max diff. from richest [m] | reduction [s] | integration [s] |")
    print("|---|---|---|---|---|---|---|---|")
    for c in cases:
        print("| %d | %d | %d | %.4f | %.2f | %.2e | %.2f | %.2f |"
              % (c["normal_modes"], c["track_stations"], c["reduced_modes"],
                 1e3 * c["max_deviation_m"], c["at_time_s"], c["max_diff_from_richest_m"],
                 c["reduction_s"], c["integration_s"]))
    print("\nEnd time %g s; %d cases in %.0f s wall; %s"
          % (a.end_time, len(cases), time.time() - started, os.path.join(out, "convergence.csv")))


if __name__ == "__main__":
    main()
