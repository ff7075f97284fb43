#!/usr/bin/python3
"""Hostile reduced-body files (issue 15, items 2, 3 and 6): each is a valid reduced body with one
thing changed the way a crafted or damaged file would change it. Every one must be refused by
`flextrack inspect` and `flextrack export --format mbdyn` with exit status 2, one message line
that names the file, no crash (a signal, or exit 4 'internal error'), nothing written, within 5 s.

usage: hostile_reduced_body.py FLEXTRACK VALID_BODY.h5 WORK_DIR
"""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

# The time limits are for the Release build; a Debug + sanitizer build is several times slower
# and scales them by FLEXTRACK_TIME_LIMIT_FACTOR (set by tests/CMakeLists.txt there).
TIME_FACTOR = float(os.environ.get("FLEXTRACK_TIME_LIMIT_FACTOR", "1"))

exe, valid, work = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def replace_attribute(f, obj, name, value):
    del f[obj].attrs[name]
    f[obj].attrs[name] = value


def replace_dataset(f, path, value):
    del f[path]
    f[path] = value


def fill(path, value):
    def change(f):
        data = np.array(f[path])
        data[...] = value
        replace_dataset(f, path, data)
    return change


def first_interface(f):
    return "/interfaces/" + sorted(f["/interfaces"].keys())[0]


def rename_interface(new_name):
    def change(f):
        f.move(first_interface(f), "/interfaces/" + new_name)
    return change


def huge_stiffness(f):
    del f["/reduced/stiffness"]
    f.create_dataset("/reduced/stiffness", shape=(100000, 100000), dtype="f8", chunks=(100, 100))
    replace_attribute(f, "/", "n_modes", np.int64(100000))


def geometry_text(text):
    """Replaces the geometry text of the first arm (issue 10: the exact curve and frame)."""
    def change(f):
        path = "/arms/" + sorted(f["/arms"].keys())[0] + "/geometry_parameters"
        value = text(f[path][()].decode()) if callable(text) else text
        replace_dataset(f, path, np.bytes_(value.encode()))
    return change


# name -> (change, what the one-line message must contain)
cases = {
    # Item 3: attributes of an unexpected shape or type (SIGSEGV / heap corruption before).
    "n_modes_int64_array": (lambda f: replace_attribute(f, "/", "n_modes", np.arange(4096, dtype=np.int64)),
                            "attribute 'n_modes' of '/' is not a single integer"),
    "index_as_array": (lambda f: replace_attribute(f, first_interface(f), "index", np.zeros(16, dtype=np.int64)),
                       "attribute 'index' of '/interfaces/.*' is not a single integer"),
    "format_as_string_array": (lambda f: replace_attribute(f, "/", "format", np.array([b"x" * 64] * 1000, dtype="S64")),
                               "not a FlexTrack reduced body"),
    "format_as_float": (lambda f: replace_attribute(f, "/", "format", 1.5), "not a FlexTrack reduced body"),
    "n_modes_as_string": (lambda f: replace_attribute(f, "/", "n_modes", np.bytes_(b"47")),
                          "attribute 'n_modes' of '/' is not a single integer"),
    "n_modes_too_large": (lambda f: replace_attribute(f, "/", "n_modes", np.int64(100000)),
                          "'n_modes' = 100000 does not match"),
    "n_modes_negative": (lambda f: replace_attribute(f, "/", "n_modes", np.int64(-3)), "'n_modes' = -3 does not match"),
    "n_normal_beyond_modes": (lambda f: replace_attribute(f, "/", "n_normal", np.int64(2**40)),
                              "'n_normal' = 1099511627776 is outside"),
    "stiffness_as_integers": (lambda f: replace_dataset(f, "/reduced/stiffness",
                                                        np.array(f["/reduced/stiffness"]).astype(np.int64)),
                              "'/reduced/stiffness' has the wrong type"),
    # n_modes = 100000 and a stiffness dataset of that shape that stores nothing (unwritten chunks):
    # a small file that asks for 80 GB (bad_alloc before).
    "huge_counts_small_file": (huge_stiffness, "'/reduced/stiffness' of shape \\[100000, 100000\\] is too large"),
    # Item 6: non-finite numbers.
    "inertia_origin_inf": (fill("/inertia/inertia_origin", np.inf), "'/inertia/inertia_origin' holds a non-finite value"),
    "stiffness_nan": (fill("/reduced/stiffness", np.nan), "'/reduced/stiffness' holds a non-finite value"),
    "mode_shapes_nan": (fill("/drawing/mode_displacements", np.nan),
                        "'/drawing/mode_displacements' holds a non-finite value"),
    # Item 2: names that would escape into other tools' inputs.
    "interface_name_with_quote_and_newline": (rename_interface('tip" ; end\nbody: 99'), "a name has 1 to 64 characters"),
    "interface_name_too_long": (rename_interface("a" * 200), "a name has 1 to 64 characters"),
    # Issue 10: the arm's curve as parameter text, rebuilt and checked against the stored nodes.
    "geometry_text_of_another_arc": (geometry_text(lambda t: t.replace("set Radius = 0.4", "set Radius = 0.41")),
                                     "arm 'boom': the curve rebuilt from 'geometry_parameters' .* does not belong"),
    "geometry_text_includes_a_file": (geometry_text("include /etc/passwd\n"), "arm 'boom': .*includes another file"),
    "geometry_text_names_a_points_file": (
        geometry_text("subsection Curve\n set Kind = spline\n subsection Spline\n  set Points file = /etc/passwd\n"
                      " end\nend\n"), "arm 'boom': .*names a points file"),
    "geometry_text_9_MiB": (geometry_text("#" * (9 << 20)), "'/arms/boom/geometry_parameters' is a string of 9437184"),
    "geometry_text_not_a_parameter_file": (geometry_text("\x7fELF binary junk \xff\xfe"),
                                           "arm 'boom': .*(not a curve|character code)"),
}

failures = []
for name, (change, expected) in cases.items():
    path = os.path.join(work, name + ".h5")
    shutil.copy(valid, path)
    with h5py.File(path, "r+") as f:
        change(f)
    for command in (["inspect", path], ["export", "--format", "mbdyn", path, "-o", os.path.join(work, name + "_out")]):
        try:
            run = subprocess.run([exe] + command, capture_output=True, text=True, errors="replace", timeout=5 * TIME_FACTOR)
        except subprocess.TimeoutExpired:
            failures.append(f"{name} ({command[0]}): did not finish within 5 s")
            continue
        message = run.stderr.strip()
        import re
        problems = []
        if run.returncode != 2:
            problems.append(f"exit status {run.returncode}, expected 2")
        if len(message.splitlines()) != 1:
            problems.append(f"{len(message.splitlines())} message lines, expected 1")
        if path not in message:
            problems.append("the message does not name the file")
        if not re.search(expected, message):
            problems.append(f"the message does not say /{expected}/")
        if os.path.exists(os.path.join(work, name + "_out")):
            problems.append("an output folder was written")
        print(f"{name:40s} {command[0]:7s} exit {run.returncode}: {message[:150]}")
        if problems:
            failures.append(f"{name} ({command[0]}): " + "; ".join(problems))

if failures:
    print("\nFAILED:\n  " + "\n  ".join(failures))
    sys.exit(1)
print(f"\nall {len(cases)} hostile reduced-body files refused cleanly by inspect and export")
