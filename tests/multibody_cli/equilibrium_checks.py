"""Static equilibrium and linearisation checks of 'flextrack run' and 'flextrack linearize'
(issue 25, items 3 and 4; tests/multibody_cli.cmake): one stability verdict for both, a pendulum
started horizontal is not a mechanism, and a state that is not an equilibrium is said to be
one. The reference and the tolerance stand next to each assertion.
Usage: equilibrium_checks.py CHECK EXE SCENE OUT
"""
import csv
import json
import math
import os
import re
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks import check, run, table  # noqa: E402

G = 9.81


def run_summary(exe, command, scene, out, *extra):
    shutil.rmtree(out, ignore_errors=True)
    p = run(exe, command, scene, "-o", out, *extra)
    with open(os.path.join(out, "summary.json")) as f:
        return p.stdout, json.load(f)


def eigenvalues(out):
    with open(os.path.join(out, "linear_modes.csv")) as f:
        return [complex(float(r["eigenvalue_real_per_s"]), float(r["eigenvalue_imag_per_s"])) for r in csv.DictReader(f)]


def reported_growth_rate(log):
    """The growth rate the static-equilibrium report prints ('UNSTABLE: ... Re s = X 1/s')."""
    m = re.search(r"Static equilibrium:.*UNSTABLE: linearised about it, (\d+) mode\(s\) grow, the fastest at "
                  r"Re s = ([0-9.eE+-]+) 1/s", log)
    check(m is not None, "the static-equilibrium report says UNSTABLE with its growth rate")
    return int(m.group(1)), float(m.group(2))


def inverted_pendulum(exe, scene, out):
    # tests/multibody_cli/inverted_pendulum_equilibrium.prm: prm/pendulum.prm's bob (m = 1.5 kg,
    # d = 0.8 m, J_c = 0.02 kg m^2) balanced upside down. Linearised, theta'' = (m g d / J_p) theta:
    # s = +-sqrt(m g d / J_p), J_p = J_c + m d^2 (a compound pendulum above its pivot).
    m, d, Jc = 1.5, 0.8, 0.02
    exact = math.sqrt(m * G * d / (Jc + m * d * d))
    log, summary = run_summary(exe, "run", scene, out + "/run")
    eq = summary["initial_conditions"]["static_equilibrium"]
    check(eq["stable"] is False, f"summary.json: static_equilibrium stable = false ({eq['stable']})")
    check(eq["moves"][0]["turned_rad"] < 1e-12, "it stays upside down (turned < 1e-12 rad)")
    n, reported = reported_growth_rate(log)
    print(f"static report: {n} mode grows at {reported:.9f} 1/s; closed form sqrt(m g d / J_p) = {exact:.9f} 1/s")
    check(n == 1, "one mode grows")
    # Central differences in the linearisation (multibody/linearization.h): good to about 1e-7;
    # tolerance 1e-6 relative, as for the hanging pendulum's frequency.
    check(abs(reported / exact - 1) < 1e-6, "the report's growth rate within 1e-6 of sqrt(m g d / J_p)")
    log, lin = run_summary(exe, "linearize", scene, out + "/linearize")
    s = max(e.real for e in eigenvalues(out + "/linearize"))
    print(f"linearize: largest Re s = {s:.12f} 1/s")
    check(lin["unstable_modes"] == 1, f"linearize: one unstable mode ({lin['unstable_modes']})")
    check(abs(s / exact - 1) < 1e-6, "linearize's growth rate within 1e-6 of sqrt(m g d / J_p)")
    # One analysis for both: the same number, to the 9 digits the report prints.
    check(abs(reported / s - 1) < 1e-8, "the report and linearize give the same growth rate (1e-8)")
    check("note:" not in log, "an equilibrium: linearize adds no note")


def inverted_flexible_link(exe, scene, out):
    # The flexible body of prm/flexible_pendulum.prm (the curved boom, 9.6 kg, modes up to 32 kHz)
    # started near upside down; Newton converges to the inverted equilibrium. The old test (the
    # smallest eigenvalue of K_T on the constraint null space, -10.6, against -1e-8 x the largest
    # row sum of K_T, -920 with the stiff modes) called it stable while linearize found 5.23 1/s.
    log, summary = run_summary(exe, "run", scene, out + "/run", "--set", "Multibody/End time=0.01")
    eq = summary["initial_conditions"]["static_equilibrium"]
    check(eq["stable"] is False, f"summary.json: static_equilibrium stable = false ({eq['stable']})")
    _, reported = reported_growth_rate(log)
    _, lin = run_summary(exe, "linearize", scene, out + "/linearize")
    s = max(e.real for e in eigenvalues(out + "/linearize"))
    print(f"static report {reported:.9f} 1/s, linearize {s:.12f} 1/s")
    check(lin["unstable_modes"] == 1, f"linearize: one unstable mode ({lin['unstable_modes']})")
    check(abs(reported / s - 1) < 1e-8, "the report and linearize give the same growth rate (1e-8)")
    # Its rigid twin (Body boom/Rigid = true: same m, s, J_O) balanced the same way grows at
    # sqrt(m g d / J_p); the boom's flexibility changes that little (measured 7.0e-5 relative; bound 1e-3:
    # the gravity load bends the stiff boom by a fraction of a millimetre).
    log, _ = run_summary(exe, "linearize", scene, out + "/rigid", "--set", "Body boom/Rigid=true")
    rigid = max(e.real for e in eigenvalues(out + "/rigid"))
    print(f"rigid twin: {rigid:.9f} 1/s")
    check(abs(s / rigid - 1) < 1e-3, "the flexible link grows within 1e-3 of its rigid twin")


def double_pendulum_from_horizontal(exe, scene, out):
    # tests/multibody_cli/double_pendulum_horizontal.prm: two identical uniform rods (m, l = 0.6 m),
    # started horizontal. It must not be refused, and ends hanging straight down.
    l = 0.6
    log, summary = run_summary(exe, "run", scene, out + "/run")
    eq = summary["initial_conditions"]["static_equilibrium"]
    check(eq["stable"] is True, f"summary.json: static_equilibrium stable = true ({eq['stable']})")
    p = table(os.path.join(out, "run", "probes.csv"))
    xe, ye, xt, yt = p["elbow_x_m"][0], p["elbow_y_m"][0], p["tip_x_m"][0], p["tip_y_m"][0]
    theta1, theta2 = math.atan2(xe, -ye), math.atan2(xt - xe, -(yt - ye))
    print(f"angles from the downward vertical: {theta1:.3e}, {theta2:.3e} rad; elbow ({xe}, {ye}), tip ({xt}, {yt})")
    # Equilibrium tolerance 1e-10 of the weight: the angles are exact to about that (the probes
    # print 12 digits); bound 1e-8 rad.
    check(abs(theta1) < 1e-8 and abs(theta2) < 1e-8, "both rods hang straight down (1e-8 rad)")
    check(abs(ye + l) < 1e-8 and abs(yt + 2 * l) < 1e-8, "elbow at y = -l, tip at y = -2 l (1e-8 m)")
    for m in eq["moves"]:
        check(abs(m["turned_rad"] - math.pi / 2) < 1e-8, f"body {m['body']} turned by pi/2 (1e-8): {m['turned_rad']}")
    # Small oscillations of the double compound pendulum of two identical uniform rods (angles
    # theta_1, theta_2 from the vertical; J_pivot = m l^2 / 3, J_c = m l^2 / 12):
    #   M = m l^2 [[4/3, 1/2], [1/2, 1/3]],  K = m g l [[3/2, 0], [0, 1/2]],
    #   det(K - w^2 M) = 0  ->  w^4 - 6 (g/l) w^2 + (27/7) (g/l)^2 = 0,  w^2 = (3 -+ 6/sqrt(7)) g / l
    # (e.g. Wikipedia, 'Double pendulum', the compound pendulum linearised; Morin, Introduction to
    # Classical Mechanics, the double physical pendulum).
    exact = sorted(math.sqrt((3 + sign * 6 / math.sqrt(7)) * G / l) / (2 * math.pi) for sign in (-1, 1))
    log, lin = run_summary(exe, "linearize", scene, out + "/linearize")
    f = lin["frequencies_Hz"]
    print(f"linearize: {f} Hz; closed form {exact} Hz")
    check(len(f) == 2 and lin["unstable_modes"] == 0, "two modes, none unstable")
    # Central differences (multibody/linearization.h): tolerance 1e-6 relative.
    for k in range(2):
        check(abs(f[k] / exact[k] - 1) < 1e-6, f"frequency {k + 1} within 1e-6 of sqrt((3 -+ 6/sqrt 7) g/l) / 2 pi")
    check("note:" not in log and lin["equilibrium_check"]["is_equilibrium"], "an equilibrium: no note")


def linearize_off_equilibrium(exe, scene, out):
    # tests/multibody_cli/pendulum_at_30_degrees.prm: prm/pendulum.prm's bob (m = 1.5 kg, d = 0.8 m,
    # J_c = 0.02 kg m^2) at rest at theta = 30 deg, as given. Released there, theta'' = -m g d
    # sin(theta) / J_p; its centre of mass accelerates along the tangent (cos, sin)(theta):
    # a_x = -m g d^2 sin(theta) cos(theta) / J_p = -4.161 m/s^2, the largest acceleration once weighted
    # by the mass (sqrt(1.5) x 4.16 against sqrt(0.02) x 6.0 rad/s^2 for omega_z).
    m, d, Jc, theta = 1.5, 0.8, 0.02, math.radians(30)
    a_x = -m * G * d * d * math.sin(theta) * math.cos(theta) / (Jc + m * d * d)
    log, lin = run_summary(exe, "linearize", scene, out + "/off")
    state = lin["equilibrium_check"]
    print(f"equilibrium_check {state}; closed form a_x = {a_x:.9f} m/s^2")
    check("note: the state linearised about is not an equilibrium" in log and "'body bob, R'_x'" in log,
          "the log says it is not an equilibrium, naming body bob, R'_x")
    check(len(lin["notes"]) == 1 and "not an equilibrium" in lin["notes"][0], f"summary.json notes say it: {lin['notes']}")
    check(state["is_equilibrium"] is False and state["largest_acceleration_component"] == "body bob, R'_x"
          and state["largest_acceleration_unit"] == "m/s^2", "summary.json names the component and its unit")
    # The index-1 solve at rest is exact up to round-off: 1e-9 relative.
    check(abs(state["largest_acceleration"] / a_x - 1) < 1e-9, "the acceleration is the closed form's a_x (1e-9)")
    check(state["imbalance"] > 0.1, f"unbalanced: {state['imbalance']:.3f} of the largest force (> 0.1)")
    # The same pendulum hanging at rest (tests/multibody_input/pendulum_at_rest.prm): no note.
    rest = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "multibody_input", "pendulum_at_rest.prm")
    log, lin = run_summary(exe, "linearize", rest, out + "/rest")
    print(f"hanging: equilibrium_check {lin['equilibrium_check']}")
    check("note:" not in log and lin["notes"] == [], "hanging at rest: no note")
    # At rest where the loads balance: the imbalance is round-off (below 1e-12; tolerance 1e-6).
    check(lin["equilibrium_check"]["is_equilibrium"] is True and lin["equilibrium_check"]["imbalance"] < 1e-12,
          "hanging at rest: an equilibrium (imbalance below 1e-12)")


if __name__ == "__main__":
    globals()[sys.argv[1]](*sys.argv[2:5])
