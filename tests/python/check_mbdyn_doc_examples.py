#!/usr/bin/env python3
"""The worked examples of doc/exports.md are what the exporter writes (issue 13).

Usage: check_mbdyn_doc_examples.py FLEXTRACK SOURCE_DIR OUTPUT_DIR

Every fenced block of doc/exports.md preceded by a marker line

    <!-- exporter output: FILE of SCENE -->            the block is the whole file
    <!-- exporter output, excerpt: FILE of SCENE -->   the block is a run of consecutive lines of it
    <!-- MBDyn model for: SCENE -->                     an MBDyn model that includes SCENE's .elm

is compared with the file FILE that 'flextrack reduce SCENE' then 'flextrack export --format
mbdyn' write (run from SOURCE_DIR, so that the scene path recorded in the file is the one the
documentation shows). For an MBDyn model block, each interface node of the .elm must be defined
there at the position the .elm states, with the label the .elm sets, the modal node at the origin,
and the joint count in the control data must be the number of joints the .elm defines.
Exit status 0 when every block matches, 1 otherwise (with a diff).
"""
import difflib
import pathlib
import re
import subprocess
import sys

MARKER = re.compile(r"<!-- (exporter output(, excerpt)?: (\S+) of (\S+)|MBDyn model for: (\S+)) -->")


def blocks(doc):
    """(marker match, block text) for each marked fenced block."""
    lines = doc.splitlines(keepends=True)
    found = []
    i = 0
    while i < len(lines):
        m = MARKER.fullmatch(lines[i].strip())
        i += 1
        if not m:
            continue
        if i >= len(lines) or not lines[i].startswith("```"):
            sys.exit(f"doc/exports.md line {i}: a marker must be followed by a fenced block")
        start = i + 1
        end = start
        while end < len(lines) and not lines[end].startswith("```"):
            end += 1
        found.append((m, "".join(lines[start:end])))
        i = end + 1
    return found


def export(exe, source, out, scene):
    folder = out / re.sub(r"[^A-Za-z0-9_]", "_", scene)
    for command in ([exe, "reduce", scene, "-o", str(folder)],
                    [exe, "export", "--format", "mbdyn", str(folder / "reduced_body.h5"), "-o", str(folder / "mbdyn")]):
        r = subprocess.run(command, cwd=source, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"{' '.join(command)} failed ({r.returncode}): {r.stderr}")
    return folder / "mbdyn"


def check_model(block, elm):
    """The MBDyn model block against the .elm it includes."""
    problems = []
    labels = {name: int(value) for name, value in re.findall(r"set: (?:ifndef )?integer (\w+) = (-?\d+);", elm)}
    statements = [s.strip() for s in re.sub(r"#[^\n]*", "", block).split(";")]
    nodes = {}
    for s in statements:
        m = re.match(r"structural:\s*(\w+)\s*,\s*(\w+)\s*,(.*)", s, re.S)
        if m:
            fields = [f.strip() for f in m.group(3).split(",")]
            nodes[m.group(1)] = (m.group(2), fields)
    modal = nodes.get("flextrack_modal_node")
    if not modal or modal[0] != "modal" or modal[1][0] != "null":
        problems.append("the modal node 'flextrack_modal_node' must be a modal node at the origin (null)")
    for name, x, y, z in re.findall(r"set: (?:ifndef )?integer (flextrack_node_\w+) = -?\d+;\s*# at \(([^,]+), ([^,]+), ([^)]+)\) m", elm):
        node = nodes.get(name)
        if not node:
            problems.append(f"no structural node '{name}' in the model")
            continue
        position = [float(v) for v in node[1][:3]]
        if position != [float(x), float(y), float(z)]:
            problems.append(f"node {name} at {position}, the .elm says ({x}, {y}, {z})")
    joints = len(re.findall(r"^joint:", re.sub(r"#[^\n]*", "", elm), re.M))
    m = re.search(r"joints:\s*\+?\s*(\d+)\s*;", re.sub(r"#[^\n]*", "", block))
    if not m or int(m.group(1)) != joints:
        problems.append(f"the control data must count the {joints} joint(s) the .elm defines")
    if 'include: "reduced_body.elm";' not in block:
        problems.append("the model does not include reduced_body.elm")
    for name in ("flextrack_modal_node",):
        if name not in labels:
            problems.append(f"the .elm does not set {name}")
    return problems


def main():
    exe = str(pathlib.Path(sys.argv[1]).resolve())  # the scenes are run from the source folder
    source, out = pathlib.Path(sys.argv[2]).resolve(), pathlib.Path(sys.argv[3]).resolve()
    doc = (source / "doc" / "exports.md").read_text()
    found = blocks(doc)
    exported = {}
    failures = 0
    whole = 0
    for m, block in found:
        scene = m.group(4) or m.group(5)
        if scene not in exported:
            exported[scene] = export(exe, source, out, scene)
        if m.group(5):
            text = (exported[scene] / "reduced_body.elm").read_text()
            problems = check_model(block, text)
            what = f"MBDyn model for {scene}"
        else:
            text = (exported[scene] / m.group(3)).read_text()
            what = f"{m.group(3)} of {scene}" + (" (excerpt)" if m.group(2) else "")
            if m.group(2):
                b, t = block.splitlines(), text.splitlines()
                ok = len(b) > 0 and any(t[i:i + len(b)] == b for i in range(len(t) - len(b) + 1))
            else:
                whole += 1
                ok = block == text
            problems = [] if ok else ["differs from the exporter's file:\n" + "".join(difflib.unified_diff(
                block.splitlines(keepends=True), text.splitlines(keepends=True), "doc/exports.md", "exported"))]
        print(f"{what}: {'matches' if not problems else 'MISMATCH'}")
        for p in problems:
            print("  " + p)
        failures += bool(problems)
    if whole == 0:
        print("doc/exports.md has no block marked as a whole exported file")
        failures += 1
    print(f"{len(found)} marked blocks, {failures} failing")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
