#!/usr/bin/python3
"""Property test of issue 15 (acceptance, item 6): every numeric entry that `flextrack
print-parameters` lists is set, in turn, to nan, inf, -1, 0 and 1e300 in a sample scene, and the
command must either run validly (exit 0, only finite numbers in summary.json) or refuse cleanly
(exit 2, one line on stderr that names the scene file and the entry, nothing in the output
folder). Anything else fails: exit 1, 3 or 4, a signal, more than TIMEOUT seconds, a non-finite
number in the results, a message that does not name the file or the entry.

Numeric entries are found in print-parameters itself, so a new entry is swept without editing
this file: an entry whose default is a number or a list of numbers, or 'auto' for a quantity
with a unit. Entries that hold numbers inside text (supports, interfaces, ties, point masses,
planes, constants) get the value through a template below; an entry whose documentation names a
unit but that is neither numeric nor templated nor listed as text makes the test fail, so that
it is classified rather than silently skipped.

Scenes: tests/input/straight_cantilever.prm (Model = arm, `modes`), tests/input/solid_box.prm
(Model = solid, `modes`), tests/input/small_body.prm (Model = body, `reduce`) and
tests/input/static_cantilever.prm (Static and Load case NAME, `static`). An entry is
swept in each scene that reads its section (Modal analysis and Output in all three; the entries
of "Arm NAME" as "Arm boom" in the body scene).

An entry is swept where it is used: for an entry of a curve kind, a section shape or a mesh
generator the override also selects that kind (CONTEXT below), e.g. 'Arc/Radius' comes with
'Curve/Kind = arc' and 'Iy' with 'Shape = explicit' and valid explicit section values.

Default run (ctest label badinput, about 250 runs): a deterministic subset. Every entry is swept
once, in the first scene that reads it (Arm in the arm scene, Solid in the solid scene, Body,
Reduction and the body-only templates in the body scene; Modal analysis and Output in the arm
scene). Entries whose text goes through a deal.II Double or Integer pattern (a plain number or
list of numbers as default), which refuses nan and inf for every such entry alike, get -1, 0 and
1e300; all others (expressions, 'auto' entries, numbers inside text) get all five values.
--full (ctest label stress, about 630 runs; `ctest -C stress -L stress`) sweeps every entry with all five values in every
scene that reads it.

usage: numeric_entries.py FLEXTRACK SOURCE_DIR WORK_DIR [--full] [--jobs N] [--timeout S]
"""
import argparse
import concurrent.futures
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import time

# The time limits are for the Release build; a Debug + sanitizer build is several times slower
# and scales them by FLEXTRACK_TIME_LIMIT_FACTOR (set by tests/CMakeLists.txt there).
TIME_FACTOR = float(os.environ.get("FLEXTRACK_TIME_LIMIT_FACTOR", "1"))

VALUES = ["nan", "inf", "-1", "0", "1e300"]

# Scenes: file, command, and how the sections of print-parameters map to the scene's sections
# (None: the scene does not read that section).
SCENES = {
    "arm": ("tests/input/straight_cantilever.prm", "modes",
            {"Arm": "Arm", "Modal analysis": "Modal analysis", "Output": "Output"}),
    "solid": ("tests/input/solid_box.prm", "modes",
              {"Solid": "Solid", "Modal analysis": "Modal analysis", "Output": "Output"}),
    "body": ("tests/input/small_body.prm", "reduce",
             {"Body": "Body", "Solid": "Solid", "Arm NAME": "Arm boom", "Reduction": "Reduction",
              "Modal analysis": "Modal analysis", "Output": "Output"}),
    "static": ("tests/input/static_cantilever.prm", "static",
               {"Static": "Static", "Load case NAME": "Load case tip"}),
    "multibody": ("tests/input/small_pendulum.prm", "run",
                  {"Multibody": "Multibody", "Body NAME": "Body bob", "Joint NAME": "Joint pivot",
                   "Force NAME": "Force spring", "Probe NAME": "Probe tip", "Output": "Output"}),
}
# The subset: each top-level section in one scene only.
SUBSET_SCENE = {"Arm": "arm", "Arm NAME": None, "Solid": "solid", "Body": "body", "Reduction": "body",
                "Modal analysis": "arm", "Output": "arm", "Multibody": "multibody", "Body NAME": "multibody",
                "Joint NAME": "multibody", "Force NAME": "multibody", "Probe NAME": "multibody",
                "Static": "static", "Load case NAME": "static"}

# Entries holding numbers inside text: entry name -> [(label, template with {v})]. Names of the
# sample scenes: arm 'boom', interface 'tip', output point 'corner'.
TEMPLATES = {
    "Intermediate": [("arc length", "{v}: pinned")],
    "Ties": [("radius", "boom: rigid, within {v}")],
    "Interfaces": [("arc length", "tip: arm boom at {v}"), ("point", "tip: point {v} {v} {v}, within 0.03")],
    "Output points": [("point", "corner: point {v} {v} {v}, within 0.03"),
                      ("radius", "corner: point 0.1 0.1 0.1, within {v}")],
    "Point masses": [("mass", "tip: {v}, 1e-5, 1e-5, 1e-5"), ("inertia", "tip: 0.2, {v}, {v}, {v}")],
    "Supports": [("plane", "XMIN: x, y, z; y = {v}: y")],
    "Constants": [("value", "c = {v}")],
    "Force": [("x", "{v}; 0; 0")],
    "Torque": [("z", "0; 0; {v}")],
    "Euler parameters": [("p0", "{v}, 0, 0, 0")],
    "Inline points": [("x", "0 0 0; {v} 1 0")],
    # 'flextrack static' (issue 12): arc lengths and load values of tests/input/static_cantilever.prm
    "Points": [("arc length", "{v}")],
    "Point forces": [("arc length", "{v}: 0 0 1"), ("force", "1: {v} 0 0")],
    "Point moments": [("arc length", "{v}: 0 0 1"), ("moment", "1: {v} 0 0")],
    "Line loads": [("start", "{v} 2: 0 0 1"), ("load", "1 2: {v} 0 0")],
    # the arm scene has no solid: every pressure is refused there, naming the entry
    "Pressures": [("pressure", "XMAX: {v}")],
    "Node forces": [("force", "XMAX: {v} 0 0")],
    "Support displacements": [("arc length", "{v}: 0 0 0"), ("displacement", "0: {v} 0 0")],
}
# Context of an entry: (section path as printed, with "Arm" standing for "Arm" and "Arm NAME") ->
# settings [(path below the arm or top section, entry, value)] that make the scene use the entry.
CURVE = {"Line": "line", "Arc": "arc", "Helix": "helix", "Parametric": "parametric", "Arc length": "arc length",
         "Spline": "spline"}
EXPLICIT_SECTION = [(["Cross section"], "Shape", "explicit"), (["Cross section"], "Area", "3e-4"),
                    (["Cross section"], "Iy", "8e-9"), (["Cross section"], "Iz", "8e-9"),
                    (["Cross section"], "Torsion constant", "1.6e-8")]


def context(path, name):
    """Settings [(path, entry, value)] that make the scene read entry @p name of @p path."""
    arm, rest = path[0], path[1:]
    settings = []
    if arm in ("Arm", "Arm NAME") and rest[:1] == ["Curve"] and len(rest) >= 2 and rest[1] in CURVE:
        settings.append(([arm, "Curve"], "Kind", CURVE[rest[1]]))
        if rest[1] == "Parametric":
            settings.append(([arm, "Curve", "Parametric"], "x(t)", "t"))
        if rest[1] == "Arc length":
            settings.append(([arm, "Curve", "Arc length"], "x(s)", "s"))
    if arm in ("Arm", "Arm NAME") and rest == ["Cross section"]:
        if name in ("Area", "Iy", "Iz", "Torsion constant", "Polar moment"):
            settings += [([arm] + p, n, v) for p, n, v in EXPLICIT_SECTION]
        elif name in ("Outer diameter", "Inner diameter"):
            settings.append(([arm, "Cross section"], "Shape", "tube"))
        elif name in ("Width", "Height"):
            settings.append(([arm, "Cross section"], "Shape", "rectangle"))
    if path[:2] == ["Solid", "Cylinder"]:
        settings.append((["Solid"], "Mesh", "cylinder"))
    return settings


# A value that moves an arm of the body scene may be refused by the check it breaks: the tie
# (the arm's root leaves the block) or the interface (the tip is no longer on the arm). The
# message then names that entry instead.
CONSEQUENCES = {"Arm boom/Curve": ("Body/Ties", "Body/Interfaces")}

# Text entries that hold no number to sweep although their documentation names a unit.
TEXT_ENTRIES = {"Plots", "Node sets", "Points file", "Mesh file", "Directory", "Export formats", "Track arms", "Arms", "Kind", "Shape",
                "Start", "End", "Method", "Mesh", "Element", "Integration", "Direct solver", "Model",
                # multibody scenes: names, lists of names, switches, file names and expressions
                "Bodies", "Joints", "Forces", "Probes", "Body", "Body 1", "Body 2", "Interface", "Interface 1",
                "Interface 2", "Frame", "Body scene", "Reduced body file", "Rigid", "Geometric stiffening",
                "Flexible bodies rigid", "Rigid reference", "Body axes", "Driver", "Modal coordinates", "Modal velocities", "Initial state",
                "Arm", "Sliding", "Arm 1", "Sliding 1", "Driver 1", "Adaptive step", "End of track", "End of track 1"}

# Failures in code owned elsewhere, reported as "known" instead of failing the test; each names
# where it is to be fixed. (scene or "*", entry path, value) -> reason.
KNOWN = {}

NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def parse_print_parameters(text):
    """[(path list, name, default, documentation)] from `print-parameters`."""
    entries, stack, doc = [], [], []
    for raw in text.splitlines():
        line = raw.strip()
        if line.startswith("#"):
            doc.append(line.lstrip("#").strip())
        elif line.startswith("subsection "):
            stack.append(line[len("subsection "):].strip())
            doc = []
        elif line == "end":
            stack.pop()
            doc = []
        elif line.startswith("set "):
            name, _, value = line[4:].partition("=")
            entries.append((list(stack), name.strip(), value.strip(), " ".join(doc)))
            doc = []
        elif not line:
            continue
    return entries


def is_number_list(value):
    items = [v.strip() for v in value.split(",")]
    return bool(value) and all(NUMBER.match(v) for v in items), len(items)


def classify(entries):
    """[(section path, name, [(label, template)], pattern checked)] of the numeric entries;
    unclassified ones."""
    numeric, unclassified = [], []
    for path, name, default, doc in entries:
        numbers, n = is_number_list(default)
        expression = re.match(r"^[xyz]\([ts]\)$", name) is not None
        if name in TEMPLATES:
            numeric.append((path, name, TEMPLATES[name], False))
        elif numbers:
            numeric.append((path, name, [("", ", ".join(["{v}"] * n))], not expression))
        elif default == "auto" and "[" in doc:
            numeric.append((path, name, [("", "{v}")], False))
        elif name not in TEXT_ENTRIES and re.search(r"\[(m|kg|Pa|s|1/s|rad|-|m\^\d|kg m\^2|kg/m\^3)\]", doc):
            unclassified.append("/".join(path + [name]))
    return numeric, unclassified


def override(path, name, value):
    """The text that sets entry @p name of @p path (deal.II keeps the last setting of an entry)."""
    lines, indent = [], ""
    for section in path:
        lines.append(f"{indent}subsection {section}")
        indent += "  "
    lines.append(f"{indent}set {name} = {value}")
    for _ in path:
        indent = indent[:-2]
        lines.append(f"{indent}end")
    return "\n".join(lines) + "\n"


def finite_json(path):
    """True if the JSON file holds only finite numbers (NaN/Infinity are flagged by Python)."""
    bad = []
    with open(path) as f:
        data = json.load(f, parse_constant=lambda c: bad.append(c))

    def walk(x):
        if isinstance(x, float) and not math.isfinite(x):
            bad.append(x)
        elif isinstance(x, dict):
            for v in x.values():
                walk(v)
        elif isinstance(x, list):
            for v in x:
                walk(v)
    walk(data)
    return not bad


def run_case(case, exe, timeout):
    scene, entry, value, prm, out, command = case
    start = time.monotonic()
    # Each run gets its own TMPDIR: Open MPI keeps a session directory there, and one process
    # removing it while another starts makes MPI_Init fail (exit 1, "A call to mkdir was unable
    # to create the desired directory: /tmp/ompi...").
    tmp = out + ".tmp"
    os.makedirs(tmp, exist_ok=True)
    proc = subprocess.Popen([exe, command, prm, "-o", out], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            start_new_session=True, cwd=os.path.dirname(prm), env=dict(os.environ, TMPDIR=tmp))
    try:
        _, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        return case, "TIME", f"no answer within {timeout} s", time.monotonic() - start
    seconds = time.monotonic() - start
    err = err.decode("utf-8", "replace")
    lines = [l for l in err.splitlines() if l.strip()]
    rc = proc.returncode
    if rc < 0:
        return case, f"SIG{-rc}", err[:200], seconds
    if rc == 0:
        summary = os.path.join(out, "summary.json")
        if not os.path.exists(summary):
            return case, "NOSUM", "exit 0 without summary.json", seconds
        if not finite_json(summary):
            return case, "NAN", "exit 0 with a non-finite number in summary.json", seconds
        return case, "ok", "", seconds
    if rc == 2:
        name = entry.split(" (")[0].split("/")[-1]
        consequences = [c for prefix, names in CONSEQUENCES.items() if entry.startswith(prefix) for c in names]
        if len(lines) != 1:
            return case, "MSG", f"{len(lines)} lines on stderr: " + " | ".join(lines)[:300], seconds
        if os.path.basename(prm) not in lines[0] or not any(n in lines[0] for n in [name] + consequences):
            return case, "MSG", "does not name the file and the entry '" + name + "': " + lines[0][:300], seconds
        if os.path.isdir(out) and os.listdir(out):
            return case, "LEFT", "files left in the output folder: " + ", ".join(sorted(os.listdir(out)))[:200], seconds
        return case, "rej", lines[0], seconds
    return case, f"EXIT{rc}", " | ".join(lines[:6])[:600], seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("exe")
    parser.add_argument("source")
    parser.add_argument("work")
    parser.add_argument("--full", action="store_true", help="every entry in every scene that reads it")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--timeout", type=float, default=5.0)
    args = parser.parse_args()
    exe = os.path.abspath(args.exe)
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    started = time.monotonic()

    listing = subprocess.run([exe, "print-parameters"], capture_output=True, text=True, check=True).stdout
    entries = parse_print_parameters(listing)
    numeric, unclassified = classify(entries)
    if unclassified:
        print("entries that name a unit but are neither numeric, templated nor known text (classify them in "
              "numeric_entries.py):\n  " + "\n  ".join(unclassified))
        return 1

    cases = []
    for path, name, templates, pattern_checked in numeric:
        top = path[0] if path else ""
        values = ["-1", "0", "1e300"] if pattern_checked and not args.full else VALUES
        for scene, (scene_file, command, sections) in SCENES.items():
            if top not in sections or (not args.full and SUBSET_SCENE.get(top) != scene):
                continue
            if name in ("Interfaces", "Output points", "Point masses", "Ties") and scene != "body":
                continue
            if name == "Supports" and top == "Solid" and path != ["Solid"]:
                continue
            scene_path = [sections[top]] + path[1:]
            text = open(os.path.join(args.source, scene_file)).read()
            setup = "".join(override([sections[p[0]]] + p[1:], n, v) for p, n, v in context(path, name))
            for label, template in templates:
                entry = "/".join(scene_path + [name]) + (f" ({label})" if label else "")
                for value in values:
                    tag = re.sub(r"[^A-Za-z0-9]+", "_", f"{scene}_{entry}_{value}").strip("_")
                    prm = os.path.join(args.work, tag + ".prm")
                    with open(prm, "w") as f:
                        f.write(text + "\n# numeric_entries.py: the entry under test, and what makes it used\n" +
                                setup + override(scene_path, name, template.format(v=value)))
                    cases.append((scene, entry, value, prm, os.path.join(args.work, "out_" + tag), command))

    scene_sections = {top for _, _, sections in SCENES.values() for top in sections}
    unswept = ["/".join(path + [name]) for path, name, _, _ in numeric if path[:1] and path[0] not in scene_sections]

    results = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for case, code, detail, seconds in pool.map(lambda c: run_case(c, exe, args.timeout * TIME_FACTOR), cases):
            results[(case[0], case[1], case[2])] = (code, detail, seconds)

    rows = sorted({(c[0], c[1]) for c in cases}, key=lambda r: (list(SCENES).index(r[0]), r[1]))
    width = max(len(f"{s}: {e}") for s, e in rows)
    print(f"{'scene: entry':<{width}}  " + "  ".join(f"{v:>6}" for v in VALUES))
    failures, known, counts = [], [], {"ok": 0, "rej": 0}
    for scene, entry in rows:
        cells = []
        for value in VALUES:
            if (scene, entry, value) not in results:
                cells.append("-")
                continue
            code, detail, seconds = results[(scene, entry, value)]
            reason = KNOWN.get((scene, entry, value)) or KNOWN.get(("*", entry, value))
            if code in counts:
                counts[code] += 1
            elif reason:
                known.append((scene, entry, value, code, detail, reason))
                code = "known"
            else:
                failures.append((scene, entry, value, code, detail))
            cells.append(code)
        print(f"{scene + ': ' + entry:<{width}}  " + "  ".join(f"{c:>6}" for c in cells))
    elapsed = time.monotonic() - started
    print(f"\n{len(rows)} scene entries, {len(cases)} runs "
          f"({'full sweep' if args.full else 'default subset: each entry in the first scene that reads it; - = not run'}): "
          f"{counts['rej']} clean rejections (rej), {counts['ok']} valid runs (ok), {len(known)} known failures "
          f"owned elsewhere, {len(failures)} failures; {elapsed:.0f} s wall time with {args.jobs} processes")
    if unswept:
        print("not swept (no sample scene reads their section; add one to SCENES): " + ", ".join(unswept))
    slowest = max(results.items(), key=lambda kv: kv[1][2])
    print(f"slowest run: {slowest[0][0]}: {slowest[0][1]} = {slowest[0][2]}: {slowest[1][2]:.1f} s")
    for scene, entry, value, code, detail, reason in known:
        print(f"known: {scene}: {entry} = {value}: {code}: {detail} [{reason}]")
    for scene, entry, value, code, detail in failures:
        print(f"FAIL: {scene}: {entry} = {value}: {code}: {detail}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
