#!/usr/bin/env python3
"""Andrews' squeezing mechanism (prm/bench/andrews_squeezer.prm) against its published reference
solution: issue 24's rigid closed-loop mechanism (work-precision, error control).

The reference: the seven angles and angular velocities at t = 0.03 s of the IVP Test Set
(F. Mazzia & C. Magherini, Test Set for IVP Solvers, problem "andrews", computed with PSIDE at
rtol = atol = 1e-14; the same values as Hairer & Wanner's RADAU5 driver). FlexTrack's probes are
points of the bars (P on K1, E on K2, D on K3, F on K5, G on K7); this script puts the published
angles through the test set's geometry (its constraint equations g and the spring point D) to get
the points' reference positions and velocities. Error = the largest distance of a probe from its
reference position [m], and relative: over 0.0347 m, the largest distance of a probe from O.

  andrews_squeezer.py FLEXTRACK SCENE WORKDIR --check
      the default-suite test: rtol 1e-4, 1e-6, 1e-8 and 1e-10 each complete and the error follows
      the tolerance (bounds in check())
  andrews_squeezer.py FLEXTRACK SCENE WORKDIR [--rtols=3,4,...,10] [--repeats=3]
      the benchmark (label bench): CPU time (user + system of the whole process, median of the
      repeats) and error side by side for IDA at each rtol, the least-squares slope of log(error)
      over log(rtol), and CPU(rtol 1e-8) / CPU(rtol 1e-5) (issue 24: slope >= 0.7, ratio <= 5)
"""
import csv
import math
import os
import re
import resource
import statistics
import subprocess
import sys

# The test set's data (andrews.f, the same in Hairer & Wanner II, section VII.7) [m].
XA, YA, XB, YB = -0.06934, -0.00227, -0.03635, 0.03273
D_, E_, RR, SS, SC, SD, U, ZF, ZT = 28e-3, 2e-2, 7e-3, 35e-3, 18e-3, 2e-2, 4e-2, 2e-2, 4e-2
# Reference solution at t = 0.03 s: beta, Theta, gamma, Phi, delta, Omega, epsilon [rad] and their
# rates [rad/s] (test set, SOLN).
Q_REF = [0.1581077119629904e+2, -0.1575637105984298e+2, 0.4082224013073101e-1, -0.5347301163226948,
         0.5244099658805304, 0.5347301163226948, 0.1048080741042263e+1]
V_REF = [0.1139920302151208e+4, -0.1424379294994111e+4, 0.1103291221937134e+2, 0.1929337464421385e+2,
         0.5735699284790808, -0.1929337464421385e+2, 0.3231791658026955]
T_END = 0.03
SIZE = 0.0347  # m, the largest distance of a probe from O over the run (|E| at t = 0.03 s: 0.0350)


def points(q):
    """Global x, y of the probe points P, E, D, F, G for the angles q [m]."""
    be, th, ga, ph, de, om, ep = q
    c, s = math.cos, math.sin
    P = (RR * c(be), RR * s(be))
    E = (P[0] - D_ * c(be + th), P[1] - D_ * s(be + th))
    D = (XB + SD * c(ga) + SC * s(ga), YB + SD * s(ga) - SC * c(ga))
    F = (XA + ZT * c(de), YA + ZT * s(de))
    G = (XA + U * s(ep), YA - U * c(ep))
    return {"P": P, "E": E, "D": D, "F": F, "G": G}


def reference():
    """Positions [m] and velocities [m/s] of the probes at t = 0.03 s from the reference angles and
    rates (the velocities: the derivatives of points() along the rates)."""
    be, th, ga, ph, de, om, ep = Q_REF
    vb, vt, vg, vp, vd, vo, ve = V_REF
    c, s = math.cos, math.sin
    vP = (-RR * vb * s(be), RR * vb * c(be))
    vel = {"P": vP,
           "E": (vP[0] + D_ * (vb + vt) * s(be + th), vP[1] - D_ * (vb + vt) * c(be + th)),
           "D": (vg * (-SD * s(ga) + SC * c(ga)), vg * (SD * c(ga) + SC * s(ga))),
           "F": (-ZT * vd * s(de), ZT * vd * c(de)),
           "G": (U * ve * c(ep), U * ve * s(ep))}
    return points(Q_REF), vel


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def run(exe, scene, out, rtol):
    """One run at @p rtol (absolute tolerance 1e-2 m x rtol, the scene's ratio): (exit status,
    CPU [s] of the process, position error [m], velocity error [m/s], steps)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    args = [exe, "run", scene, "-o", out]
    if rtol is not None:
        args += ["--set", f"Multibody/Integrator/Relative tolerance={rtol:g}",
                 "--set", f"Multibody/Integrator/Absolute tolerance={rtol * 1e-2:g}"]
    with open(out + ".log", "w") as log:
        status = subprocess.run(args, stdout=log, stderr=subprocess.STDOUT).returncode
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if status != 0:
        return status, cpu, None, None, None
    with open(os.path.join(out, "probes.csv")) as f:
        rows = list(csv.DictReader(f))
    last = rows[-1]
    if abs(float(last["time_s"]) - T_END) > 1e-12:
        fail(f"{out}: the last row is at t = {last['time_s']} s, not {T_END} s")
    pos, vel = reference()
    e_pos = max(math.dist((float(last[f"{k}_x_m"]), float(last[f"{k}_y_m"])), pos[k]) for k in pos)
    e_vel = max(math.dist((float(last[f"{k}_vx_m_per_s"]), float(last[f"{k}_vy_m_per_s"])), vel[k]) for k in vel)
    steps = None
    summary = os.path.join(out, "summary.json")
    if os.path.exists(summary):
        m = re.search(r'"steps"\s*:\s*(\d+)', open(summary).read())
        steps = int(m.group(1)) if m else None
    return status, cpu, e_pos, e_vel, steps


def slope(ks, errors):
    """Least-squares slope of log10(error) over log10(rtol) = -k."""
    xs, ys = [-k for k in ks], [math.log10(e) for e in errors]
    mx, my = statistics.mean(xs), statistics.mean(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def check(exe, scene, work):
    # Bounds (issue 24: "the measured error must follow the tolerance: no plateau and no failure";
    # "an average slope of at least 0.7 on log-log axes"): every run completes; the position error
    # relative to SIZE is at most 300 x rtol (BDF's global error is the local tolerance times an
    # amplification of the problem, here 0.03 s with 2.5 revolutions at up to 1400 rad/s); it
    # falls from each rtol to the next tighter one; and its least-squares slope over log(rtol) is
    # at least 0.7. Why 300: from rtol 1e-8 on, round-off alone moves the error by up to 40 times
    # (it changes the step sequence): five variants of the same method (Amesos' KLU; SuiteSparse's
    # KLU with and without reused pivots, with and without a step of iterative refinement),
    # 2026-12-02, gave 3 to 123 x rtol at 1e-8 and 59 to 138 x rtol at 1e-10 (16 x at 1e-4).
    # The bound was 100 x until then (36 x at 1e-10 measured on 2026-12-01).
    ks, errors = (4, 6, 8, 10), []
    for k in ks:
        rtol = 10.0 ** -k
        status, cpu, e_pos, e_vel, steps = run(exe, scene, os.path.join(work, f"rtol_1e-{k:02d}"), rtol)
        if status != 0:
            fail(f"rtol 1e-{k}: the run failed (exit {status}); see {work}/rtol_1e-{k:02d}.log")
        rel = e_pos / SIZE
        print(f"rtol 1e-{k:02d}: position error {e_pos:.3e} m ({rel:.2e} of {SIZE} m), velocity error "
              f"{e_vel:.3e} m/s, {steps} steps, {cpu:.2f} s CPU")
        if rel > 300 * rtol:
            fail(f"rtol 1e-{k}: relative error {rel:.2e} above 300 x rtol")
        errors.append(rel)
    for a, b, k in zip(errors, errors[1:], ks):
        if not b < a:
            fail(f"the error does not fall with the tolerance: {a:.2e} at rtol 1e-{k}, {b:.2e} at 1e-{k + 2}")
    fitted = slope(ks, errors)
    print(f"slope of log(error) over log(rtol): {fitted:.2f} (at least 0.7)")
    if not fitted >= 0.7:
        fail(f"the error falls as rtol^{fitted:.2f}, less than rtol^0.7")
    print("PASS")


def bench(exe, scene, work, rtols, repeats):
    rows = []
    print("rtol     position error [m]  relative   velocity error [m/s]  steps   CPU [s] (median of "
          f"{repeats})")
    for k in rtols:
        rtol = 10.0 ** -k
        cpus = []
        for r in range(repeats):
            status, cpu, e_pos, e_vel, steps = run(exe, scene, os.path.join(work, f"rtol_1e-{k:02d}"), rtol)
            if status != 0:
                print(f"1e-{k:02d}  failed (exit {status})")
                break
            cpus.append(cpu)
        if status != 0:
            rows.append((k, None, None))
            continue
        cpu = statistics.median(cpus)
        rows.append((k, e_pos / SIZE, cpu))
        print(f"1e-{k:02d}    {e_pos:.3e}           {e_pos / SIZE:.2e}   {e_vel:.3e}             "
              f"{steps}   {cpu:.3f}")
    done = [(k, e, c) for k, e, c in rows if e is not None]
    if len(done) >= 2:
        fitted = slope([k for k, _, _ in done], [e for _, e, _ in done])
        print(f"slope of log(error) over log(rtol): {fitted:.2f} (target >= 0.7)")
    cpu_of = {k: c for k, _, c in done}
    if 5 in cpu_of and 8 in cpu_of:
        print(f"CPU(rtol 1e-8) / CPU(rtol 1e-5) = {cpu_of[8] / cpu_of[5]:.2f} (target <= 5)")
    failed = [k for k, e, _ in rows if e is None]
    if failed:
        fail("runs failed at rtol " + ", ".join(f"1e-{k}" for k in failed))


def main():
    if len(sys.argv) < 4:
        fail(__doc__)
    exe, scene, work = sys.argv[1:4]
    os.makedirs(work, exist_ok=True)
    opts = dict(a[2:].split("=", 1) if "=" in a else (a[2:], "") for a in sys.argv[4:])
    if "check" in opts:
        check(exe, scene, work)
    else:
        rtols = [int(x) for x in opts.get("rtols", "3,4,5,6,7,8,9,10").split(",")]
        bench(exe, scene, work, rtols, int(opts.get("repeats", "3")))


if __name__ == "__main__":
    main()
