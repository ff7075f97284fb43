#!/usr/bin/python3
"""Hostile and careless mesh files (issue 15, items 5, 6 and 9). Each case is a solid scene whose
Mesh file is one of tests/input/hostile_meshes/ (or, for what git cannot hold, a directory or a
device made here). `flextrack modes` must refuse it with exit status 2 and one printable line of
at most 400 characters that names the scene entry, the mesh file and says what is wrong, write
nothing, and finish within 5 s: no crash, no "internal error" (std::bad_alloc), no hang. The
cases 'valid_*' are the meshes the hostile ones were made from: they must be read and solved.

usage: hostile_meshes.py FLEXTRACK SOURCE_DIR WORK_DIR CASE
"""
import os
import resource
import re
import shutil
import subprocess
import sys

# The time limits are for the Release build; a Debug + sanitizer build is several times slower
# and scales them by FLEXTRACK_TIME_LIMIT_FACTOR (set by tests/CMakeLists.txt there).
TIME_FACTOR = float(os.environ.get("FLEXTRACK_TIME_LIMIT_FACTOR", "1"))

# name -> (mesh file: a file of tests/input/hostile_meshes, or a special made below; the message)
CASES = {
    # *NSET, GENERATE ranges that never end or name far more nodes than there are (bad_alloc or a hang before).
    "nset_generate_step_zero": ("nset_generate_step_zero.inp",
                                r"line 19: \*NSET, GENERATE from 1 to 8 by 0: allowed are first <= last and an increment >= 1"),
    "nset_generate_negative_step": ("nset_generate_negative_step.inp",
                                    r"line 19: \*NSET, GENERATE from 1 to 8 by -1: allowed are first <= last"),
    "nset_generate_huge_end": ("nset_generate_huge_end.inp",
                               r"line 19: \*NSET, GENERATE from 1 to 9223372036854775807 by 1 names 9223372036854775807 "
                               r"nodes, more than the 12 the file defines"),
    # Small files that multiply into any number of set members (made here: 1.6 MB and 700 kB).
    "nset_generate_ranges_multiply": ("<200000 GENERATE ranges of 1000 nodes>",
                                      r"line \d+: the node sets would hold more than 10000000 members in all; "
                                      r"allowed: at most 64 per node of the mesh"),
    "gmsh_physical_tags_multiply": ("<10000 points of 100000 physical groups>",
                                    r"line \d+: the node sets would hold more than 10000000 members in all"),
    # Counts in Gmsh files beyond what the file can hold (std::length_error / bad_alloc before).
    "gmsh_node_block_of_2_to_the_62": ("node_block_count_huge.msh",
                                       r"line 18: 4611686018427387904 nodes in a block announced, but the rest of the "
                                       r"file \(\d+ bytes\) can hold at most \d+; allowed: a count from 0 to \d+"),
    "gmsh_node_block_of_minus_5": ("node_block_count_negative.msh", r"line 18: -5 nodes in a block announced"),
    "gmsh_element_with_minus_1_tags": ("element_tags_negative.msh",
                                       r"line 28: element 1 announces -1 tags; its line holds 5 more numbers "
                                       r"\(allowed: 0 to 5\)"),
    "gmsh_element_with_2e9_tags": ("element_tags_huge.msh", r"line 28: element 1 announces 2000000000 tags"),
    "gmsh_element_block_of_2e9": ("element_block_count_huge.msh",
                                  r"line 48: 2000000000 elements in a block announced, but the rest of the file "
                                  r"\(52 bytes\) can hold at most 2"),
    "gmsh_element_block_of_minus_1": ("element_block_count_negative.msh", r"line 48: -1 elements in a block announced"),
    "gmsh_entity_with_2e9_physical_tags": ("entity_physical_tags_huge.msh",
                                           r"line 13: entity 1 announces 2000000000 physical tags; its line holds 2"),
    # Silent nonsense before: accepted.
    "duplicate_element_id_inp": ("duplicate_element_id.inp",
                                 r"line 17: element 1 is defined a second time \(first at line 16\); element numbers "
                                 r"must be unique"),
    "duplicate_element_id_msh": ("duplicate_element_id.msh",
                                 r"line 30: element 2 is defined a second time \(first at line 29\)"),
    "coincident_elements": ("coincident_elements.inp",
                            r"line 17: element 2 has the corner nodes of element 1 \(line 16\); two elements may not "
                            r"fill the same space"),
    "nset_names_missing_node": ("nset_missing_node.inp",
                                r"line 19: node set 'FIX' names node 99, which is not defined under \*NODE"),
    # Issue 23, item 8: an element flattened to 1e-12 m was accepted (its determinant small but even).
    "collapsed_element": ("collapsed_element.inp",
                          r"element 2 .* is collapsed: its Jacobian determinant is .* of that of a cube of its "
                          r"longest edge \(1 m; at least 1e-9 needed\)"),
    # Reported as an inverted element before.
    "duplicate_node_id_inp": ("duplicate_node_id.inp",
                              r"line 15: node 3 is defined a second time \(first at line 5\); node numbers must be unique"),
    "duplicate_node_id_msh": ("duplicate_node_id.msh", r"line 37: node 3 is defined a second time \(first at line 33\)"),
    # Reached the eigen solver before ("ARPACK dsaupd failed with code -9999"), or "zero length".
    "coordinate_nan_inp": ("coordinate_nan.inp",
                           r"line 9: node 7: the coordinate 'nan' is not allowed; a coordinate is a finite number "
                           r"from -1e9 to 1e9 m"),
    "coordinate_inf_inp": ("coordinate_inf.inp", r"line 9: node 7: the coordinate 'inf' is not allowed"),
    "coordinate_1e300_inp": ("coordinate_1e300.inp", r"line 9: node 7: the coordinate '1e300' is not allowed"),
    "coordinate_1e308_inp": ("coordinate_1e308.inp", r"line 9: node 7: the coordinate '1e308' is not allowed"),
    "coordinate_nan_msh": ("coordinate_nan.msh", r"line 37: node 7: the coordinate 'nan' is not allowed"),
    # Not a mesh file at all: said "not exist", or read forever (/dev/zero).
    "mesh_file_is_a_directory": ("<directory>", r"the mesh file '[^']*folder\.msh' is a directory, not a regular file"),
    "mesh_file_is_dev_zero": ("/dev/zero", r"the mesh file '/dev/zero' is a character device"),
    "mesh_file_links_to_dev_zero": ("<link to /dev/zero>", r"the mesh file '[^']*zero\.msh' is a character device"),
    # Sizes: a sparse file of 1.5 GiB (made here) is refused unread; a line of 2 MiB is not a mesh's.
    "mesh_file_over_1_gib": ("<sparse file of 1.5 GiB>",
                             r"the mesh file '[^']*huge\.msh' has 1610612736 bytes; a mesh file may have at most 1 GiB"),
    "line_of_2_mib": ("<a line of 2 MiB>", r"line 2: a line of more than 1 MiB; this is not a mesh file"),
    # Raw bytes echoed before: at most a short printable excerpt.
    "binary_bytes_in_element_lines": ("binary.inp", r"line 16: not a text file: the line holds the byte 0x"),
    "gzip_compressed_gmsh_file": ("gzip.msh", r"line 1: not a text file: the line holds the byte 0x"),
    "utf16_abaqus_file_with_byte_order_mark": ("utf16.inp", r"line 1: the file is UTF-16 text; save it as ASCII"),
    "utf16_gmsh_file": ("utf16.msh", r"line 1: not a text file: the line holds the byte 0x00"),
}
VALID = ["valid.inp", "valid_v2.msh", "valid_v4.msh"]
SOURCE = ""


def scene(mesh_file):
    return ("set Model = solid\nsubsection Solid\n  set Mesh = file\n  set Mesh file = " + mesh_file +
            "\n  set Supports = FIX: x, y, z\nend\nsubsection Modal analysis\n  set Number of modes = 4\nend\n")


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return path


def generate_ranges_multiply():
    """valid.inp with 988 more nodes and 200000 lines '1, 1000' of *NSET, GENERATE: 2e8 members."""
    with open(os.path.join(SOURCE, "tests", "input", "hostile_meshes", "valid.inp")) as f:
        valid = f.read().split("*ELEMENT")
    nodes = "".join(f"{i}, {i * 0.001}, 5, 5\n" for i in range(13, 1001))
    return valid[0] + nodes + "*ELEMENT" + valid[1] + "*NSET, NSET=ALL, GENERATE\n" + "1, 1000\n" * 200000


def physical_tags_multiply():
    """valid_v4.msh with a point entity in 100000 physical groups and 10000 point elements on it: 1e9 members."""
    with open(os.path.join(SOURCE, "tests", "input", "hostile_meshes", "valid_v4.msh")) as f:
        valid = f.read()
    point = "1 0 0 0 100000 " + " ".join(str(k) for k in range(1, 100001))
    valid = valid.replace("$Entities\n0 0 1 1\n", "$Entities\n1 0 1 1\n" + point + "\n")
    points = "0 1 15 10000\n" + "".join(f"{100 + k} 1\n" for k in range(10000))
    return valid.replace("$Elements\n2 3 1 3\n", "$Elements\n3 10003 1 10099\n" + points)


def mesh_path(spec, source, work):
    if spec == "<directory>":
        os.makedirs(os.path.join(work, "folder.msh"))
        return os.path.join(work, "folder.msh")
    if spec == "<link to /dev/zero>":
        os.symlink("/dev/zero", os.path.join(work, "zero.msh"))
        return os.path.join(work, "zero.msh")
    if spec == "<200000 GENERATE ranges of 1000 nodes>":
        return write(os.path.join(work, "ranges.inp"), generate_ranges_multiply())
    if spec == "<10000 points of 100000 physical groups>":
        return write(os.path.join(work, "physical_tags.msh"), physical_tags_multiply())
    if spec == "<sparse file of 1.5 GiB>":
        path = os.path.join(work, "huge.msh")
        with open(path, "wb") as f:
            f.truncate(3 << 29)
        return path
    if spec == "<a line of 2 MiB>":
        return write(os.path.join(work, "long_line.inp"), "*NODE\n1, " + "1" * (2 << 20) + ", 0, 0\n")
    if spec.startswith("/"):
        return spec
    return os.path.join(source, "tests", "input", "hostile_meshes", spec)


def child_cpu_seconds():
    """User + system CPU time of the finished child processes so far [s]: the time bound of a
    case is on CPU, not wall time, which grows with the machine's load (issue 25, item 16: a
    case took 7.9 s of wall time on a loaded machine)."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(exe, work, mesh):
    prm = os.path.join(work, "scene.prm")
    with open(prm, "w") as f:
        f.write(scene(mesh))
    out = os.path.join(work, "out")
    start = child_cpu_seconds()
    try:
        result = subprocess.run([exe, "modes", prm, "-o", out], capture_output=True, timeout=30 * TIME_FACTOR)
    except subprocess.TimeoutExpired:
        return None, "", child_cpu_seconds() - start, out
    return result.returncode, result.stderr.decode("latin-1"), child_cpu_seconds() - start, out


def main():
    global SOURCE
    exe, source, work, case = sys.argv[1:5]
    SOURCE = source
    work = os.path.join(work, case)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    if case.startswith("valid_"):
        failures = []
        for name in VALID:
            status, err, seconds, out = run(exe, work, mesh_path(name, source, work))
            print(f"{name}: exit {status} in {seconds:.1f} s {err.strip()}")
            if status != 0:
                failures.append(name)
        return 1 if failures else 0
    if case not in CASES:
        print(f"unknown case '{case}'; known: valid_meshes_are_read, " + ", ".join(CASES))
        return 1
    spec, expected = CASES[case]
    mesh = mesh_path(spec, source, work)
    status, err, seconds, out = run(exe, work, mesh)
    if mesh.startswith(work) and os.path.isfile(mesh) and os.path.getsize(mesh) > 1 << 20:
        os.remove(mesh)  # made here; not left in the build tree
    message = err.strip()
    print(f"{case}: exit {status} in {seconds:.2f} s: {message[:600]!r}")
    problems = []
    if status is None:
        problems.append("did not finish within 30 s")
    elif status != 2:
        problems.append(f"exit status {status}, expected 2")
    if seconds > 5 * TIME_FACTOR:
        problems.append(f"took {seconds:.1f} s of CPU, more than 5 s")
    if len(message.splitlines()) != 1:
        problems.append(f"{len(message.splitlines())} message lines, expected 1")
    if len(message) > 400 or any(not (32 <= ord(c) < 127) for c in message):
        problems.append("the message is longer than 400 characters or not printable ASCII")
    if "Solid/Mesh file" not in message or os.path.basename(mesh) not in message:
        problems.append("the message does not name the entry 'Solid/Mesh file' and the mesh file")
    if not re.search(expected, message):
        problems.append(f"the message does not say /{expected}/")
    if os.path.exists(out):
        problems.append("an output folder was written")
    for p in problems:
        print("FAIL: " + p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
