#!/usr/bin/python3
"""The include rules of doc/architecture.md (issue 14), checked on the sources:
  1. layers, lowest first: base < geometry < fem < reduction < multibody < io < app;
     a file includes project headers from its own folder or folders below it only;
  2. the value headers that cross a stage boundary (reduction/reduced_body.h,
     reduction/inertia_invariants.h, reduction/mode_field.h) include no fem header, directly or
     through other project headers, so a consumer of a reduced body compiles without the FE model.
usage: layering.py SRC_DIR
"""
import os
import re
import sys

src = sys.argv[1]
layers = ["base", "geometry", "fem", "reduction", "multibody", "io", "app"]
rank = {name: i for i, name in enumerate(layers)}
include = re.compile(r'^\s*#\s*include\s*<([a-z_]+)/([^>]+)>', re.M)


def project_includes(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        return [(folder, name) for folder, name in include.findall(f.read()) if folder in rank]


problems = []
for folder in os.listdir(src):
    if folder not in rank:
        continue
    for name in sorted(os.listdir(os.path.join(src, folder))):
        if not name.endswith((".h", ".cc")):
            continue
        for target, header in project_includes(os.path.join(src, folder, name)):
            if rank[target] > rank[folder]:
                problems.append(f"{folder}/{name} includes {target}/{header}: {folder} may include only "
                                f"{', '.join(layers[:rank[folder] + 1])}")

for value_header in ["reduction/reduced_body.h", "reduction/inertia_invariants.h", "reduction/mode_field.h"]:
    seen, todo = set(), [value_header]
    while todo:
        current = todo.pop()
        if current in seen or not os.path.exists(os.path.join(src, current)):
            continue
        seen.add(current)
        for target, header in project_includes(os.path.join(src, current)):
            if target == "fem":
                problems.append(f"{value_header} includes fem/{header} (through {current}): value headers must not "
                                "include the FE model")
            todo.append(f"{target}/{header}")

if problems:
    print("\n".join(problems))
    sys.exit(1)
print("include rules hold: layers " + " < ".join(layers) + "; value headers free of fem")
