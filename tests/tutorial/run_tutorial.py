"""Runs doc/tutorial.md as written (issue 25, item 15): every file block is written and every
command of its sh blocks is run, in order, in an empty folder; each must succeed, and what the
text says of the results is checked. Usage: run_tutorial.py EXE TUTORIAL WORK [--bench-only | --no-bench]

File blocks open with ```prm file=NAME or ```gnuplot file=NAME; command blocks with ```sh, one
command a line. A command is split like a shell would split it (shlex) and run without a shell;
'flextrack' is the program under test. The benchmark (the slowest step) is its own test.
"""
import json
import os
import re
import shlex
import shutil
import subprocess
import sys


def check(condition, message):
    print(("ok:   " if condition else "FAIL: ") + message)
    if not condition:
        sys.exit(1)


def blocks(text):
    """(kind, file name or None, body) of every fenced block, in order."""
    return [(m.group(1), m.group(2), m.group(3))
            for m in re.finditer(r"^```(\w+)(?: file=(\S+))?\n(.*?)^```", text, re.S | re.M)]


def main():
    exe, tutorial, work = sys.argv[1:4]
    mode = sys.argv[4] if len(sys.argv) > 4 else ""
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    with open(tutorial) as f:
        found = blocks(f.read())
    check(sum(1 for k, n, _ in found if n) >= 3 and any(k == "sh" for k, _, _ in found),
          f"the tutorial has {len(found)} blocks, files and commands among them")
    ran = []
    for kind, name, body in found:
        if name:
            with open(os.path.join(work, name), "w") as f:
                f.write(body)
            continue
        if kind != "sh":
            continue
        for line in body.splitlines():
            if not line.strip():
                continue
            words = shlex.split(line)
            is_bench = words[:2] == ["flextrack", "bench"]
            if (mode == "--no-bench" and is_bench) or (mode == "--bench-only" and not is_bench and words[1:2] != ["reduce"]):
                continue
            command = [exe if words[0] == "flextrack" else words[0]] + words[1:]
            p = subprocess.run(command, cwd=work, capture_output=True, text=True)
            print(p.stdout[-3000:], p.stderr[-3000:])
            check(p.returncode == 0, f"{line} (exit {p.returncode})")
            ran.append(words)
    out = os.path.join(work, "output")
    if mode == "--bench-only":
        check(os.path.getsize(os.path.join(out, "bench", "bench.csv")) > 0, "bench.csv written")
        return
    # What the text says of the results.
    check(os.path.exists(os.path.join(out, "arm_body", "reduced_body.h5")), "reduce wrote output/arm_body/reduced_body.h5")
    with open(os.path.join(out, "slider_on_arm", "summary.json")) as f:
        run = json.load(f)
    check(run["status"] == "completed" and abs(run["time_reached_s"] - 2) < 1e-9, "the run completes its 2 s")
    check(os.path.getsize(os.path.join(work, "slider.png")) > 10000, "gnuplot drew slider.png")
    with open(os.path.join(out, "more_friction", "summary.json")) as f:
        friction = json.load(f)
    check(friction["set_on_command_line"] == ["Joint slide/Friction=0.5"], "the --set run records its entry")
    with open(os.path.join(out, "at_rest", "summary.json")) as f:
        rest = json.load(f)
    check(rest["unstable_modes"] == 0, "at rest, no mode is called unstable (the neutral slide is s = 0)")


if __name__ == "__main__":
    main()
