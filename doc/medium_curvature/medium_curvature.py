#!/usr/bin/env python3
"""Medium curvature (seed section VI.3, eq. 45): the seed's small- and medium-curvature
approximations of a track's geometry against the exact geometry FlexTrack uses, and what they do
to a bead sliding under gravity.  Pure Python 3 (no numpy).  See doc/validation.md, section
"Medium curvature (seed VI.3)".

Track: a circular arc of radius R = L / phi (phi = kappa L, L = 1 m), written as the seed's
section VI.3 presupposes, as a plane graph y = f(x) over its chord (x horizontal, y up, the
lowest point at the origin):  f(x) = R - sqrt(R^2 - x^2),  |x| <= R sin(phi/2).

Geometries, each anchored at the lowest point (x = 0, where f' = 0 and all three agree) and built
from its arc length and curvature (the seed's frame rates, eq. (1): omega3 = k s'):
  exact   ds = sqrt(1 + f'^2) dx,   k = f'' / (1 + f'^2)^(3/2)            (what FlexTrack uses)
  small   ds = dx,                  k = f''                               (seed VI.3 (1))
  medium  ds = (1 + f'^2/2) dx,     k = f'' (1 - 3/2 f'^2)                (seed VI.3 (2), eq. 45)
The tangent angle is theta(s) = int k ds, the position r(s) = int (cos theta, sin theta) ds.
A second reading (A) keeps the exact shape and only mislabels the arc length (the point at
abscissa x is taken to be at s = x, or s = int (1 + f'^2/2) dx); its position error is reported
too.

Bead: frictionless, released at rest at the end of each track; s'' = -g sin(theta(s)) (RK4).
The exact case has a closed form (a pendulum of length R and amplitude phi/2: the time to the
lowest point is sqrt(R/g) K(sin(phi/4)), the speed there sqrt(2 g R (1 - cos(phi/2)))) and is
also run with FlexTrack (point_on_track bead on the rigid twin of a flexible arc arm, scenes
written to the output folder).

Usage (from the repository root; 16 s of Python and 8 FlexTrack runs of about 1 s each: 26 s wall
time on 2 shared, loaded cores):
  nice python3 doc/medium_curvature/medium_curvature.py [--flextrack build/flextrack | --no-flextrack]
Writes output/medium_curvature/{geometry.csv, bead.csv, scenes/, runs/} and prints the tables.
"""
import bisect
import csv
import math
import os
import subprocess
import sys
import time

G = 9.81          # m/s^2
L = 1.0           # m, arc length of the exact track
PHIS = [0.1, 0.3, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0]   # kappa L = total turning angle [rad]
NX = 20000        # RK4 steps in x from the lowest point to one end
DT = 2e-5         # s, RK4 step of the bead


def graph(R):
    """f', f'' of the arc y = R - sqrt(R^2 - x^2)."""
    def fp(x):
        return x / math.sqrt(R * R - x * x)

    def fpp(x):
        return R * R / (R * R - x * x) ** 1.5
    return fp, fpp


def rates(kind, fp, fpp):
    """ds/dx and k(x) of each geometry."""
    if kind == "exact":
        return (lambda x: math.sqrt(1 + fp(x) ** 2),
                lambda x: fpp(x) / (1 + fp(x) ** 2) ** 1.5)
    if kind == "small":
        return (lambda x: 1.0, lambda x: fpp(x))
    if kind == "medium":
        return (lambda x: 1 + 0.5 * fp(x) ** 2,
                lambda x: fpp(x) * (1 - 1.5 * fp(x) ** 2))
    raise ValueError(kind)


def build(kind, fp, fpp, xend):
    """Tables over x in [0, xend] (one half; the curve is symmetric): s, theta, X, Y, k."""
    dsdx, k = rates(kind, fp, fpp)

    def rhs(x, y):
        j = dsdx(x)
        th = y[1]
        return (j, k(x) * j, math.cos(th) * j, math.sin(th) * j)
    h = xend / NX
    y = (0.0, 0.0, 0.0, 0.0)
    rows = [(0.0,) + y + (k(0.0),)]
    for i in range(NX):
        x = i * h
        k1 = rhs(x, y)
        k2 = rhs(x + h / 2, tuple(a + h / 2 * b for a, b in zip(y, k1)))
        k3 = rhs(x + h / 2, tuple(a + h / 2 * b for a, b in zip(y, k2)))
        k4 = rhs(x + h, tuple(a + h * b for a, b in zip(y, k3)))
        y = tuple(a + h / 6 * (b1 + 2 * b2 + 2 * b3 + b4)
                  for a, b1, b2, b3, b4 in zip(y, k1, k2, k3, k4))
        rows.append((x + h,) + y + (k(x + h),))
    return rows   # x, s, theta, X, Y, k


class Track:
    """theta(s), r(s) of one half-track by cubic Hermite interpolation (theta' = k)."""

    def __init__(self, rows):
        self.s = [r[1] for r in rows]
        self.th = [r[2] for r in rows]
        self.X = [r[3] for r in rows]
        self.Y = [r[4] for r in rows]
        self.k = [r[5] for r in rows]
        self.half = self.s[-1]

    def _seg(self, s):
        i = min(max(bisect.bisect_right(self.s, s) - 1, 0), len(self.s) - 2)
        h = self.s[i + 1] - self.s[i]
        return i, h, (s - self.s[i]) / h

    def theta(self, s):
        """Tangent angle at signed arc length s from the lowest point (odd in s)."""
        a = abs(s)
        i, h, u = self._seg(a)
        h00, h10 = 2 * u ** 3 - 3 * u ** 2 + 1, u ** 3 - 2 * u ** 2 + u
        h01, h11 = -2 * u ** 3 + 3 * u ** 2, u ** 3 - u ** 2
        v = (h00 * self.th[i] + h10 * h * self.k[i] * 1 + h01 * self.th[i + 1]
             + h11 * h * self.k[i + 1])
        return v if s >= 0 else -v

    def pos(self, s):
        a = abs(s)
        i, h, u = self._seg(a)
        t0, t1 = self.th[i], self.th[i + 1]
        h00, h10 = 2 * u ** 3 - 3 * u ** 2 + 1, u ** 3 - 2 * u ** 2 + u
        h01, h11 = -2 * u ** 3 + 3 * u ** 2, u ** 3 - u ** 2
        X = (h00 * self.X[i] + h10 * h * math.cos(t0) + h01 * self.X[i + 1]
             + h11 * h * math.cos(t1))
        Y = (h00 * self.Y[i] + h10 * h * math.sin(t0) + h01 * self.Y[i + 1]
             + h11 * h * math.sin(t1))
        return (X if s >= 0 else -X), Y


def ellipk(m):
    """Complete elliptic integral of the first kind K(m), m = k^2, by the AGM."""
    a, b = 1.0, math.sqrt(1 - m)
    for _ in range(40):           # quadratic convergence: 6 rounds suffice for m <= 0.99
        a, b = (a + b) / 2, math.sqrt(a * b)
    return math.pi / (2 * a)


def bead(track, tmax):
    """Released at rest at s = -half; time to reach s = 0 and the speed there (RK4 in t).
    None, reason if it leaves the track through the end it started from (the approximate
    track's end points downhill, away from the lowest point) or has not arrived by tmax."""
    def acc(s):
        return -G * math.sin(track.theta(s))
    s, v, t = -track.half, 0.0, 0.0
    while True:
        if s < -track.half - 1e-12:
            return None, "leaves the track at its end"
        if t > tmax:
            return None, "has not reached s = 0 after %.2f s" % tmax
        a1 = acc(s)
        a2 = acc(s + DT / 2 * v)
        a3 = acc(s + DT / 2 * (v + DT / 2 * a1))
        a4 = acc(s + DT * (v + DT / 2 * a2))
        s1 = s + DT * v + DT * DT / 6 * (a1 + a2 + a3)
        v1 = v + DT / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
        if s1 >= 0:
            # cubic Hermite in t through (s, v), (s1, v1): root of s(t) = 0 by bisection
            lo, hi = 0.0, 1.0
            for _ in range(60):
                u = (lo + hi) / 2
                su = ((2 * u ** 3 - 3 * u ** 2 + 1) * s + (u ** 3 - 2 * u ** 2 + u) * DT * v
                      + (-2 * u ** 3 + 3 * u ** 2) * s1 + (u ** 3 - u ** 2) * DT * v1)
                lo, hi = (u, hi) if su < 0 else (lo, u)
            u = (lo + hi) / 2
            vb = (v * (1 - u) + v1 * u)   # speed at the bottom: d s/dt, linear (|dv/dt| = 0 there)
            return t + u * DT, vb
        s, v, t = s1, v1, t + DT


BODY = """# Medium-curvature study (doc/validation.md): a circular arc arm of length {L} m turning through
# kappa L = {phi} rad, in the x-y plane, starting at the origin heading +y. Used as its rigid twin.
set Model = body
subsection Body
  set Solid = false
  set Arms  = arm
end
subsection Arm arm
  subsection Curve
    set Kind = arc
    subsection Arc
      set Radius = {R!r}
      set Angle  = {phi!r}
      set Centre = {mR!r}, 0, 0
    end
  end
  subsection Section frame
    set Kind             = fixed vector
    set Reference vector = 0, 0, 1
  end
  subsection Cross section
    set Shape          = tube
    set Outer diameter = 0.04
    set Inner diameter = 0.032
  end
  subsection Material
    set Young's modulus = 2.1e11
    set Poisson's ratio = 0.3
    set Density         = 7850
  end
  subsection Supports
    set Start = clamped
    set End   = free
  end
  subsection Mesh
    set Number of elements = 8
  end
end
subsection Reduction
  set Method                 = craig bampton
  set Number of normal modes = 2
  set Track arms             = arm
  set Track stations         = 2
end
subsection Output
  set Directory = {outdir}
  set Mode shapes = false
end
"""

SCENE = """# Medium-curvature study (doc/validation.md): a 1 kg bead released at rest at s = 0 of the rigid
# arc arm_{tag}_body.prm; gravity points from the arc's centre to its midpoint (the lowest point,
# s = L/2), so the bead swings like a pendulum of length R = {R!r} m and amplitude {half!r} rad.
set Model = multibody
subsection Multibody
  set Bodies  = arm, bead
  set Flexible bodies rigid = true
  set Joints  = clamp, slide
  set Probes  = bead
  set Gravity = {gx!r}, {gy!r}, 0
  set End time        = {tend!r}
  set Output interval = 0.001
  subsection Integrator
    set Relative tolerance = 1e-10
    set Absolute tolerance = 1e-12
  end
end
subsection Body arm
  set Kind       = flexible
  set Body scene = arm_{tag}_body.prm
end
subsection Body bead
  set Kind     = rigid
  set Mass     = 1
  set Inertia  = 1e-4, 1e-4, 1e-4, 0, 0, 0
  set Position = 0, 0, 0
end
subsection Joint clamp
  set Kind   = fixed
  set Body 1 = arm
  set Body 2 = ground
end
subsection Joint slide
  set Kind    = point_on_track
  set Body 1  = bead
  set Body 2  = arm
  set Arm     = arm
  set Sliding = free
  set Start arc length = 0
  set Start speed      = 0
end
subsection Probe bead
  set Body = bead
end
"""


def flextrack_bead(exe, phi, outroot):
    """Run the exact bead in FlexTrack; time to the lowest point (s = L/2) and the speed there."""
    R = L / phi
    tag = ("%.2f" % phi).replace(".", "p")
    scenes = os.path.join(outroot, "scenes")
    os.makedirs(scenes, exist_ok=True)
    tb = math.sqrt(R / G) * ellipk(math.sin(phi / 4) ** 2)
    with open(os.path.join(scenes, "arm_%s_body.prm" % tag), "w") as f:
        f.write(BODY.format(L=L, phi=phi, R=R, mR=-R,
                            outdir=os.path.join(outroot, "reduced", tag)))
    scene = os.path.join(scenes, "bead_%s.prm" % tag)
    with open(scene, "w") as f:
        f.write(SCENE.format(tag=tag, R=R, half=phi / 2, gx=G * math.cos(phi / 2),
                             gy=G * math.sin(phi / 2), tend=round(1.2 * tb, 3)))
    out = os.path.join(outroot, "runs", tag)
    t0 = time.time()
    p = subprocess.run([exe, "run", scene, "-o", out], capture_output=True, text=True)
    wall = time.time() - t0
    if p.returncode != 0:
        sys.exit("flextrack failed for kappa L = %g:\n%s%s" % (phi, p.stdout, p.stderr))
    rows = []
    with open(os.path.join(out, "probes.csv")) as f:
        for r in csv.DictReader(f):
            t = float(r["time_s"])
            x, y = float(r["bead_x_m"]) + R, float(r["bead_y_m"])
            vx, vy = float(r["bead_vx_m_per_s"]), float(r["bead_vy_m_per_s"])
            al = math.atan2(y, x)
            sd = -vx * math.sin(al) + vy * math.cos(al)
            rows.append((t, R * al - L / 2, sd))
    for (t0_, s0, v0), (t1, s1, v1) in zip(rows, rows[1:]):
        if s0 < 0 <= s1:
            dt = t1 - t0_
            lo, hi = 0.0, 1.0
            for _ in range(60):
                u = (lo + hi) / 2
                su = ((2 * u ** 3 - 3 * u ** 2 + 1) * s0 + (u ** 3 - 2 * u ** 2 + u) * dt * v0
                      + (-2 * u ** 3 + 3 * u ** 2) * s1 + (u ** 3 - u ** 2) * dt * v1)
                lo, hi = (u, hi) if su < 0 else (lo, u)
            u = (lo + hi) / 2
            return t0_ + u * dt, v0 * (1 - u) + v1 * u, wall
    sys.exit("flextrack run for kappa L = %g never reached the lowest point" % phi)


def main():
    exe = "build/flextrack"
    if "--flextrack" in sys.argv:
        exe = sys.argv[sys.argv.index("--flextrack") + 1]
    if "--no-flextrack" in sys.argv:
        exe = None
    outroot = os.path.abspath(os.path.join("output", "medium_curvature"))
    os.makedirs(outroot, exist_ok=True)
    if exe:
        exe = os.path.abspath(exe)
    geo, dyn = [], []
    for phi in PHIS:
        R = L / phi
        fp, fpp = graph(R)
        xend = R * math.sin(phi / 2)
        tr = {kind: Track(build(kind, fp, fpp, xend)) for kind in ("exact", "small", "medium")}
        ex = tr["exact"]
        # exact geometry check: s = R theta, theta = s / R
        chk = max(abs(ex.th[i] - ex.s[i] / R) for i in range(0, NX + 1, 50))
        g = {"kappaL": phi, "max_slope": fp(xend), "table_check_rad": chk}
        for kind in ("small", "medium"):
            ap = tr[kind]
            n = 2000
            smax = min(ap.half, ex.half)
            dpos = dang = 0.0
            for j in range(n + 1):
                s = smax * j / n
                xa, ya = ap.pos(s)
                xe, ye = ex.pos(s)
                dpos = max(dpos, math.hypot(xa - xe, ya - ye))
                dang = max(dang, abs(ap.theta(s) - ex.theta(s)))
            xa, ya = ap.pos(ap.half)
            xe, ye = ex.pos(ex.half)
            # reading (A): exact shape, arc length mislabelled: the point at abscissa x sits at
            # exact arc length s_exact(x) but is taken to be at s_approx(x) of the same x
            dposA = 0.0
            for j in range(0, NX + 1, 10):
                s_ap = ap.s[j]
                if s_ap > ex.half:
                    break
                xe2, ye2 = ex.pos(s_ap)
                dposA = max(dposA, math.hypot(ex.X[j] - xe2, ex.Y[j] - ye2))
            g[kind + "_length_rel"] = (2 * ap.half - L) / L
            g[kind + "_max_pos_m"] = dpos
            g[kind + "_end_gap_m"] = math.hypot(xa - xe, ya - ye)
            g[kind + "_max_angle_rad"] = dang
            g[kind + "_end_angle_rad"] = ap.th[-1] - ex.th[-1]
            g[kind + "_readingA_max_pos_m"] = dposA
        geo.append(g)
        tb_cf = math.sqrt(R / G) * ellipk(math.sin(phi / 4) ** 2)
        vb_cf = math.sqrt(2 * G * R * (1 - math.cos(phi / 2)))
        d = {"kappaL": phi, "t_exact_closed_form_s": tb_cf, "v_exact_closed_form_m_per_s": vb_cf}
        for kind in ("exact", "small", "medium"):
            tb, vb = bead(tr[kind], 5 * tb_cf)
            if tb is None:
                d["t_%s_s" % kind], d["v_%s_m_per_s" % kind] = float("nan"), float("nan")
                d["note_" + kind] = vb
            else:
                d["t_%s_s" % kind], d["v_%s_m_per_s" % kind] = tb, vb
        if exe:
            tf, vf, wall = flextrack_bead(exe, phi, outroot)
            d["t_flextrack_s"], d["v_flextrack_m_per_s"], d["flextrack_wall_s"] = tf, vf, wall
        dyn.append(d)
        print("kappa L = %g done" % phi, file=sys.stderr)
    for name, rows in (("geometry.csv", geo), ("bead.csv", dyn)):
        with open(os.path.join(outroot, name), "w", newline="") as f:
            keys = []
            for r in rows:
                keys += [k for k in r if k not in keys]
            w = csv.DictWriter(f, fieldnames=keys)
            w.writeheader()
            for r in rows:
                w.writerow({k: (v if isinstance(v, str) else "%.10g" % v) for k, v in r.items()})

    print("\nGeometry (L = 1 m; errors at equal arc length s from the lowest point)\n")
    print("| kappa L | max slope f' | length small | length medium | max position small [m] "
          "| max position medium [m] | max angle small [rad] | max angle medium [rad] "
          "| reading (A) position small / medium [m] |")
    print("|---|---|---|---|---|---|---|---|---|")
    for g in geo:
        print("| %g | %.3g | %+.2e | %+.2e | %.2e | %.2e | %.2e | %.2e | %.2e / %.2e |" % (
            g["kappaL"], g["max_slope"], g["small_length_rel"], g["medium_length_rel"],
            g["small_max_pos_m"], g["medium_max_pos_m"], g["small_max_angle_rad"],
            g["medium_max_angle_rad"], g["small_readingA_max_pos_m"],
            g["medium_readingA_max_pos_m"]))
    print("\nBead released at rest at the end: time to the lowest point and speed there\n")
    print("| kappa L | t exact (closed form) [s] | FlexTrack - closed form [s] | t small [s] (rel.) "
          "| t medium [s] (rel.) | v exact [m/s] | v small (rel.) | v medium (rel.) |")
    print("|---|---|---|---|---|---|---|---|")
    for d in dyn:
        te, ve = d["t_exact_closed_form_s"], d["v_exact_closed_form_m_per_s"]
        ft = ("%.1e" % (d["t_flextrack_s"] - te)) if "t_flextrack_s" in d else "-"
        def tv(kind, q, ref):
            x = d["%s_%s" % (q, kind) + ("_s" if q == "t" else "_m_per_s")]
            if math.isnan(x):
                return d["note_" + kind] if q == "t" else "-"
            return "%.6f (%+.2e)" % (x, x / ref - 1)
        print("| %g | %.6f | %s | %s | %s | %.6f | %s | %s |" % (
            d["kappaL"], te, ft, tv("small", "t", te), tv("medium", "t", te), ve,
            tv("small", "v", ve), tv("medium", "v", ve)))
    print("\nChecks: exact table theta - s/R max %.1e rad; Python exact bead - closed form: "
          "t %.1e s, v %.1e m/s; FlexTrack - closed form: t %s s, v %s m/s" % (
              max(g["table_check_rad"] for g in geo),
              max(abs(d["t_exact_s"] - d["t_exact_closed_form_s"]) for d in dyn),
              max(abs(d["v_exact_m_per_s"] - d["v_exact_closed_form_m_per_s"]) for d in dyn),
              ("%.1e" % max(abs(d["t_flextrack_s"] - d["t_exact_closed_form_s"]) for d in dyn))
              if exe else "-",
              ("%.1e" % max(abs(d["v_flextrack_m_per_s"] - d["v_exact_closed_form_m_per_s"])
                            for d in dyn)) if exe else "-"))
    if exe:
        print("FlexTrack wall time per run: %s s" % ", ".join(
            "%.2f" % d["flextrack_wall_s"] for d in dyn))


if __name__ == "__main__":
    main()
