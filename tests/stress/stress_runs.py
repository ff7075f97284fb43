"""What tests/stress/long_runs.py and perturbations.py share: a wrapper scene that includes a scene
and overrides some of its entries, one `flextrack run` of it with a time limit, and the CSV files
and summary.json it writes.

A wrapper is written into the test's binary folder (never next to the scene). It includes the
scene by its absolute path, then sets the overridden entries again (deal.II's parameter files:
the last `set` wins). A flexible body's `Body scene` is resolved against the folder of the scene
that is run (the wrapper's), not of the file that names it, so every body scene is given again as
an absolute path (as tests/bench_scenes/run_scene.py does)."""
import csv
import json
import math
import os
import shutil
import signal
import subprocess
import time

# FLEXTRACK_TIME_LIMIT_FACTOR (8 in the Debug + sanitizer build, tests/CMakeLists.txt): programs
# run that many times slower there, so the scripts do that much less work.
TIME_FACTOR = max(1.0, float(os.environ.get("FLEXTRACK_TIME_LIMIT_FACTOR", "1")))


def expanded_lines(path):
    """The scene's lines with every 'include FILE' replaced by that file's lines (the rule of
    src/io/scene_file.cc: FILE relative to the including file's folder)."""
    lines = []
    with open(path) as f:
        for line in f:
            s = line.strip()
            if s.startswith("include ") or s.startswith("include\t"):
                lines += expanded_lines(os.path.join(os.path.dirname(path), s[8:].strip()))
            else:
                lines.append(line)
    return lines


def body_scenes(scene):
    """{body: absolute path of its body scene} for the flexible bodies of @p scene."""
    body, found = None, {}
    for line in expanded_lines(scene):
        s = line.split("#")[0].strip()
        if s.startswith("subsection Body "):
            body = s[len("subsection Body "):].strip()
        elif s == "end":
            body = None
        elif body and s.startswith("set Body scene") and "=" in s:
            value = s.split("=", 1)[1].strip()
            if value:
                found[body] = os.path.normpath(os.path.join(os.path.dirname(scene), value))
    return found


def write_wrapper(path, scene, overrides, comment):
    """Writes the scene file @p path: 'include SCENE', then @p overrides, a dict
    {"Multibody/Integrator": {"Method": "ida"}, "Body bob": {"Mass": "2"}, ...}, then the body
    scenes as absolute paths."""
    scene = os.path.abspath(scene)
    text = [f"# Written by tests/stress: {comment}", f"include {scene}"]
    sections = dict(overrides)
    for body, body_scene in body_scenes(scene).items():
        sections.setdefault(f"Body {body}", {}).setdefault("Body scene", body_scene)
    for section, entries in sections.items():
        names = section.split("/")
        text += [f"{'  ' * i}subsection {n}" for i, n in enumerate(names)]
        text += [f"{'  ' * len(names)}set {k} = {v}" for k, v in entries.items()]
        text += [f"{'  ' * i}end" for i in reversed(range(len(names)))]
    with open(path, "w") as f:
        f.write("\n".join(text) + "\n")


class Run:
    """One `flextrack run` of a scene file: exit status (negative: killed by that signal; None:
    killed at the time limit), wall time, the last lines of the log, and what it wrote."""

    def __init__(self, exe, prm, out, timeout, cwd=None):
        shutil.rmtree(out, ignore_errors=True)
        start = time.monotonic()
        try:
            proc = subprocess.run([exe, "run", prm, "-o", out], capture_output=True, text=True,
                                  timeout=timeout, cwd=cwd)
            self.returncode, self.stdout, self.stderr = proc.returncode, proc.stdout, proc.stderr
        except subprocess.TimeoutExpired as e:
            self.returncode, self.stdout, self.stderr = None, str(e.stdout or ""), str(e.stderr or "")
        self.wall = time.monotonic() - start
        self.out = out
        self.summary = None
        if os.path.exists(os.path.join(out, "summary.json")):
            with open(os.path.join(out, "summary.json")) as f:
                self.summary = json.load(f)

    def outcome(self):
        """'completed', 'solver failure' (exit 3), 'bad input' (exit 2), 'hang', 'signal NAME',
        or 'exit N'."""
        if self.returncode is None:
            return "hang"
        if self.returncode < 0:
            return "signal " + signal.Signals(-self.returncode).name
        return {0: "completed", 2: "bad input", 3: "solver failure"}.get(self.returncode, f"exit {self.returncode}")

    def table(self, name):
        """{column: [values]} of OUT/name (probes.csv or monitors.csv), values as floats."""
        return read_csv(os.path.join(self.out, name))


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    header, columns = rows[0], {h: [] for h in rows[0]}
    for row in rows[1:]:
        for h, v in zip(header, row):
            columns[h].append(float(v))
    return columns


def non_finite(columns):
    """The first (column, row) whose value is NaN or infinite, or None."""
    for h, values in columns.items():
        for i, v in enumerate(values):
            if not math.isfinite(v):
                return h, i
    return None
