#!/usr/bin/env python3
"""Benchmark (ctest label bench): the laser robot, 10 s simulated, work against precision.

Issue 10, Performance: prm/laser_robot.prm for 10 s, total wall time (process start-up included,
bodies cached) against the laser head's position error, with the peak memory. Targets: error
under 1e-5 m in under 1 s total; at least 100x faster than the same scene with the bodies' full
FE bases at equal error.

  laser_robot_bench.py FLEXTRACK_EXE SOURCE_DIR WORKDIR [--quick] [--cases=M:S:RTOL,...] [--repeats=N]
      [--no-reference] [--reuse-runs] [--reference-rtol=R] [--reference-check=R]
      [--partial-reference=PROBES_CSV]

What it runs (copies of the three scenes in WORKDIR, each body scene with its own
Output/Directory in WORKDIR, so ./output/ of prm/laser_robot.prm is never touched):

  - every scene copy as prm/laser_robot.prm, with 'Rigid reference = false' (no second, rigid
    run) and 'Animation interval = 0' (no VTU frames): only the flexible run and its CSV/HDF5
    results are timed. The integrator tolerances scale together: Absolute tolerance = rtol/100,
    Velocity tolerance = 100 rtol (the scene: 1e-6, 1e-8, 1e-4);
  - bodies reduced once beforehand ('flextrack reduce'; reused while unchanged), so every timed
    run loads them from the cache;
  - reference: body I with 24 normal modes and 16 track stations (the richest basis of
    prm/laser_robot_convergence.prm, 72 reduced modes), rtol 1e-6 (--reference-rtol;
    tighter ones stall after t = 3.3 s, see below); --reference-check=RTOL runs it also at RTOL
    and prints the difference; --partial-reference=PROBES_CSV adds the error against a tighter
    run over the times that file covers;
  - timed runs: body I with (8 normal modes, 8 stations: the scene's basis), (16, 4) and (4, 4),
    each at rtol 1e-3 ... 1e-6 (1e-7 costs 20-30 times 1e-6, see the reference); three runs each under /usr/bin/time -v; the median wall time
    (whole process), the median CPU time (user + system: on a machine shared with other jobs the
    wall time grows with the load, the CPU time much less), the peak resident memory of that run, integration wall time and IDA steps
    from its summary.json; error = max over the 1001 output times of |r_head - r_head,ref|.

--cases (normal modes : track stations : rtol of each case) and --repeats replace the defaults;
--no-reference stops after the timed runs; --reuse-runs takes the runs already in WORKDIR (their
/usr/bin/time logs and results, however many there are per case) instead of running them.

Prints the table and 'target met' / 'target missed' for the 1 s / 1e-5 m target. The full-FE-basis
comparison is not run here (doc/benchmarks.md: its cost was measured separately and
extrapolated). Prints 'benchmark failed' on an error.
"""
import csv
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys

SCENE, BASE, ARM2 = "laser_robot.prm", "laser_robot_base.prm", "laser_robot_arm2.prm"


def fail(msg):
    print("benchmark failed: " + msg, flush=True)
    sys.exit(1)


def set_entry(text, entry, value, path):
    pattern = re.compile(r"^(\s*set\s+" + re.escape(entry) + r"\s*=\s*)([^#\n]*?)(\s*(#.*)?)$", re.MULTILINE)
    if len(pattern.findall(text)) != 1:
        fail("%s: expected exactly one 'set %s = ...'" % (path, entry))
    return pattern.sub(lambda m: m.group(1) + value + m.group(3), text)


def with_output_directory(text, directory):
    return text.rstrip("\n") + "\nsubsection Output\n  set Directory = %s\nend\n" % directory


def read_head(path):
    with open(path) as f:
        return [(float(r["time_s"]), (float(r["head_x_m"]), float(r["head_y_m"]), float(r["head_z_m"])))
                for r in csv.DictReader(f)]


def timed(cmd, log):
    """Runs cmd under /usr/bin/time -v: (exit status, wall [s], peak RSS [MiB], CPU user + system [s])."""
    with open(log, "w") as f:
        subprocess.run(["/usr/bin/time", "-v"] + cmd, stdout=f, stderr=subprocess.STDOUT)
    return parse_time(log)


def parse_time(log):
    """The figures of /usr/bin/time -v at the end of log."""
    text = open(log).read()
    status = re.search(r"Exit status: (\d+)", text)
    m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([\d.]+)", text)
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", text)
    if not m or not rss or not status:
        fail("no /usr/bin/time output in " + log)
    wall = int(m.group(1) or 0) * 3600 + int(m.group(2)) * 60 + float(m.group(3))
    cpu = sum(float(x) for x in re.findall(r"(?:User|System) time \(seconds\): ([\d.]+)", text))
    return int(status.group(1)), wall, int(rss.group(1)) / 1024, cpu


def main():
    if len(sys.argv) < 4:
        fail("usage: laser_robot_bench.py FLEXTRACK_EXE SOURCE_DIR WORKDIR [options, see the file's head]")
    exe, srcdir, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2]), os.path.abspath(sys.argv[3])
    quick = "--quick" in sys.argv[4:]

    def option(name):
        for a in sys.argv[4:]:
            if a.startswith(name + "="):
                return a[len(name) + 1:]
        return None
    os.makedirs(work, exist_ok=True)
    src = {n: open(os.path.join(srcdir, "prm", n)).read() for n in (SCENE, BASE, ARM2)}
    arm2 = with_output_directory(src[ARM2], os.path.join(work, "cache_arm2"))

    def case(modes, stations, rtol, tag):
        """Writes the three scene files of one case into WORKDIR/tag and returns the main scene."""
        d = os.path.join(work, tag)
        os.makedirs(d, exist_ok=True)
        base = set_entry(src[BASE], "Number of normal modes", str(modes), BASE)
        base = set_entry(base, "Track stations", str(stations), BASE)
        base = with_output_directory(base, os.path.join(work, "cache_base_m%d_s%d" % (modes, stations)))
        scene = set_entry(src[SCENE], "End time", "10", SCENE)
        scene = set_entry(scene, "Rigid reference", "false", SCENE)
        scene = set_entry(scene, "Animation interval", "0", SCENE)
        scene = set_entry(scene, "Relative tolerance", "%.0e" % rtol, SCENE)
        scene = set_entry(scene, "Absolute tolerance", "%.0e" % (rtol / 100), SCENE)
        scene = set_entry(scene, "Velocity tolerance", "%.0e" % (rtol * 100), SCENE)
        for name, text in ((SCENE, scene), (BASE, base), (ARM2, arm2)):
            with open(os.path.join(d, name), "w") as f:
                f.write(text)
        return os.path.join(d, SCENE), os.path.join(d, BASE)

    def reduce(base_scene):
        log = os.path.join(os.path.dirname(base_scene), "reduce.log")
        with open(log, "w") as f:
            if subprocess.run([exe, "reduce", base_scene], stdout=f, stderr=subprocess.STDOUT).returncode:
                fail("reduce " + base_scene + ": " + open(log).read()[-2000:])

    def run(scene, out, reuse=False):
        if reuse:
            status, wall, rss, cpu = parse_time(out + ".log")
        else:
            shutil.rmtree(out, ignore_errors=True)
            status, wall, rss, cpu = timed([exe, "run", scene, "-o", out], out + ".log")
        if status != 0:
            return None
        s = json.load(open(os.path.join(out, "summary.json")))
        return dict(wall=wall, rss=rss, cpu=cpu, integration=s["wall_time_s"]["time integration"],
                    steps=s["integrator"]["steps"], jac=s["integrator"]["jacobian_evaluations"],
                    head=read_head(os.path.join(out, "probes.csv")))

    def distance(a, b):
        if [t for t, _ in a] != [t for t, _ in b]:
            fail("output times differ from the reference run")
        return max(math.dist(p, q) for (_, p), (_, q) in zip(a, b))

    # Timed runs first (they do not need the reference), errors once the reference is there.
    cases = [(m, s, r) for m, s in [(8, 8), (16, 4), (4, 4)] for r in [1e-3, 1e-4, 1e-5, 1e-6]]
    repeats = 3
    if quick:
        cases, repeats = [(8, 8, 1e-4), (8, 8, 1e-6)], 1
    if option("--cases"):
        cases = [(int(m), int(s), float(r)) for m, s, r in (c.split(":") for c in option("--cases").split(","))]
    if option("--repeats"):
        repeats = int(option("--repeats"))
    reuse = "--reuse-runs" in sys.argv[4:]
    rows = []
    for modes, stations, rtol in cases:
        tag = "m%d_s%d_rtol%.0e" % (modes, stations, rtol)
        scene, base = case(modes, stations, rtol, tag)
        reduce(base)
        n_red = json.load(open(os.path.join(work, "cache_base_m%d_s%d" % (modes, stations), "summary.json")))["modes"]
        runs = [run(scene, os.path.join(work, tag, "run%d" % i), reuse) for i in range(repeats)
                if not reuse or os.path.exists(os.path.join(work, tag, "run%d.log" % i))]
        if not runs:
            fail("--reuse-runs: no run of " + tag)
        if any(r is None for r in runs):
            print("%d modes, %d stations, rtol %.0e: failed (%s)" % (modes, stations, rtol, os.path.join(work, tag)),
                  flush=True)
            continue
        med = sorted(runs, key=lambda r: r["wall"])[len(runs) // 2]
        rows.append(dict(modes=modes, stations=stations, reduced=n_red, rtol=rtol, wall=med["wall"],
                         walls=[r["wall"] for r in runs], cpu=statistics.median(r["cpu"] for r in runs),
                         rss=med["rss"], integration=med["integration"],
                         steps=med["steps"], jac=med["jac"], head=med["head"]))
        print("%d modes, %d stations, rtol %.0e: walls %s s, CPU %s s"
              % (modes, stations, rtol, " ".join("%.2f" % r["wall"] for r in runs),
                 " ".join("%.2f" % r["cpu"] for r in runs)), flush=True)

    if "--no-reference" in sys.argv[4:]:
        return

    # Reference: the richest basis at rtol 1e-6 (kept between runs of the benchmark while its scene
    # files are unchanged); with --reference-check=RTOL also at that tolerance, and the difference.
    # Tighter references stall: with 72 modes rtol 1e-9 reached t = 3.5 s after 26 min, rtol 1e-7
    # 3.35 s after 4 min (IDA fails the error test on most steps from there on); doc/benchmarks.md.
    ref_rtol = float(option("--reference-rtol") or 1e-6)
    reference = {}
    for rtol in [ref_rtol] + ([float(option("--reference-check"))] if option("--reference-check") else []):
        tag = "reference_rtol%.0e" % rtol
        scene, base = case(24, 16, rtol, tag)
        reduce(base)
        out = os.path.join(work, tag, "run")
        stamp = os.path.join(work, tag, "inputs")
        inputs = "".join(open(os.path.join(work, tag, n)).read() for n in (SCENE, BASE, ARM2)) + exe
        if os.path.exists(stamp) and open(stamp).read() == inputs and os.path.exists(os.path.join(out, "probes.csv")):
            print("reference rtol %.0e: reused %s" % (rtol, out), flush=True)
        else:
            if run(scene, out) is None:
                fail("reference run " + tag + ": " + open(out + ".log").read()[-2000:])
            open(stamp, "w").write(inputs)
        s = json.load(open(os.path.join(out, "summary.json")))
        reference[rtol] = dict(head=read_head(os.path.join(out, "probes.csv")),
                               integration=s["wall_time_s"]["time integration"], steps=s["integrator"]["steps"])
        print("reference rtol %.0e (24 normal modes, 16 stations, 72 reduced modes): integration %.1f s, %d steps"
              % (rtol, reference[rtol]["integration"], reference[rtol]["steps"]), flush=True)
    ref = reference[ref_rtol]["head"]
    for rtol in reference:
        if rtol != ref_rtol:
            print("reference's integration error, estimated as |rtol %.0e - rtol %.0e|: %.2e m"
                  % (rtol, ref_rtol, distance(reference[rtol]["head"], ref)), flush=True)

    # --partial-reference=PROBES_CSV: a tighter reference over the times it covers (e.g. the rows a
    # stopped rtol 1e-9 run had written); a second error column over that window.
    partial = read_head(option("--partial-reference")) if option("--partial-reference") else None
    if partial:
        print("partial reference %s: t <= %g s; the reference's own error there: %.2e m"
              % (option("--partial-reference"), partial[-1][0], distance(ref[:len(partial)], partial)))
    print("\n%6s %8s %8s %7s %13s %12s %11s %12s %8s %6s %11s %11s"
          % ("modes", "stations", "reduced", "rtol", "wall med [s]", "CPU med [s]", "peak [MiB]", "integr. [s]",
             "steps", "Jacs", "error [m]", "err. part."))
    for r in rows:
        r["error"] = distance(r["head"], ref)
        r["error_partial"] = distance(r["head"][:len(partial)], partial) if partial else float("nan")
        print("%6d %8d %8d %7.0e %13.2f %12.2f %11.1f %12.2f %8d %6d %11.2e %11.2e"
              % (r["modes"], r["stations"], r["reduced"], r["rtol"], r["wall"], r["cpu"], r["rss"], r["integration"],
                 r["steps"], r["jac"], r["error"], r["error_partial"]))
    with open(os.path.join(work, "work_precision.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["normal_modes", "track_stations", "reduced_modes", "rtol", "wall_median_s", "walls_s",
                    "cpu_median_s", "peak_MiB", "integration_s", "steps", "jacobians", "error_m", "error_partial_m"])
        for r in rows:
            w.writerow([r["modes"], r["stations"], r["reduced"], "%.0e" % r["rtol"], "%.3f" % r["wall"],
                        " ".join("%.2f" % x for x in r["walls"]), "%.2f" % r["cpu"], "%.1f" % r["rss"], "%.3f" % r["integration"],
                        r["steps"], r["jac"], "%.3e" % r["error"], "%.3e" % r["error_partial"]])
    within = [r for r in rows if r["error"] < 1e-5]
    if within:
        best = min(within, key=lambda r: r["wall"])
        print("\nfastest run with error < 1e-5 m: %d modes, %d stations, rtol %.0e: %.2f s total (CPU %.2f s), error %.2e m"
              % (best["modes"], best["stations"], best["rtol"], best["wall"], best["cpu"], best["error"]))
        print("target (error < 1e-5 m in < 1 s total): %s" % ("target met" if best["wall"] < 1 else "target missed"))
    else:
        print("\nno run within 1e-5 m: target missed")
    print("table: " + os.path.join(work, "work_precision.csv"))


if __name__ == "__main__":
    main()
