#!/usr/bin/env python3
"""The pendulum example of doc/exports.md (issue 28): a supported body on a revolute joint.

Usage: check_mbdyn_pendulum_example.py FLEXTRACK SOURCE_DIR OUTPUT_DIR [MBDYN]

1. 'flextrack export --mbdyn-clamp' on the reduced body of prm/curved_boom_body.prm: the default
   and 'yes' write the clamp of the modal node, 'no' does not; an unknown value exits with status 2
   and names the option and the allowed values.
2. The block of doc/exports.md marked

       <!-- exporter output with --mbdyn-clamp no, excerpt: reduced_body.elm of SCENE -->

   is a run of consecutive lines of that export's .elm.
3. The block marked

       <!-- MBDyn model for a joint: SCENE.prm as MULTIBODY_SCENE.prm -->

   (the complete MBDyn input of the example) is checked as text against the FlexTrack scene
   MULTIBODY_SCENE: the body frame (a 'reference:' with the scene's Position and Rotation vector,
   a rotation about z written as euler123 0, 0, angle), the interface node where the .elm says in
   that frame, the revolute pin's offset mapped to the scene's joint position and axis, gravity,
   end time, the node and joint counts of the control data (those of the model plus the .elm),
   and the initial-value settings MBDyn needs to start (derivatives coefficient: auto,
   derivatives tolerance).
4. With MBDYN (an MBDyn executable; MBDyn is not a Debian package): the model is run in the
   export folder and the tip of the boom is compared with 'flextrack run MULTIBODY_SCENE':
   the largest distance over the run is printed and must be at most the tolerance the document
   states in the line 'agreement tolerance: X m'.

Exit status 0 when everything holds, 1 otherwise.
"""
import math
import pathlib
import re
import subprocess
import sys

ELM_MARKER = re.compile(r"<!-- exporter output with --mbdyn-clamp no, excerpt: (\S+) of (\S+) -->")
MODEL_MARKER = re.compile(r"<!-- MBDyn model for a joint: (\S+) as (\S+) -->")


def marked_blocks(doc, marker):
    """(match, text) of every fenced block that follows a line matching @p marker."""
    lines = doc.splitlines(keepends=True)
    found = []
    for i, line in enumerate(lines):
        m = marker.fullmatch(line.strip())
        if not m:
            continue
        if i + 1 >= len(lines) or not lines[i + 1].startswith("```"):
            sys.exit(f"doc/exports.md line {i + 1}: a marker must be followed by a fenced block")
        end = i + 2
        while end < len(lines) and not lines[end].startswith("```"):
            end += 1
        found.append((m, "".join(lines[i + 2:end])))
    return found


def run(command, cwd):
    return subprocess.run(command, cwd=cwd, capture_output=True, text=True)


def prm_entries(path):
    """'Section/Sub/Entry' -> value of a deal.II parameter file (comments removed)."""
    entries, stack = {}, []
    for raw in pathlib.Path(path).read_text().splitlines():
        line = raw.split("#", 1)[0].strip()
        if line.startswith("subsection "):
            stack.append(line[len("subsection "):].strip())
        elif line == "end":
            stack.pop()
        elif line.startswith("set "):
            key, value = line[4:].split("=", 1)
            entries["/".join(stack + [key.strip()])] = value.strip()
    return entries


def numbers(text):
    return [float(v) for v in text.split(",")]


def statements(text):
    """The MBDyn statements of @p text: '#' comments removed, split at ';', blanks collapsed."""
    clean = re.sub(r"#[^\n]*", "", text)
    return [" ".join(s.split()) for s in clean.split(";") if s.strip()]


def fields(statement):
    """'description: a, b, c' -> (description, [a, b, c])."""
    description, rest = statement.split(":", 1)
    return description.strip(), [f.strip() for f in rest.split(",")]


def close(a, b, tol=1e-12):
    return len(a) == len(b) and all(abs(x - y) <= tol * max(1.0, abs(y)) for x, y in zip(a, b))


def rotate_z(angle, p):
    c, s = math.cos(angle), math.sin(angle)
    return [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]]


def check_model(block, elm, scene):
    """Problems of the MBDyn model @p block against the .elm it includes and the FlexTrack scene."""
    problems = []
    st = statements(block)
    body = scene["Multibody/Bodies"].split(",")[0].strip()
    joint = scene["Multibody/Joints"].split(",")[0].strip()
    position = numbers(scene[f"Body {body}/Position"])
    rotation = numbers(scene[f"Body {body}/Rotation vector"])
    if rotation[0] != 0 or rotation[1] != 0:
        return ["the check handles a body turned about z only"]
    angle = rotation[2]
    # The body frame: 'reference: LABEL, x, y, z, euler123, 0., 0., angle, null, null'.
    references = [fields(s)[1] for s in st if s.startswith("reference:")]
    frame = None
    for r in references:
        if len(r) >= 10 and r[4] == "euler123" and close(numbers(",".join(r[1:4])), position) and \
                close(numbers(",".join(r[5:8])), [0.0, 0.0, angle]):
            frame = r[0]
    if frame is None:
        problems.append(f"no 'reference:' with the scene's Position {position} and euler123 0, 0, {angle}")
    # Nodes: the modal node at the frame's origin, each interface node where the .elm says.
    nodes = {}
    for s in st:
        if s.startswith("structural:"):
            f = fields(s)[1]
            nodes[f[0]] = f
    modal = nodes.get("flextrack_modal_node")
    if not modal or modal[1] != "modal" or modal[2:5] != ["reference", frame, "null"]:
        problems.append("the modal node must be 'modal' at the origin of the body frame (reference, FRAME, null)")
    for name, x, y, z in re.findall(r"set: ifndef integer (flextrack_node_\w+) = -?\d+;\s*# at \(([^,]+), ([^,]+), ([^)]+)\) m", elm):
        node = nodes.get(name)
        if not node or node[2:4] != ["reference", frame] or not close(numbers(",".join(node[4:7])), [float(x), float(y), float(z)]):
            problems.append(f"interface node {name} must stand at ({x}, {y}, {z}) m in the body frame")
        elif node[7:10] != ["reference", frame, "eye"]:
            problems.append(f"interface node {name} must be oriented as the modal node (reference, FRAME, eye)")
    # The pivot: a revolute pin on the modal node whose offset is the scene's joint position.
    pins = [fields(s)[1] for s in st if s.startswith("joint:") and fields(s)[1][1] == "revolute pin"]
    if len(pins) != 1:
        problems.append("the model must hold the body by one 'revolute pin'")
    else:
        pin = pins[0]
        # flextrack_modal_node, position, OFFSET (node frame = body frame), orientation, eye,
        # position, null, orientation, eye: axis 3 of both is the body's z, turned about z.
        where = numbers(scene[f"Joint {joint}/Position"])
        axis = numbers(scene[f"Joint {joint}/Axis"])
        if len(pin) != 13 or pin[2:4] != ["flextrack_modal_node", "position"] or pin[7:] != ["orientation", "eye", "position", "null", "orientation", "eye"]:
            problems.append("the pin must read 'flextrack_modal_node, position, OFFSET, orientation, eye, position, null, orientation, eye'")
        elif not close([a + b for a, b in zip(position, rotate_z(angle, numbers(",".join(pin[4:7]))))], where, 1e-12):
            problems.append(f"the revolute pin's offset must be, in the body frame, the scene's joint position {where}")
        if where != [0.0, 0.0, 0.0] or axis != [0.0, 0.0, 1.0]:
            problems.append("the check expects the scene's joint at the origin with axis 0, 0, 1")
    # Gravity, end time.
    g = [fields(s)[1] for s in st if s.startswith("gravity:")]
    gravity = numbers(scene["Multibody/Gravity"])
    if len(g) != 1 or g[0][0] != "uniform" or g[0][4] != "const" or \
            not close([float(v) * float(g[0][5]) for v in g[0][1:4]], gravity):
        problems.append(f"gravity must be 'uniform, ..., const, ...' equal to the scene's {gravity} m/s^2")
    final = [fields(s)[1][0] for s in st if s.startswith("final time:")]
    if final != [] and float(final[0]) != float(scene["Multibody/End time"]):
        problems.append("the final time must be the scene's End time")
    # Counts of the control data: the model's own and those of the .elm.
    joints_elm = len(re.findall(r"^joint:", re.sub(r"#[^\n]*", "", elm), re.M))
    joints = joints_elm + sum(1 for s in st if s.startswith("joint:"))
    for what, count in (("structural nodes", len(nodes)), ("joints", joints)):
        m = [fields(s)[1][0] for s in st if s.startswith(what + ":")]
        if m != [str(count)]:
            problems.append(f"the control data must count {count} {what} (the model's and those of the .elm)")
    if 'include: "reduced_body.elm"' not in [s for s in st]:
        problems.append("the model does not include reduced_body.elm")
    for setting in ("derivatives coefficient: auto", "derivatives tolerance: 1.e-6"):
        if setting not in st:
            problems.append(f"the initial-value block needs '{setting}' (MBDyn does not start otherwise)")
    return problems


def tip_distance(mov, label, dt_out, probes, probe):
    """Largest distance [m] between the node @p label of MBDyn's .mov (one row per output, every
    @p dt_out s from 0) and FlexTrack's probe @p probe, at FlexTrack's output times."""
    rows = [line.split() for line in mov.read_text().splitlines()]
    mbdyn = [[float(v) for v in r[1:4]] for r in rows if r and r[0] == str(label)]
    header, *data = [line.split(",") for line in probes.read_text().splitlines()]
    columns = [header.index(f"{probe}_{c}_m") for c in "xyz"]
    largest, at = 0.0, 0.0
    for row in data:
        t = float(row[0])
        k = round(t / dt_out)
        if abs(k * dt_out - t) > 1e-9 or k >= len(mbdyn):
            continue
        d = math.dist(mbdyn[k], [float(row[c]) for c in columns])
        if d >= largest:
            largest, at = d, t
    return largest, at, len(mbdyn)


def main():
    exe = str(pathlib.Path(sys.argv[1]).resolve())
    source, out = pathlib.Path(sys.argv[2]).resolve(), pathlib.Path(sys.argv[3]).resolve()
    mbdyn = sys.argv[4] if len(sys.argv) > 4 and sys.argv[4] else None
    doc = (source / "doc" / "exports.md").read_text()
    elm_blocks, models = marked_blocks(doc, ELM_MARKER), marked_blocks(doc, MODEL_MARKER)
    failures = []
    if len(elm_blocks) != 1 or len(models) != 1:
        return print("doc/exports.md must hold one .elm excerpt and one model block of the pendulum example") or 1
    body_scene, multibody_scene = models[0][0].group(1), models[0][0].group(2)
    body = out / "body"
    r = run([exe, "reduce", body_scene, "-o", str(body)], source)
    if r.returncode != 0:
        return print(f"reduce {body_scene} failed: {r.stderr}") or 1
    h5 = str(body / "reduced_body.h5")
    # 1. The option: both cases, the default, and a wrong value.
    elm = {}
    for value in ("", "auto", "yes", "no"):
        folder = out / ("export_" + (value or "default"))
        r = run([exe, "export", "--format", "mbdyn", h5, "-o", str(folder)] + (["--mbdyn-clamp", value] if value else []), source)
        if r.returncode != 0:
            return print(f"export --mbdyn-clamp {value} failed: {r.stderr}") or 1
        elm[value] = (folder / "reduced_body.elm").read_text()
    clamp = re.compile(r"^joint: flextrack_clamp_joint, clamp, flextrack_modal_node, node, node;$", re.M)
    if elm[""] != elm["auto"] or elm["yes"] != elm["auto"] or not clamp.search(elm[""]):
        failures.append("the default export of a supported body must clamp the modal node, as 'auto' and 'yes'")
    if clamp.search(elm["no"]) or "count 1 joint" not in elm["no"]:
        failures.append("'--mbdyn-clamp no' must write no clamp and count 1 joint")
    r = run([exe, "export", "--format", "mbdyn", h5, "-o", str(out / "export_bad"), "--mbdyn-clamp", "maybe"], source)
    if r.returncode != 2 or not re.search(r"--mbdyn-clamp.*'maybe'.*allowed: auto, yes, no", r.stderr) or (out / "export_bad").exists():
        failures.append(f"'--mbdyn-clamp maybe' must exit with 2 naming the option and the allowed values, "
                        f"and write nothing (got {r.returncode}: {r.stderr.strip()})")
    print("export --mbdyn-clamp: default/auto/yes clamp, no does not; 'maybe' refused with exit status", r.returncode)
    # 2. The .elm excerpt.
    m, block = elm_blocks[0]
    b, t = block.splitlines(), elm["no"].splitlines()
    if not b or not any(t[i:i + len(b)] == b for i in range(len(t) - len(b) + 1)):
        failures.append("the .elm excerpt of the pendulum example is not in the exporter's file")
    # 3. The model as text.
    scene = prm_entries(source / multibody_scene)
    problems = check_model(models[0][1], elm["no"], scene)
    failures += problems
    print(f"MBDyn model for {body_scene} as {multibody_scene}: {'matches the scene' if not problems else 'MISMATCH'}")
    # 4. A real MBDyn, if there is one.
    if not mbdyn:
        print("no MBDyn given: the model was checked as text only")
    else:
        folder = out / "export_no"
        (folder / "pendulum.mbd").write_text(models[0][1])
        r = run([mbdyn, "-f", "pendulum.mbd", "-o", "pendulum"], folder)
        warnings = [line for line in (r.stdout + r.stderr).splitlines() if "ifndef variable" in line or "skipping redefinition" in line]
        print(f"MBDyn exit status {r.returncode}; {len(warnings)} 'set: ifndef' warning lines")
        if r.returncode != 0:
            failures.append("MBDyn failed: " + (r.stdout + r.stderr)[-2000:])
        else:
            run_folder = out / "flextrack_run"
            # From the output folder: the body the scene reduces is cached there, not in the sources.
            rr = run([exe, "run", str(source / multibody_scene), "-o", str(run_folder)], out)
            if rr.returncode != 0:
                return print(f"flextrack run {multibody_scene} failed: {rr.stderr}") or 1
            st = statements(models[0][1])
            dt = float([fields(s)[1][0] for s in st if s.startswith("time step:")][0])
            every = int([fields(s)[1][0] for s in st if s.startswith("output frequency:")][0])
            label = int(re.search(r"set: integer flextrack_node_tip = (\d+);", models[0][1]).group(1))
            d, at, n = tip_distance(folder / "pendulum.mov", label, dt * every, run_folder / "probes.csv", "tip")
            tol = re.search(r"agreement tolerance: ([0-9.e+-]+) m", doc)
            print(f"tip of MBDyn against flextrack run: largest distance {d:.2e} m (at t = {at:g} s; {n} MBDyn outputs)")
            if not tol or not d <= float(tol.group(1)):
                failures.append(f"the tips differ by {d:.2e} m, more than the document's agreement tolerance")
    for f in failures:
        print("  " + f)
    print(f"{len(failures)} problems")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
