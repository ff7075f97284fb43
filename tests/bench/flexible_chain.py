#!/usr/bin/env python3
"""Benchmark (ctest label bench): cost against the number of bodies, issue 24 item 6.

A chain of N identical flexible links (a 1 m steel rod of 20 mm diameter each, Craig-Bampton with
both ends as interfaces, 4 normal modes; revolute joints about z at the link ends, the first to
the ground), released horizontally under gravity, 1 s simulated at rtol 1e-5 (atol 1e-7, the
integrator's other entries at their defaults). Each N runs three times under /usr/bin/time -v;
printed: N, the median CPU time (user + system, whole process), steps, Jacobians, the CPU per
simulated second, and the exponent of a least-squares fit CPU ~ N^k over the N given.
Targets (issue 24): k <= 1 (at most linear growth) and N = 16 under 2 s CPU.

  flexible_chain.py FLEXTRACK_EXE WORKDIR [--n=1,2,4,8,16,32] [--repeats=3]
"""
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys

LINK = """set Model = body
subsection Body
  set Solid      = false
  set Arms       = rod
  set Interfaces = root: arm rod at 0; end: arm rod at 1   # m of arc length
end
subsection Arm rod
  subsection Curve
    set Kind = line
    subsection Line
      set Start point = 0, 0, 0      # m
      set End point   = 1, 0, 0
    end
  end
  subsection Cross section
    set Shape    = circle
    set Diameter = 0.02              # m
  end
  subsection Supports
    set Start = free
  end
  subsection Mesh
    set Number of elements = 10
  end
end
subsection Reduction
  set Method                 = craig bampton
  set Number of normal modes = 4
end
"""


def chain(n):
    bodies = ", ".join(f"link{i}" for i in range(n))
    joints = ", ".join(f"pin{i}" for i in range(n))
    text = f"""set Model = multibody
subsection Multibody
  set Bodies  = {bodies}
  set Joints  = {joints}
  set Probes  = tip
  set Gravity = 0, -9.81, 0
  set End time        = 1
  set Output interval = 0.01
  subsection Integrator
    set Relative tolerance = 1e-5
    set Absolute tolerance = 1e-7
  end
end
"""
    for i in range(n):
        text += f"""subsection Body link{i}
  set Kind       = flexible
  set Body scene = link_body.prm
  set Position   = {i}, 0, 0
end
subsection Joint pin{i}
  set Kind        = revolute
  set Body 1      = link{i}
  set Interface 1 = root
  set Body 2      = {'ground' if i == 0 else f'link{i - 1}'}
  {'' if i == 0 else 'set Interface 2 = end'}
  set Position    = {i}, 0, 0
  set Axis        = 0, 0, 1
end
"""
    text += f"""subsection Probe tip
  set Body      = link{n - 1}
  set Interface = end
end
"""
    return text


def main():
    exe, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    options = dict(a[2:].split("=", 1) for a in sys.argv[3:] if a.startswith("--") and "=" in a)
    ns = [int(x) for x in options.get("n", "1,2,4,8,16,32").split(",")]
    repeats = int(options.get("repeats", "3"))
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    os.chdir(work)
    with open("link_body.prm", "w") as f:
        f.write(LINK)
    rows = []
    for n in ns:
        with open(f"chain_{n}.prm", "w") as f:
            f.write(chain(n))
        cpu = []
        for r in range(repeats + 1):  # the first run reduces the link (not timed)
            log = f"chain_{n}_{r}.time"
            with open(log, "w") as f:
                status = subprocess.run(["/usr/bin/time", "-v", exe, "run", f"chain_{n}.prm", "-o", f"out_{n}"],
                                        stdout=f, stderr=subprocess.STDOUT).returncode
            text = open(log).read()
            if status != 0:
                print(f"benchmark failed: N = {n}: exit {status}; see {log}")
                sys.exit(1)
            if r > 0:
                cpu.append(float(re.search(r"User time \(seconds\): ([\d.]+)", text).group(1)) +
                           float(re.search(r"System time \(seconds\): ([\d.]+)", text).group(1)))
        with open(os.path.join(f"out_{n}", "summary.json")) as f:
            integrator = json.load(f)["integrator"]
        rows.append((n, statistics.median(cpu), integrator["steps"], integrator["jacobian_evaluations"],
                     integrator["rejected_steps_error_test"]))
    print(f"{'N':>4} {'CPU [s]':>8} {'steps':>7} {'rejected':>8} {'Jacobians':>9}")
    for n, c, steps, jacobians, rejected in rows:
        print(f"{n:4d} {c:8.2f} {steps:7d} {rejected:8d} {jacobians:9d}")
    if len(rows) > 1:
        xs = [math.log(r[0]) for r in rows]
        ys = [math.log(r[1]) for r in rows]
        mx, my = statistics.mean(xs), statistics.mean(ys)
        k = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
        print(f"CPU ~ N^{k:.2f} (least squares over N = {', '.join(str(n) for n in ns)}); target exponent <= 1: "
              + ("target met" if k <= 1 else "target missed"))
    for n, c, *_ in rows:
        if n == 16:
            print(f"N = 16: {c:.2f} s CPU (target < 2 s): " + ("target met" if c < 2 else "target missed"))


if __name__ == "__main__":
    main()
