#!/usr/bin/env python3
"""Benchmark (ctest label bench): the laser robot's work-precision with its default integrator.

Issue 24's acceptance ("work-precision on ... the laser robot, rtol 1e-3 ... 1e-10"):
prm/laser_robot.prm for 10 s as a user writes it, without its Integrator subsection (the
tuned IDA settings): `Method = auto` then chooses Radau IIA for the elastic modes, and the log
says so. No rigid reference, no animation; the bodies as in prm/, reduced once beforehand into
WORKDIR. Runs at rtol 1e-3 ... 1e-10 with Absolute tolerance = rtol / 100 (the velocity
tolerances automatic), one run each, and a reference at rtol 1e-11 (atol 1e-13).

Error: the largest distance of the head probe from the reference's over the 1001 output times
[m]. Every run uses the same bodies, so this is the error of the time integration alone. CPU:
user + system of the whole process (/usr/bin/time -v: start-up, reading the cached bodies and
gnuplot's run.png included).

Checks (issue 24): every run completes; the error falls from each tolerance to the next; the
slope of log(error) over log(rtol), least squares over all eight runs, is at least 0.7; CPU at
rtol 1e-8 is at most 5 times CPU at rtol 1e-5. Prints the table and FAILED on a miss.

  laser_robot_work_precision.py FLEXTRACK_EXE SOURCE_DIR WORKDIR
"""
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import laser_robot_bench as lrb  # noqa: E402  (the scene edits, /usr/bin/time, probes.csv)

RTOLS = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
REFERENCE_RTOL = 1e-11


def without_subsection(text, name):
    """The scene text without 'subsection NAME' ... its matching 'end'."""
    lines, out, depth = text.split("\n"), [], 0
    for line in lines:
        words = line.split("#")[0].split()
        if depth == 0 and words[:2] == ["subsection", name]:
            depth = 1
            continue
        if depth > 0:
            if words[:1] == ["subsection"]:
                depth += 1
            elif words[:1] == ["end"]:
                depth -= 1
            continue
        out.append(line)
    if len(out) == len(lines):
        lrb.fail("no 'subsection %s' in the scene" % name)
    return "\n".join(out)


def main():
    if len(sys.argv) != 4:
        lrb.fail("usage: laser_robot_work_precision.py FLEXTRACK_EXE SOURCE_DIR WORKDIR")
    exe, srcdir, work = (os.path.abspath(a) for a in sys.argv[1:4])
    os.makedirs(work, exist_ok=True)
    src = {n: open(os.path.join(srcdir, "prm", n)).read() for n in (lrb.SCENE, lrb.BASE, lrb.ARM2)}
    scene = without_subsection(src[lrb.SCENE], "Integrator")
    scene = lrb.set_entry(scene, "Rigid reference", "false", lrb.SCENE)
    scene = lrb.set_entry(scene, "Animation interval", "0", lrb.SCENE)
    bodies = {lrb.BASE: lrb.with_output_directory(src[lrb.BASE], os.path.join(work, "cache_base")),
              lrb.ARM2: lrb.with_output_directory(src[lrb.ARM2], os.path.join(work, "cache_arm2"))}
    for name, text in bodies.items():
        with open(os.path.join(work, name), "w") as f:
            f.write(text)
        log = os.path.join(work, "reduce_" + name + ".log")
        with open(log, "w") as f:
            if subprocess.run([exe, "reduce", os.path.join(work, name)], stdout=f, stderr=subprocess.STDOUT).returncode:
                lrb.fail("reduce " + name + ": " + open(log).read()[-2000:])

    def run(rtol, tag):
        text = scene.replace("subsection Multibody\n", "subsection Multibody\n  subsection Integrator\n"
                             "    set Relative tolerance = %.0e\n    set Absolute tolerance = %.0e\n  end\n"
                             % (rtol, rtol / 100), 1)
        path = os.path.join(work, tag + ".prm")
        with open(path, "w") as f:
            f.write(text)
        out = os.path.join(work, tag)
        status, wall, rss, cpu = lrb.timed([exe, "run", path, "-o", out], out + ".log")
        if status != 0:
            return None
        log = open(out + ".log").read()
        return dict(cpu=cpu, head=lrb.read_head(os.path.join(out, "probes.csv")),
                    radau="Radau IIA" in log and "chosen" in log)

    reference = run(REFERENCE_RTOL, "reference")
    if reference is None:
        lrb.fail("the reference run (rtol %g) did not complete" % REFERENCE_RTOL)
    rows, ok = [], True
    for rtol in RTOLS:
        r = run(rtol, "rtol%.0e" % rtol)
        if r is None:
            print("FAILED: the run at rtol %g did not complete" % rtol)
            ok = False
            continue
        error = max(math.dist(a[1], b[1]) for a, b in zip(r["head"], reference["head"]))
        rows.append((rtol, error, r["cpu"], r["radau"]))
    print("%8s %12s %8s  %s" % ("rtol", "error [m]", "CPU [s]", "method chosen"))
    for rtol, error, cpu, radau in rows:
        print("%8.0e %12.3e %8.2f  %s" % (rtol, error, cpu, "Radau IIA" if radau else "not Radau (see the log)"))
    if not ok:
        sys.exit(1)
    for (r0, e0, _, _), (r1, e1, _, _) in zip(rows, rows[1:]):
        if not e1 < e0:
            print("FAILED: the error does not fall from rtol %g (%.3e m) to rtol %g (%.3e m)" % (r0, e0, r1, e1))
            ok = False
    x = [math.log10(r) for r, _, _, _ in rows]
    y = [math.log10(e) for _, e, _, _ in rows]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    slope = sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)
    cpu = {r: c for r, _, c, _ in rows}
    ratio = cpu[1e-8] / cpu[1e-5]
    print("slope of log(error) over log(rtol): %.2f (target at least 0.7): %s" % (slope, "met" if slope >= 0.7 else "missed"))
    print("CPU(rtol 1e-8) / CPU(rtol 1e-5): %.2f (target at most 5): %s" % (ratio, "met" if ratio <= 5 else "missed"))
    if slope < 0.7 or ratio > 5:
        print("FAILED: a work-precision target of issue 24 is missed")
        ok = False
    if not all(radau for _, _, _, radau in rows):
        print("FAILED: Method = auto did not choose Radau IIA for the laser robot (its log)")
        ok = False
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
