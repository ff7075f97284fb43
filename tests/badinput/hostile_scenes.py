#!/usr/bin/python3
"""Hostile and careless scenes and command lines (issue 15, items 4, 5, 6, 7, 8 and 9). Each case
writes the scene files it needs into its own work folder, runs one flextrack command there and
checks the outcome the issue asks for:

- refused input: exit status 2, one printable line of at most 400 characters on stderr that names
  the file and the entry (where there is one) and says what is wrong (a regular expression per
  case), nothing in the output folder, within 5 s (a resource bomb must be refused before it
  allocates, not after);
- accepted input: exit status 0 and the files the case names.

The inputs are those the issue reports (nesting that overflowed the stack, counts that ended in
std::bad_alloc or ran until killed, values that reached the eigen solver, write errors).

usage: hostile_scenes.py FLEXTRACK WORK_DIR CASE [MPIRUN]
"""
import os
import re
import resource
import shutil
import signal
import subprocess
import sys

# The time limits are for the Release build; a Debug + sanitizer build is several times slower
# and scales them by FLEXTRACK_TIME_LIMIT_FACTOR (set by tests/CMakeLists.txt there).
TIME_FACTOR = float(os.environ.get("FLEXTRACK_TIME_LIMIT_FACTOR", "1"))

# The small body (tests/input/small_body.prm) hinged to the ground, run for 10 ms.
PENDULUM_OF_SMALL_BODY = """set Model = multibody
subsection Multibody
  set Bodies = b
  set Joints = pivot
  set End time = 0.01
  set Output interval = 0.005
end
subsection Body b
  set Kind = flexible
  set Body scene = s.prm
end
subsection Joint pivot
  set Kind = revolute
  set Body 1 = b
  set Body 2 = ground
  set Position = 0, 0, 0
  set Axis = 0, 0, 1
end
"""

# A straight steel cantilever (the arm scene of tests/input/straight_cantilever.prm).
ARM = """subsection Arm
  subsection Curve
    set Kind = {kind}
{curve}
  end
  subsection Cross section
    set Shape = circle
    set Diameter = 0.01
  end
  subsection Mesh
    set Number of elements = {elements}
    set Element degree = 2
  end
end
subsection Modal analysis
  set Number of modes = {modes}
{modal}
end
"""


def arm(kind="line", curve="    subsection Line\n      set End point = 3, 0, 0\n    end", elements="4", modes="4",
        modal=""):
    return ARM.format(kind=kind, curve=curve, elements=elements, modes=modes, modal=modal)


def parametric(x, y="0", z="0", start="0", end="1"):
    return arm("parametric", f"""    subsection Parametric
      set x(t) = {x}
      set y(t) = {y}
      set z(t) = {z}
      set Parameter start = {start}
      set Parameter end = {end}
    end""")


def box(cells="4, 1, 1"):
    return f"""set Model = solid
subsection Solid
  set Mesh = box
  subsection Box
    set Size  = 1, 0.1, 0.1
    set Cells = {cells}
  end
  set Supports = XMIN: x, y, z
end
subsection Modal analysis
  set Number of modes = 3
end
"""


def nested_json(depth):
    return '{"a": ' * depth + "1" + "}" * depth


def spline_points(n):
    return "".join(f"{i * 1e-3:.6f} {1e-4 * (i % 7):.6f} 0\n" for i in range(n))


# Two unit cubes (C3D8) that share no node; node set FIX holds one face of the first cube only.
TWO_PARTS = """*NODE
1, 0, 0, 0
2, 1, 0, 0
3, 1, 1, 0
4, 0, 1, 0
5, 0, 0, 1
6, 1, 0, 1
7, 1, 1, 1
8, 0, 1, 1
9, 3, 0, 0
10, 4, 0, 0
11, 4, 1, 0
12, 3, 1, 0
13, 3, 0, 1
14, 4, 0, 1
15, 4, 1, 1
16, 3, 1, 1
*ELEMENT, TYPE=C3D8, ELSET=EALL
1, 1, 2, 3, 4, 5, 6, 7, 8
2, 9, 10, 11, 12, 13, 14, 15, 16
*NSET, NSET=FIX
1, 4, 5, 8
"""
TWO_PARTS_SCENE = """set Model = solid
subsection Solid
  set Mesh = file
  set Mesh file = two_parts.inp
  set Supports = FIX: x, y, z
end
subsection Modal analysis
  set Number of modes = 4
end
"""

SPLINE = arm("spline", "    subsection Spline\n      set Points file = points.txt\n    end")

# name -> dict(files={name: text or bytes or callable}, args=[command, scene, ...], status, regex,
# entry (text the message must hold besides the file name), outputs (files of an accepted run))
CASES = {
    # Item 4: nesting that overflowed the stack (SIGSEGV before).
    "expression_100000_nested_parentheses": dict(
        files={"s.prm": parametric("(" * 100000 + "t" + ")" * 100000)}, args=["modes", "s.prm"],
        regex=r"x\(t\).*has 200001 characters; at most 10000 are allowed"),
    "expression_nested_4000_deep": dict(
        files={"s.prm": parametric("(" * 4000 + "t" + ")" * 4000)}, args=["modes", "s.prm"],
        regex=r"x\(t\).*nested deeper than 200 levels"),
    "expression_sum_of_200000_terms": dict(
        files={"s.prm": parametric("t" + "+t" * 200000)}, args=["modes", "s.prm"],
        regex=r"x\(t\).*characters; at most 10000 are allowed"),
    "expression_100000_unary_minus": dict(
        files={"s.prm": parametric("-" * 100000 + "t")}, args=["modes", "s.prm"],
        regex=r"x\(t\).*characters; at most 10000"),
    "expression_3000_unary_minus": dict(
        files={"s.prm": parametric("-" * 3000 + "t")}, args=["modes", "s.prm"],
        regex=r"x\(t\).*nested deeper than 200 levels"),
    "expression_power_tower_50000": dict(
        files={"s.prm": parametric("t" + "^t" * 50000)}, args=["modes", "s.prm"],
        regex=r"x\(t\).*characters; at most 10000"),
    "expression_power_tower_300": dict(
        files={"s.prm": parametric("t" + "^1" * 300)}, args=["modes", "s.prm"],
        regex=r"x\(t\).*nested deeper than 200 levels"),
    # A long but flat sum is fine: evaluation does not recurse ((t + ... + t) / 3000 = t, 3000 terms).
    "expression_sum_of_3000_terms_is_read": dict(
        files={"s.prm": parametric("(t" + "+t" * 2999 + ")/3000")}, args=["modes", "s.prm"],
        status=0, outputs=["frequencies.csv", "summary.json"]),
    "scene_includes_itself": dict(
        files={"s.prm": "include s.prm\n" + arm()}, args=["modes", "s.prm"],
        regex=r"includes are nested more than 8 deep", entry="include"),
    "json_nested_100000_deep": dict(
        files={"s.json": nested_json(100000)}, args=["modes", "s.json"], regex=r"JSON nested more than 64 deep",
        entry=""),
    # Item 5: resource bombs (std::bad_alloc, "internal error", or killed before).
    "arm_2147483647_elements": dict(
        files={"s.prm": arm(elements="2147483647")}, args=["modes", "s.prm"], regex=r"Number of elements"),
    "box_2147483647_cells": dict(
        files={"s.prm": box("2147483647, 1, 1")}, args=["modes", "s.prm"], regex=r"Box/Cells"),
    "spline_of_200000_points": dict(
        files={"s.prm": SPLINE, "points.txt": spline_points(200000)}, args=["modes", "s.prm"],
        regex=r"Points file.*more than 100000 points; at most 100000"),
    "converge_12_refinements_of_a_box": dict(
        files={"s.prm": box()}, args=["converge", "s.prm", "--refinements", "12"],
        regex=r"Solid/Mesh after 12 refinements.*allowed: at most 1000000 cells", entry="Solid/Mesh"),
    "converge_12_refinements_of_an_arm": dict(
        files={"s.prm": arm(elements="100")}, args=["converge", "s.prm", "--refinements", "12"],
        regex=r"Number of elements.*refinement"),
    # Item 6: silent nonsense (exit 0 with absurd results before).
    "helix_of_1e9_turns": dict(
        files={"s.prm": arm("helix", "    subsection Helix\n      set Turns = 1e9\n    end")},
        args=["modes", "s.prm"], regex=r"Turns"),
    "tan_across_its_pole": dict(
        files={"s.prm": parametric("t", "tan(t)", start="0", end="2")}, args=["modes", "s.prm"],
        regex=r"Curve"),
    "mesh_with_a_loose_part": dict(
        files={"s.prm": TWO_PARTS_SCENE, "two_parts.inp": TWO_PARTS}, args=["modes", "s.prm"],
        regex=r"Solid/Supports.*2 parts that share no node.*1 cells around \(3.5, 0.5, 0.5\) m has no support"),
    "shift_nan": dict(files={"s.prm": arm(modal="  set Shift = nan")}, args=["modes", "s.prm"],
                      regex=r"Modal analysis/Shift.*not a finite number"),
    # Item 9: reached ARPACK before ("dsaupd failed with code -9999", exit 3, no entry named).
    "shift_1e300": dict(files={"s.prm": arm(modal="  set Shift = 1e300")}, args=["modes", "s.prm"],
                        regex=r"Modal analysis/Shift.*allowed: 'auto' or a number from -1e16 to 1e16"),
    "line_end_at_1e308": dict(
        files={"s.prm": arm(curve="    subsection Line\n      set End point = 1e308, 0, 0\n    end")},
        args=["modes", "s.prm"], regex=r"End point"),
    # Raw bytes echoed whole before; a directory or a device said "not to exist".
    "scene_is_binary": dict(files={"s.prm": bytes(range(256)) * 64}, args=["modes", "s.prm"], regex=r".", entry=""),
    "scene_is_utf16": dict(files={"s.prm": "\ufeff".encode("utf-16-le") + arm().encode("utf-16-le")},
                           args=["modes", "s.prm"], regex=r".", entry=""),
    "value_of_50_mb": dict(files={"s.prm": lambda: arm(modes="1" + "2" * 50_000_000)}, args=["modes", "s.prm"],
                           regex=r"larger than 16 MiB", entry=""),
    "value_of_1_mb": dict(files={"s.prm": lambda: arm(modes="1" + "2" * 1_000_000)}, args=["modes", "s.prm"],
                          regex=r"Number of modes", entry="Number of modes"),
    "scene_is_a_directory": dict(files={"s.prm": "<directory>"}, args=["modes", "s.prm"], regex=r"is a folder, not a parameter file",
                                 entry=""),
    "scene_is_dev_zero": dict(files={}, args=["modes", "/dev/zero"], regex=r"is not a regular file", entry=""),
    # Item 7: write errors. The output files are staged and renamed, so a link to /dev/full in the
    # folder is replaced, not written through; a file-size limit (EFBIG, like a full disk) must be
    # reported as a write error with nothing half-written left behind.
    "frequencies_csv_links_to_dev_full": dict(
        files={"s.prm": arm(), "out/frequencies.csv": "<link to /dev/full>"}, args=["modes", "s.prm", "-o", "out"],
        status=0, outputs=["frequencies.csv", "summary.json"]),
    "write_error_file_size_limit": dict(
        files={"s.prm": arm(modes="20", elements="40")}, args=["modes", "s.prm", "-o", "out"], fsize_limit=400,
        status=(2, 3), regex=r"cannot write 'out/[a-z_.]+': (File too large|No space)", entry="Output/Directory",
        names_file=False),
    # HDF5 writes most of a file at its close: a full disk there left a truncated reduced_body.h5
    # under its final name and a crash in MPI_Finalize (SIGSEGV).
    "reduce_write_error_file_size_limit": dict(
        files={"s.prm": "<small body>"}, args=["reduce", "s.prm", "-o", "out"], fsize_limit=20000, status=(2, 3),
        regex=r"reduced_body.h5.*(File too large|No space|disk full)", entry="", names_file=False),
    # A cached reduced body whose input hash matches but whose stiffness is NaN ("up to date,
    # nothing recomputed" before): it is checked on read, reported unusable and rebuilt.
    "cached_body_with_nan_stiffness_is_rebuilt": dict(
        files={"s.prm": "<small body>"}, before=["reduce", "s.prm", "-o", "out"], tamper="nan_stiffness",
        args=["reduce", "s.prm", "-o", "out"], status=0, outputs=["reduced_body.h5", "summary.json"],
        stdout=r"reduced_body.h5 is unusable \(.*stiffness.*\): recomputing"),
    # Issue 23, item 4: a cached body with 20 flipped mantissa bits in its arm's mode shapes (finite,
    # each value near its old one) was "up to date"; its checksum no longer matches. One whose
    # mass is -1 kg under a matching checksum (rewritten) fails the physical checks. Both are
    # reduced again, and the log says why.
    "cached_body_with_20_flipped_bits_is_rebuilt": dict(
        files={"s.prm": "<small body>"}, before=["reduce", "s.prm", "-o", "out"], tamper="flip_bits",
        args=["reduce", "s.prm", "-o", "out"], status=0, outputs=["reduced_body.h5", "summary.json"],
        stdout=r"reduced_body.h5 is unusable \(.*checksum mismatch: the file was changed or damaged.*\): recomputing"),
    "cached_body_of_negative_mass_with_matching_checksum_is_rebuilt": dict(
        files={"s.prm": "<small body>"}, before=["reduce", "s.prm", "-o", "out"], tamper="negative_mass",
        args=["reduce", "s.prm", "-o", "out"], status=0, outputs=["reduced_body.h5", "summary.json"],
        stdout=r"reduced_body.h5 is unusable \(.*the mass \(/inertia/mass\) is not positive \(-1.00e\+00 kg\)\)"
               r": recomputing"),
    # A multibody run whose body scene's cached body is damaged but carries the right input hash:
    # the run decided from the hash alone that nothing was to be reduced, did not start MPI, and
    # aborted in the reduction that followed (exit status 1). It reduces again and runs.
    "multibody_run_rebuilds_a_damaged_cached_body": dict(
        files={"s.prm": "<small body>", "m.prm": PENDULUM_OF_SMALL_BODY}, before=["run", "m.prm"],
        tamper="flip_bits", tampered="output/s/reduced_body.h5", args=["run", "m.prm"], status=0,
        outputs=["monitors.csv", "summary.json"],
        stdout=r"output/s/reduced_body.h5 is unusable \(.*checksum mismatch.*\): recomputing"),
    "track_stations_2147483647": dict(
        files={"s.prm": "<small body>", "t.prm": "include s.prm\nsubsection Reduction\n  set Track arms = boom\n"
               "  set Track stations = 2147483647\nend\n"}, args=["reduce", "t.prm"],
        regex=r"Track stations.*allowed: 1 to 1000"),
    "stale_mode_shapes_removed": dict(
        files={"s.prm": arm(modes="6"), "t.prm": arm(modes="2")}, args=["modes", "t.prm", "-o", "out"],
        before=["modes", "s.prm", "-o", "out"], status=0, outputs=["frequencies.csv"], stale=["mode_5", "mode_6"]),
    # Item 8: reduce under mpirun (internal error from every rank before; refused from
    # 2026-11 on; distributed since issue 27: the first process writes one complete file).
    "mpirun_reduce": dict(files={"s.prm": "<small body>"}, args=["reduce", "s.prm", "-o", "out"], mpi=2,
                          status=0, outputs=["reduced_body.h5", "summary.json"]),
    # A multibody run under mpirun: every process would simulate and write the same files, and
    # reduce its flexible bodies together while each held their cache lock (a deadlock).
    "mpirun_run_multibody": dict(files={"s.prm": "<small body>", "m.prm": PENDULUM_OF_SMALL_BODY},
                                 args=["run", "m.prm"], mpi=2, status=2,
                                 regex=r"m.prm: 'flextrack run' of a multibody scene runs on one process: start it "
                                       r"without mpirun", entry="", names_file=False),
    # A distributed reduction whose first process cannot write: every process ends (MPI_Abort),
    # none waits for ever in a collective step.
    "mpirun_reduce_unwritable_output": dict(files={"s.prm": "<small body>"},
                                            args=["reduce", "s.prm", "-o", "/proc/flextrack_reduce"], mpi=2,
                                            status=2, regex=r"cannot create the output folder '/proc/flextrack_reduce",
                                            entry="", names_file=False),
}


def make_files(case, work, source):
    for name, text in case.get("files", {}).items():
        path = os.path.join(work, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        if callable(text):
            text = text()
        if text == "<directory>":
            os.makedirs(path)
        elif text == "<link to /dev/full>":
            os.symlink("/dev/full", path)
        elif text == "<small body>":
            shutil.copy(os.path.join(source, "tests", "input", "small_body.prm"), path)
        else:
            with open(path, "wb") as f:
                f.write(text if isinstance(text, bytes) else text.encode())


def child_cpu_seconds():
    """User + system CPU time of the finished child processes so far [s]: the time bound of a
    case is on CPU, not wall time, which grows with the machine's load (issue 25, item 16: a
    case took 7.9 s of wall time on a loaded machine)."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(exe, work, args, case, mpirun):
    # OpenMPI refuses to start as root (CI runs as root) unless told it may.
    env = dict(os.environ, TMPDIR=work, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    command = [exe] + args
    if case.get("mpi"):
        command = [mpirun, "--oversubscribe", "-np", str(case["mpi"])] + command
    limit = case.get("fsize_limit")

    def preexec():
        if limit:
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # write() fails with EFBIG instead of a signal
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    start = child_cpu_seconds()
    try:
        p = subprocess.run(command, cwd=work, env=env, capture_output=True, timeout=60 * TIME_FACTOR, preexec_fn=preexec)
        status, err = p.returncode, p.stderr.decode("utf-8", "replace")
        case["stdout_text"] = p.stdout.decode("utf-8", "replace")
    except subprocess.TimeoutExpired:
        status, err = None, ""
    return status, err, child_cpu_seconds() - start


def main(cases=None):
    """Runs the case named on the command line, from @p cases (default: CASES)."""
    cases = CASES if cases is None else cases
    exe, work, name = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2]), sys.argv[3]
    mpirun = sys.argv[4] if len(sys.argv) > 4 else "mpirun"
    source = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    case = cases[name]
    work = os.path.join(work, name)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    make_files(case, work, source)
    problems = []
    if "before" in case:
        status, err, _ = run(exe, work, case["before"], {}, mpirun)
        if status != 0:
            problems.append(f"the first run ({' '.join(case['before'])}) failed: {status} {err[:300]}")
    if case.get("tamper"):
        import h5py
        from reduced_body_checksum import flip_bits, rewrite_checksum
        with h5py.File(os.path.join(work, case.get("tampered", "out/reduced_body.h5")), "r+") as f:
            if case["tamper"] == "nan_stiffness":
                f["/reduced/stiffness"][0, 0] = float("nan")
            elif case["tamper"] == "flip_bits":
                flip_bits(f, "/arms/boom/modes", 20)
            elif case["tamper"] == "negative_mass":
                f["/inertia/mass"][0] = -1.0
                rewrite_checksum(f)
    status, err, seconds = run(exe, work, case["args"], case, mpirun)
    message = err.strip()
    if case.get("mpi"):  # mpirun adds its own lines about the exit status; only flextrack's count
        message = "\n".join(l for l in message.splitlines() if l.startswith("flextrack"))
    print(f"{name}: exit status {status} after {seconds:.2f} s; stderr: {message[:400]}")
    expected = case.get("status", 2)
    expected = expected if isinstance(expected, tuple) else (expected,)
    # The output folder: -o, else output/<scene file stem> (no sample scene sets Output/Directory).
    out = os.path.join(work, "out") if "-o" in case["args"] else os.path.join(
        work, "output", os.path.splitext(os.path.basename(case["args"][1]))[0])
    # Files no run may create anywhere (a command smuggled into a script: touch PWNED).
    for folder, _, names in os.walk(work):
        for f in case.get("absent", []):
            if f in names:
                problems.append(f"a file {f} appeared in {folder}: input text ran a command")
    if status is None:
        problems.append("did not finish within 60 s")
    elif status not in expected:
        problems.append(f"exit status {status}, expected {' or '.join(map(str, expected))}")
    if status == 0:
        if "stdout" in case and not re.search(case["stdout"], case.get("stdout_text", "")):
            problems.append(f"the log does not say /{case['stdout']}/")
        for f in case.get("outputs", []):
            if not os.path.isfile(os.path.join(out, f)) or os.path.getsize(os.path.join(out, f)) == 0:
                problems.append(f"no output file {f}")
        for prefix in case.get("stale", []):
            left = [f for f in os.listdir(out) if f.startswith(prefix)]
            if left:
                problems.append("files of the previous run left in the output folder: " + ", ".join(left))
    else:
        if seconds > 5 * TIME_FACTOR:
            problems.append(f"took {seconds:.1f} s of CPU, more than 5 s")
        if len(message.splitlines()) != 1:
            problems.append(f"{len(message.splitlines())} message lines, expected 1")
        if len(message) > 400 or any(not (32 <= ord(c) < 127) for c in message):
            problems.append("the message is longer than 400 characters or not printable ASCII")
        scene = case["args"][1]
        entry = case.get("entry")
        if entry is None:
            entry = re.sub(r"\\.*", "", case.get("regex", "").split(".*")[0])
        if (case.get("names_file", True) and os.path.basename(scene) not in message) or entry not in message:
            problems.append(f"the message does not name the file '{os.path.basename(scene)}' and the entry '{entry}'")
        if not re.search(case.get("regex", "^$"), message):
            problems.append(f"the message does not say /{case.get('regex', '')}/ (exit status {status}): {message[:300]}")
        if os.path.isdir(out) and [f for f in os.listdir(out) if not os.path.islink(os.path.join(out, f))]:
            problems.append("files were left in the output folder: " + ", ".join(sorted(os.listdir(out)))[:200])
    for p in problems:
        print("FAIL: " + p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
