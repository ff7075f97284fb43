#!/usr/bin/python3
"""Hostile reduced-body files (issue 15, items 2, 3 and 6; issue 23, item 4): each is a valid
reduced body with one thing changed the way a crafted or damaged file would change it. Every one
must be refused by `flextrack inspect` and `flextrack export --format mbdyn` with exit status 2,
one message line that names the file, no crash (a signal, or exit 4 'internal error'), nothing
written, within 5 s.

Issue 23, item 4: bodies that are physically impossible but hold no NaN (mass -1 kg, an all-zero
mass matrix, -K, K[0,1] = 1e12, damping -100 I, ...) must be refused naming the property, both
as damaged (the content checksum no longer matches: the message says that too) and with the
checksum rewritten to match (as a crafted file would be: only the physical checks can see it).
Flipped bits that leave every value finite and plausible must be refused by the checksum. These
cases and the issue's flipped bits are also read as the 'Reduced body file' of a multibody scene
('flextrack run'), which must refuse them the same way.

usage: hostile_reduced_body.py FLEXTRACK VALID_BODY.h5 WORK_DIR
"""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

from reduced_body_checksum import content_checksum, flip_bits, rewrite_checksum

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
    # Format 4 (issue 25, items 4 and 13): section outlines, track stations, point masses.
    "section_outline_of_two_corners": (lambda f: replace_dataset(f, "/arms/boom/section_outline", np.zeros((2, 2))),
                                       "arm 'boom': dataset 'section_outline' is not K x 2 with 3 <= K <= 64"),
    "section_outline_nan": (fill("/arms/boom/section_outline", np.nan),
                            "'/arms/boom/section_outline' holds a non-finite value"),
    "section_outline_corner_2_km": (fill("/arms/boom/section_outline", 2000.0),
                                    "arm 'boom': 'section_outline' holds a corner beyond 1000 m"),
    "track_stations_minus_1": (lambda f: replace_attribute(f, "/arms/boom", "track_stations", np.int64(-1)),
                               "arm 'boom': attribute 'track_stations' = -1 is not from 0 to 100000"),
    "track_stations_missing": (lambda f: f["/arms/boom"].attrs.__delitem__("track_stations"), "track_stations"),
    "point_mass_at_a_missing_interface": (fill("/drawing/point_mass_interfaces", 7),
                                          "'/drawing/point_mass_interfaces' refers to a missing interface"),
    "point_mass_negative": (fill("/drawing/point_masses", -1.0),
                            "'/drawing/point_masses' holds a mass that is not in \\(0, 1e12\\) kg"),
}


def change_entries(path, change):
    """Replaces the values of dataset @p path by change(values) (a copy), in place."""
    def apply(f):
        data = np.array(f[path])
        f[path][...] = change(data)
    return apply


def set_entry(index, value):
    def change(data):
        data[index] = value
        return data
    return change


# Issue 23, item 4: physically impossible bodies without NaN. name -> (change, the property named).
M_, K_, C_ = "the reduced mass matrix \\(/reduced/mass\\)", "the reduced stiffness matrix \\(/reduced/stiffness\\)", \
    "the symmetric part of the reduced damping matrix \\(/reduced/damping\\)"
J_O = "the inertia tensor about the origin \\(/inertia/inertia_origin\\)"
physical_cases = {
    "mass_minus_1_kg": (change_entries("/inertia/mass", lambda m: -np.ones_like(m)),
                        "the mass \\(/inertia/mass\\) is not positive \\(-1.00e\\+00 kg\\)"),
    "mass_matrix_all_zero": (change_entries("/reduced/mass", np.zeros_like),
                             M_ + " is not positive definite \\(smallest eigenvalue 0.00e\\+00 kg, largest 0.00e\\+00 kg\\)"),
    "mass_matrix_with_a_negative_diagonal_entry": (change_entries("/reduced/mass", set_entry((0, 0), -0.5)),
                                                   M_ + " is not positive definite \\(smallest eigenvalue -"),
    "stiffness_negated": (change_entries("/reduced/stiffness", lambda K: -K),
                          K_ + " is not positive semi-definite \\(smallest eigenvalue -[0-9.]+e\\+[0-9]+ N/m"),
    "stiffness_01_is_1e12": (change_entries("/reduced/stiffness", set_entry((0, 1), 1e12)),
                             K_ + " is not symmetric: \\[0,1\\] = 1.00e\\+12 N/m but \\[1,0\\] = "),
    "damping_minus_100_I": (change_entries("/reduced/damping", lambda C: -100.0 * np.eye(C.shape[0])),
                            C_ + " is not positive semi-definite \\(smallest eigenvalue -1.00e\\+02 N s/m"),
    "frequency_negative": (change_entries("/reduced/frequencies_hz", lambda f: -f),
                           "frequency 0 \\(/reduced/frequencies_hz\\) is negative"),
    "inertia_origin_negated": (change_entries("/inertia/inertia_origin", lambda J: -J),
                               J_O + " has a principal moment that is not positive"),
    "inertia_origin_not_symmetric": (change_entries("/inertia/inertia_origin", lambda J: J + np.triu(np.ones((3, 3)), 1)),
                                     J_O + " is not symmetric: \\[0,1\\]"),
    "inertia_origin_violates_triangle_inequality": (
        change_entries("/inertia/inertia_origin", lambda J: np.diag([1.0, 1.0, 3.0])),
        J_O + " has principal moments 1.00e\\+00, 1.00e\\+00, 3.00e\\+00 kg m\\^2 that violate the triangle inequality"),
    "first_moment_100_times_too_large": (change_entries("/inertia/first_moment", lambda s: 100 * s),
                                         "the inertia tensor about the centre of mass .* is not positive semi-definite"),
}
for name, (change, expected) in physical_cases.items():
    cases[name] = (change, expected + ".*; also checksum mismatch: the file was changed or damaged after it was written")

    def changed_and_checksum_rewritten(f, change=change):
        change(f)
        rewrite_checksum(f)
    cases[name + "_checksum_rewritten"] = (changed_and_checksum_rewritten, expected + "(?!.*checksum mismatch)")

# Damage that leaves every value finite and physically plausible: only the checksum sees it.
MISMATCH = "checksum mismatch: the file was changed or damaged after it was written \\(content_checksum [0-9a-f]{16}, " \
           "its contents sum to [0-9a-f]{16}\\); reduce the body again"
checksum_cases = {
    # The case: 20 flipped bits changed a slider path by 7.5 mm, exit status 0.
    "twenty_flipped_bits_in_arm_modes": (lambda f: flip_bits(f, "/arms/boom/modes", 20), MISMATCH),
    "twenty_flipped_bits_in_mass_matrix": (lambda f: flip_bits(f, "/reduced/mass", 20), "checksum mismatch"),
    "one_flipped_bit_in_interface_modes": (lambda f: flip_bits(f, first_interface(f) + "/modes", 1), MISMATCH),
    "one_flipped_bit_in_drawing_quads": (change_entries("/drawing/quads", lambda q: q ^ np.uint32(1)), MISMATCH),
    "source_attribute_edited": (lambda f: replace_attribute(f, "/", "source", np.bytes_(b"elsewhere.prm")), MISMATCH),
    # An input hash edited to match another scene would make the cache take the file as up to date.
    "input_hash_edited": (lambda f: replace_attribute(f, "/", "input_hash", np.bytes_(b"0000000000000000")), MISMATCH),
    "n_normal_one_less": (lambda f: replace_attribute(f, "/", "n_normal", np.int64(f.attrs["n_normal"] - 1)), MISMATCH),
    "checksum_edited": (lambda f: replace_attribute(f, "/", "content_checksum", np.bytes_(b"0123456789abcdef")),
                        "content_checksum 0123456789abcdef, its contents sum to"),
    "checksum_missing": (lambda f: f.attrs.__delitem__("content_checksum"), "no valid content checksum"),
    "format_version_2": (lambda f: replace_attribute(f, "/", "format_version", np.int64(2)),
                         "format version 2 is not supported \\(this FlexTrack reads 4\\); reduce the body again"),
}
cases.update(checksum_cases)
# Read as a multibody scene's 'Reduced body file' too (each run costs a start of flextrack).
read_by_a_scene = set(physical_cases) | {"mass_minus_1_kg_checksum_rewritten", "twenty_flipped_bits_in_arm_modes"}

# The checksum as doc/reduced_body_file.md defines it, computed here from the file alone, equals
# the one flextrack wrote; and a file whose checksum is rewritten without any other change is
# accepted (so the refusals of the *_checksum_rewritten cases come from the physical checks).
with h5py.File(valid, "r") as f:
    stored, recomputed = f.attrs["content_checksum"].decode(), content_checksum(f)
print(f"content checksum: stored {stored}, recomputed from the file {recomputed}")
control = os.path.join(work, "unchanged_checksum_rewritten.h5")
shutil.copy(valid, control)
with h5py.File(control, "r+") as f:
    rewrite_checksum(f)
accepted = subprocess.run([exe, "inspect", control], capture_output=True, text=True, errors="replace")
print(f"unchanged file with its checksum rewritten: inspect exit {accepted.returncode} {accepted.stderr.strip()[:150]}")
if stored != recomputed or accepted.returncode != 0:
    print("FAILED: the checksum of doc/reduced_body_file.md is not the one flextrack writes, or an unchanged file "
          "was refused")
    sys.exit(1)

failures = []
for name, (change, expected) in cases.items():
    path = os.path.join(work, name + ".h5")
    shutil.copy(valid, path)
    with h5py.File(path, "r+") as f:
        change(f)
    commands = [["inspect", path], ["export", "--format", "mbdyn", path, "-o", os.path.join(work, name + "_out")]]
    if name in read_by_a_scene:
        scene = os.path.join(work, name + ".prm")
        with open(scene, "w") as out:
            out.write("set Model = multibody\nsubsection Multibody\n  set Bodies = boom\nend\n"
                      "subsection Body boom\n  set Kind = flexible\n  set Reduced body file = " + path + "\nend\n"
                      "subsection Output\n  set Directory = " + os.path.join(work, name + "_out") + "\nend\n")
        commands.append(["run", scene])
    for command in commands:
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
        print(f"{name:40s} {command[0]:7s} exit {run.returncode}: {message[:300]}")
        if problems:
            failures.append(f"{name} ({command[0]}): " + "; ".join(problems))

if failures:
    print("\nFAILED:\n  " + "\n  ".join(failures))
    sys.exit(1)
print(f"\nall {len(cases)} hostile reduced-body files refused cleanly by inspect and export "
      f"({len(read_by_a_scene)} also by a multibody scene)")
