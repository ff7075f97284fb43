#!/usr/bin/python3
"""Hostile input, round two (issue 23): the multibody commands (run, bench). Each case is one
scene of the new corpus, run as hostile_scenes.py runs its cases (same checks: a refused input
exits 2 within 5 s with one printable line naming the file and the entry and leaves nothing in
the output folder; an accepted one exits 0 with its files).

- item 1: `bench` on a scene file whose name ends gnuplot's string and calls system(), or holds a
  newline and '!' (both ran `touch PWNED` with exit 0 before);
- item 3: bench with 'Relative tolerance = 0' (errors of exactly 0 before) or a probe on the ground
  (every error 0, a "fastest run within 1e-6");
- items 5-7: laws of time that are not finite, have a pole or overflow (log(t), sqrt(-1),
  1/(t-0.5), exp(1000 t), 1e308 t^2; internal errors, hangs or SUNDIALS failures before), a
  spring whose points coincide (internal error), tolerances and steps at 1e-300 (stuck at t = 0).

usage: hostile_multibody.py FLEXTRACK WORK_DIR CASE
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import hostile_scenes  # noqa: E402  (the runner and its checks)

# A compound pendulum on a revolute joint, 1 s (prm/pendulum.prm at the default tolerances).
PENDULUM = """set Model = multibody
subsection Multibody
  set Bodies  = bob
  set Joints  = pivot
  set Forces  = {forces}
  set Probes  = {probes}
  set Gravity = 0, -9.81, 0
  set End time        = 1
  set Output interval = 0.01
  subsection Integrator
{integrator}
  end
end
subsection Body bob
  set Kind    = rigid
  set Mass    = 1.5
  set Inertia = 0.02, 0.02, 0.02, 0, 0, 0
  set Position        = 0.4, 0.69282032302755, 0
  set Rotation vector = 0, 0, 2.6179938779914944
end
subsection Joint pivot
  set Kind     = revolute
  set Body 1   = bob
  set Body 2   = ground
  set Position = 0, 0, 0
  set Axis     = 0, 0, 1
  set Driver   = {driver}
end
{probe_sections}
{extra}
"""
PROBES = {"bob_centre": "bob\n  set Position = 0.4, 0.69282032302755, 0",  # on the bob
          "pin": "ground\n  set Position = 0, 0, 0"}  # on the ground: it never moves


def pendulum(driver="", forces="", probes="bob_centre", integrator="", extra=""):
    sections = "".join(f"subsection Probe {p}\n  set Body = {PROBES[p]}\nend\n" for p in probes.split(", "))
    return PENDULUM.format(driver=driver, forces=forces, probes=probes, integrator=integrator, extra=extra,
                           probe_sections=sections)


def load(force="0; 0; 0", torque="0; 0; 0"):
    return pendulum(forces="push", extra=f"""subsection Force push
  set Kind   = applied load
  set Body 1 = bob
  set Position 1 = 0.4, 0.69282032302755, 0
  set Force  = {force}
  set Torque = {torque}
end""")


SPRING_AT_ONE_POINT = pendulum(forces="spring", extra="""subsection Force spring
  set Kind   = spring damper
  set Body 1 = bob
  set Body 2 = ground
  set Position 1 = 0.4, 0.69282032302755, 0
  set Position 2 = 0.4, 0.69282032302755, 0
  set Stiffness = 100
end""")

JSON_PLAIN_KEYS = """{
  "Model": "multibody",
  "Multibody": {"Bodies": "my_bob", "Joints": "the_pivot", "Probes": "bob_centre", "Gravity": "0, -9.81, 0",
                "End time": "0.5", "Output interval": "0.01"},
  "Body my_bob": {"Kind": "rigid", "Mass": "1.5", "Inertia": "0.02, 0.02, 0.02, 0, 0, 0",
                  "Position": "0.4, 0.69282032302755, 0", "Rotation vector": "0, 0, 2.6179938779914944"},
  "Joint the_pivot": {"Kind": "revolute", "Body 1": "my_bob", "Body 2": "ground", "Position": "0, 0, 0",
                      "Axis": "0, 0, 1"},
  "Probe bob_centre": {"Body": "my_bob", "Position": "0.4, 0.69282032302755, 0"}
}
"""

QUOTE_NAME = "x'; system 'touch PWNED'; y='.prm"
NEWLINE_NAME = "x\n!touch PWNED\ny.prm"

CASES = {
    # Item 1: the scene file's name reached bench.gp unquoted.
    "bench_scene_name_ends_gnuplot_string": dict(
        files={QUOTE_NAME: pendulum()}, args=["bench", QUOTE_NAME], status=0, absent=["PWNED"],
        outputs=["bench.csv", "bench.gp", "bench.png", "summary.json"]),
    "bench_scene_name_with_newline_and_bang": dict(
        files={NEWLINE_NAME: pendulum()}, args=["bench", NEWLINE_NAME], status=0, absent=["PWNED"],
        outputs=["bench.csv", "bench.gp", "bench.png", "summary.json"]),
    # Item 3
    "bench_relative_tolerance_zero": dict(
        files={"s.prm": pendulum(integrator="    set Relative tolerance = 0")}, args=["bench", "s.prm"],
        regex=r"Relative tolerance.*must be from 1e-14"),
    "bench_only_probe_on_the_ground": dict(
        files={"s.prm": pendulum(probes="pin")}, args=["bench", "s.prm"],
        regex=r"Multibody/Probes.*no probe moves more than 1e-9 m in the reference run \(pin\)"),
    # Items 5-7: laws of time checked before the run, with their entry.
    "driver_log_t": dict(files={"s.prm": pendulum(driver="log(t)")}, args=["run", "s.prm"],
                         regex=r"Joint pivot/Driver.*'log\(t\)' is not finite at t = 0 s"),
    "driver_sqrt_of_minus_1": dict(files={"s.prm": pendulum(driver="sqrt(-1)")}, args=["run", "s.prm"],
                                   regex=r"Joint pivot/Driver.*is not finite at t = 0 s \(value -?nan\)"),
    "driver_pole_on_the_grid": dict(files={"s.prm": pendulum(driver="1/(t-0.5)")}, args=["run", "s.prm"],
                                    regex=r"Joint pivot/Driver.*(not finite|pole) at t = 0.5 s"),
    "driver_pole_between_grid_points": dict(
        files={"s.prm": pendulum(driver="1/(t-0.50001234)")}, args=["run", "s.prm"],
        regex=r"Joint pivot/Driver.*has a pole (near|at) t = 0.5000"),
    "driver_exp_1000_t": dict(files={"s.prm": pendulum(driver="exp(1000*t)")}, args=["run", "s.prm"],
                              regex=r"Joint pivot/Driver.*'exp\(1000\*t\)' (is not finite|reaches)"),
    "driver_1e308_t_squared": dict(files={"s.prm": pendulum(driver="1e308*t*t")}, args=["run", "s.prm"],
                                   regex=r"Joint pivot/Driver.*(is not finite|reaches)"),
    "force_1e308": dict(files={"s.prm": load(force="1e308; 1e308; 0")}, args=["run", "s.prm"],
                        regex=r"Force push/Force.*'1e308' reaches value 1e\+308 at t = 0 s"),
    "torque_nan_before_1_s": dict(files={"s.prm": load(torque="0; 0; sqrt(t-1)")}, args=["run", "s.prm"],
                                  regex=r"Force push/Torque.*'sqrt\(t-1\)' is not finite at t = 0 s"),
    "spring_with_coincident_points": dict(files={"s.prm": SPRING_AT_ONE_POINT}, args=["run", "s.prm"],
                                          regex=r"Force spring/Position 2.*is 0.* m from Position 1"),
    "absolute_tolerance_1e-300": dict(
        files={"s.prm": pendulum(integrator="    set Absolute tolerance = 1e-300")}, args=["run", "s.prm"],
        regex=r"Absolute tolerance.*must be >= 1e-15"),
    "generalized_alpha_adaptive_step_1e-300": dict(
        files={"s.prm": pendulum(integrator="    set Method = generalized_alpha\n    set Adaptive step = true\n"
                                            "    set Step = 1e-300")}, args=["run", "s.prm"],
        regex=r"Integrator/Step.*must be from 1e-10 s \(1e-10 of the run\)"),
    # Item 8: a run left the previous run's deviation and animation files beside its own results.
    "rerun_removes_previous_runs_files": dict(
        files={"a.prm": pendulum(extra="subsection Output\n  set Animation interval = 0.1\nend").replace(
                   "set Gravity", "set Rigid reference = true\n  set Gravity"),
               "s.prm": pendulum()},
        before=["run", "a.prm", "-o", "out"], args=["run", "s.prm", "-o", "out"], status=0,
        outputs=["probes.csv", "summary.json"], stale=["deviation", "animation"]),
    "linearize_writes_to_its_folder": dict(
        files={"s.prm": pendulum()}, args=["linearize", "s.prm", "-o", "out"], status=0,
        outputs=["linear_modes.csv", "summary.json"]),
    "body_listed_without_subsection": dict(
        files={"s.prm": pendulum().replace("set Bodies  = bob", "set Bodies  = bob, ghost")}, args=["run", "s.prm"],
        regex=r"Multibody/Bodies.*Body 'ghost' is listed but has no 'subsection Body ghost'"),
    "reference_axis_parallel_to_axis": dict(
        files={"s.prm": pendulum().replace("set Axis     = 0, 0, 1", "set Axis     = 0, 0, 1\n  set Reference axis = 0, 0, 2")},
        args=["run", "s.prm"], regex=r"Joint pivot/Reference axis.*is parallel to Axis"),
    "empty_scene_file": dict(files={"s.prm": "# nothing but a comment\n\n"}, args=["run", "s.prm"],
                             regex=r"holds no entries", entry=""),
    # Item 5: 1e7 output rows wrote 161 MB of CSV a minute and built a 1.9 GB results.h5 in memory.
    "ten_million_output_rows": dict(
        files={"s.prm": pendulum().replace("set Output interval = 0.01", "set Output interval = 1e-7")},
        args=["run", "s.prm"], regex=r"Multibody/Output interval.*asks for 1e\+07 output rows, about .* GiB of results"),
    # Item 5: results.h5 is written as the run goes; a disk that fills (here a file size limit of
    # 8 MB, under which the first 4 MiB block cannot be written with its margin) stops the run with
    # exit 2 naming the output, and leaves no half-written files.
    "results_beyond_file_size_limit": dict(
        files={"s.prm": pendulum().replace("set Output interval = 0.01", "set Output interval = 1e-4").replace(
            "set End time        = 1", "set End time        = 20")},
        args=["run", "s.prm", "-o", "out"], fsize_limit=8000000, status=2,
        regex=r"cannot write 'results.h5'.*(file size limit|disk full|File too large)", entry="Output/Directory",
        names_file=False),
    # Item 5: at the old limit of 1e6 rad/s a 1 s pendulum took 566 502 steps and 41 s of CPU.
    "angular_velocity_1e6": dict(
        files={"s.prm": pendulum().replace("set Rotation vector = 0, 0, 2.6179938779914944",
                                           "set Rotation vector = 0, 0, 2.6179938779914944\n  set Angular velocity = 0, 0, 1e6")},
        args=["run", "s.prm"], regex=r"Body bob/Angular velocity"),
    # Item 10: a JSON scene with its keys as a user writes them ("Body my_bob", where deal.II writes
    # "Body my_5fbob") ended with "You can't ask for entry <Kind> you have not yet declared".
    "json_scene_with_plain_keys_runs": dict(
        files={"s.json": JSON_PLAIN_KEYS}, args=["run", "s.json"], status=0, outputs=["probes.csv", "summary.json"]),
    # Item 5: 200 000 body names: the repeat check was pairwise and ran before the limit of 1000.
    "bodies_200000_names": dict(
        files={"s.prm": pendulum().replace("set Bodies  = bob", "set Bodies  = " + ", ".join(f"b{i}" for i in range(200000)))},
        args=["run", "s.prm"], regex=r"Multibody/Bodies.*names 200000 instances; at most 1000 are allowed"),
    # Item 8: a cusp and a curve that crosses itself were accepted as arms.
    "arm_with_a_cusp": dict(
        files={"s.prm": hostile_scenes.parametric("t^3", "t^2", start="-1", end="1")}, args=["modes", "s.prm"],
        regex=r"Arm/Curve.*turns its tangent by .* degrees between s = .*: a cusp or a kink"),
    "arm_crossing_itself": dict(
        files={"s.prm": hostile_scenes.parametric("sin(t)", "sin(2*t)", start="-0.5", end="3.6")},
        args=["modes", "s.prm"], regex=r"Arm/Curve.*crosses or touches itself: the parts near s = "),
    # Not refused: a whole ring (its two ends meet) and a helix whose turns are 1 mm apart.
    "arm_full_ring_is_read": dict(
        files={"s.prm": hostile_scenes.parametric("cos(t)", "sin(t)", start="0", end="6.283185307179586")}, args=["modes", "s.prm"],
        status=0, outputs=["frequencies.csv"]),
    "arm_tight_helix_is_read": dict(
        files={"s.prm": hostile_scenes.parametric("0.1*cos(t)", "0.1*sin(t)", "0.001*t/(2*pi)", start="0", end="18.84955592153876")},
        args=["modes", "s.prm"], status=0, outputs=["frequencies.csv"]),
    # Item 9: a full disk while writing mode shapes ended as deal.II's internal error (exit 4). A file
    # size limit of 4000 bytes lets the small files through and stops the first mode shape.
    "modes_write_error_in_mode_shapes": dict(
        files={"s.prm": hostile_scenes.arm(modes="20", elements="40")}, args=["modes", "s.prm", "-o", "out"],
        fsize_limit=4000, regex=r"cannot write 'out/mode_shapes_001.vtu': (File too large|No space)",
        entry="Output/Directory", names_file=False),
    # Item 8, many turns: 1024 samples do not resolve a curve of 200 turns, so its cusps and
    # crossings went unchecked; the samples now follow the total turn (0.1 rad apart, up to 65536).
    # A helix that climbs 100 turns and comes down the next 100 crosses its way up; a 64-turn
    # spiral that reverses at t = 100 has a cusp there; a 200-turn helix of 1 mm pitch is read.
    "arm_200_turns_crossing_itself": dict(
        files={"s.prm": hostile_scenes.parametric("0.1*cos(t)", "0.1*sin(t)", "0.05*sin(t/400)", start="0",
                                                  end="1256.6370614359173")},
        args=["modes", "s.prm"], regex=r"Arm/Curve.*crosses or touches itself: the parts near s = "),
    "arm_many_turns_with_a_cusp": dict(
        files={"s.prm": hostile_scenes.parametric("0.1*cos((t-100)^2)", "0.1*sin((t-100)^2)", "0.001*(t-100)^2/(2*pi)",
                                                  start="79.7", end="120")},
        args=["modes", "s.prm"], regex=r"Arm/Curve.*turns its tangent by .* degrees between s = 41\.\d* and .*: a cusp"),
    "arm_200_turn_helix_is_read": dict(
        files={"s.prm": hostile_scenes.parametric("0.1*cos(t)", "0.1*sin(t)", "0.001*t/(2*pi)", start="0",
                                                  end="1256.6370614359173")},
        args=["modes", "s.prm"], status=0, outputs=["frequencies.csv"]),
    # Issue 25, item 6: a misspelt entry or subsection in the file gave deal.II's message without the
    # subsection or the name meant; a misspelt selection printed the raw pattern.
    "file_misspelt_entry": dict(
        files={"s.prm": pendulum().replace("set End time", "set End tme")}, args=["run", "s.prm"],
        regex=r"line \d+ of the scene .*, in subsection 'Multibody': there is no entry 'End tme'; nearest declared: "
              r"'End time'", entry=""),
    "file_misspelt_subsection": dict(
        files={"s.prm": pendulum() + "subsection Joint pivto\n  set Kind = revolute\nend\n"}, args=["run", "s.prm"],
        regex=r"at the top level: there is no subsection 'Joint pivto'; nearest declared: 'Joint pivot'", entry=""),
    "file_selection_misspelt": dict(
        files={"s.prm": pendulum().replace("set Kind     = revolute", "set Kind     = revolutee")}, args=["run", "s.prm"],
        regex=r"in subsection 'Joint pivot': entry 'Kind' is 'revolutee'; allowed: fixed, revolute, spherical", entry=""),
    # results.h5 names its columns one string each: 1650 multiplier names of 63 characters do not
    # fit the 64 KiB of an HDF5 object header (exit 2 before the file used dense attribute storage).
    "chain_of_150_bodies_names_every_column": dict(
        files={"s.prm": "set Model = multibody\nsubsection Multibody\n  set Bodies = " +
               ", ".join(f"b{i}" for i in range(150)) + "\n  set Joints = " + ", ".join(f"j{i}" for i in range(150)) +
               "\n  set End time = 0.001\n  set Output interval = 0.001\n  set Gravity = 0, -9.81, 0\nend\n" +
               "".join(f"subsection Body b{i}\n  set Kind = rigid\n  set Mass = 1\n  set Inertia = 0.01, 0.01, 0.01, 0, 0, 0\n"
                       f"  set Position = {i + 0.5}, 0, 0\nend\nsubsection Joint j{i}\n  set Kind = revolute\n"
                       f"  set Body 1 = b{i}\n" + (f"  set Body 2 = b{i - 1}\n" if i else "") +
                       f"  set Position = {i}, 0, 0\n  set Axis = 0, 0, 1\nend\n" for i in range(150))},
        args=["run", "s.prm"], status=0, outputs=["results.h5", "summary.json"]),
    # Issue 26, item 1: --set is checked like the file's own entries; a misspelt name gets the
    # nearest declared ones, a bad value the entry's allowed values; nothing is written.
    "set_misspelt_entry": dict(
        files={"s.prm": pendulum()}, args=["run", "s.prm", "--set", "Multibody/End tme=2"],
        regex=r"--set.*'Multibody/End tme=2': there is no entry or subsection 'End tme' in subsection 'Multibody'; "
              r"nearest declared: 'End time'", entry="--set"),
    "set_misspelt_subsection": dict(
        files={"s.prm": pendulum()}, args=["run", "s.prm", "--set", "Multibdy/End time=2"],
        regex=r"there is no entry or subsection 'Multibdy' at the top level; nearest declared: 'Multibody'", entry="--set"),
    "set_value_outside_pattern": dict(
        files={"s.prm": pendulum()}, args=["run", "s.prm", "--set", "Joint pivot/Kind=hinge"],
        regex=r"--set.*'Joint pivot/Kind=hinge'.*hinge.*(revolute|allowed|match)", entry="--set"),
    "set_unknown_body_scope": dict(
        files={"s.prm": pendulum()}, args=["run", "s.prm", "--set", "Body ghost:Reduction/Number of normal modes=4"],
        regex=r"the scene has no body 'ghost'; its bodies: bob", entry="--set"),
    "set_rigid_body_scope": dict(
        files={"s.prm": pendulum()}, args=["run", "s.prm", "--set", "Body bob:Reduction/Number of normal modes=4"],
        regex=r"body 'bob' is rigid: it has no body scene", entry="--set"),
    "set_without_equals": dict(
        files={"s.prm": pendulum()}, args=["run", "s.prm", "--set", "Multibody/End time"],
        regex=r"expected ENTRY=VALUE", entry="--set", names_file=False),
    "set_value_with_a_line_break": dict(
        files={"s.prm": pendulum()}, args=["run", "s.prm", "--set", "Multibody/End time=1\nset Gravity = 0, 0, 0"],
        regex=r"a line break, '#' or a NUL character is not allowed", entry="--set", names_file=False),
    # Issue 24: 'auto' or a number in the two entries chosen for the scene by default.
    "maximum_order_seven": dict(
        files={"s.prm": pendulum(integrator="    set Maximum order = 7")}, args=["run", "s.prm"],
        regex=r"Multibody/Integrator/Maximum order.*is '7'; allowed: auto, 1, 2, 3, 4, 5"),
    "velocity_tolerance_word": dict(
        files={"s.prm": pendulum(integrator="    set Velocity tolerance = fast")}, args=["run", "s.prm"],
        regex=r"Multibody/Integrator/Velocity tolerance.*'fast' is not a finite number \('auto' or a number"),
    # Not refused: a smooth driver that is large but bounded runs.
    "driver_smooth_runs": dict(files={"s.prm": pendulum(driver="0.5*sin(2*pi*t)")}, args=["run", "s.prm"],
                               status=0, outputs=["probes.csv", "summary.json"]),
}

if __name__ == "__main__":
    sys.exit(hostile_scenes.main(CASES))
