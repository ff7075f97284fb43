#!/usr/bin/env python3
"""The order in which flextrack names its shared libraries, for a faster start-up.

Why: libdeal.ii pulls in about 200 shared libraries. At start-up the dynamic linker resolves
about 330 000 symbol references, each by searching the libraries in load order (the executable,
its DT_NEEDED entries, then theirs, breadth first) until one defines the symbol. Most references
resolve to a few large C++ libraries (deal.II, gmsh, OpenCASCADE, OpenBLAS: mostly their own
symbols, which they export and so look up globally) that sit deep in that order. Naming every
library as the executable's own DT_NEEDED entry, those that receive the most lookups first, cuts
the libraries searched per lookup about twofold; nothing else changes. (All are named: naming
only some would move the others as well, since each is loaded where the walk first meets it.)

What must not change: which library defines a symbol that several libraries define as a strong
(non-weak, non-unique) symbol, e.g. BLAS in libblas and libopenblas, IDA in libsundials_ida and
libsundials_idas, METIS in libmetis and libscotchmetis. The first library in load order wins, so
for each such symbol the library that wins in the executable's natural order (its link line
without this list) must stay ahead of every other library defining it. Weak and unique symbols
(templates, inline functions, vtables: one definition by the ODR) may bind to another copy.

  startup_link_order.py order EXE OUT      write the sonames in the order to name them, one per
                                            line (EXE is flextrack linked WITHOUT the list: configure
                                            with -DFLEXTRACK_STARTUP_LINK_ORDER=OFF)
  startup_link_order.py check EXE LIST     verify that EXE (linked WITH the list) binds every
                                            multiply defined strong symbol to the same library as
                                            its natural order; exit 1 with the symbols if not

Both run `EXE --version` under LD_DEBUG (glibc) to read the load order and the bindings.
"""
import collections
import os
import re
import subprocess
import sys
import tempfile

# Symbols every shared object defines (the linker makes them); not a conflict.
LINKER_SYMBOLS = {"_init", "_fini", "_edata", "_end", "__bss_start", "_DYNAMIC", "_GLOBAL_OFFSET_TABLE_"}


def ld_debug(exe, what):
    """Runs EXE --version with LD_DEBUG=what; returns the debug output as text."""
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, LD_DEBUG=what, LD_DEBUG_OUTPUT=os.path.join(tmp, "ld"))
        subprocess.run([exe, "--version"], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        text = ""
        for name in sorted(os.listdir(tmp)):
            with open(os.path.join(tmp, name), errors="replace") as f:
                text += f.read()
        return text


def load_order(exe):
    """The global search scope of EXE (paths, the executable first)."""
    for line in ld_debug(exe, "scopes").splitlines():
        if "scope 0:" in line:
            return line.split("scope 0:", 1)[1].split()
    sys.exit("startup_link_order.py: no 'scope 0' in LD_DEBUG=scopes output of " + exe)


def soname_paths(order):
    return {os.path.basename(p): p for p in order}


def needed(path):
    out = subprocess.run(["readelf", "-d", path], capture_output=True, text=True, check=True).stdout
    return re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", out)


def natural_order(direct, order):
    """Breadth-first load order from the executable's own DT_NEEDED entries direct (its link line
    without the list), over the libraries of order."""
    paths = soname_paths(order)
    result, seen = [], set()
    queue = collections.deque(direct)
    while queue:
        name = queue.popleft()
        if name in seen or name not in paths:
            continue
        seen.add(name)
        result.append(name)
        queue.extend(needed(paths[name]))
    # Anything the breadth-first walk did not reach (libraries only the prefix names) goes last.
    result += [os.path.basename(p) for p in order[1:] if os.path.basename(p) not in seen]
    return result


def strong_definitions(order):
    """symbol -> sonames defining it, for symbols defined by more than one library and as a strong
    symbol by at least one (the dynamic linker takes the first definition in load order, weak or
    strong, so a weak one moved ahead of a strong one would change the binding too)."""
    defs, strong = collections.defaultdict(set), set()
    for path in order[1:]:
        out = subprocess.run(["nm", "-D", "--defined-only", path], capture_output=True, text=True).stdout
        for line in out.splitlines():
            fields = line.split()
            # u: unique (one copy per process whatever the order); A: version names (GLIBC_2.2.5).
            if len(fields) < 3 or fields[1] in "uA":
                continue
            symbol = fields[2].split("@")[0]
            if symbol in LINKER_SYMBOLS:
                continue
            defs[symbol].add(os.path.basename(path))
            if fields[1] not in "VvWw":  # V, W: weak (templates, inline functions: one by the ODR)
                strong.add(symbol)
    return {s: sorted(libs) for s, libs in defs.items() if len(libs) > 1 and s in strong}


def winners(libraries, rank):
    """For each multiply defined symbol, the library that defines it first in the order rank."""
    return {s: min(libs, key=lambda lib: rank.get(lib, len(rank))) for s, libs in libraries.items()}


def command_order(exe, out_path):
    order = load_order(exe)
    names = [os.path.basename(p) for p in order]
    direct = needed(exe)
    natural = natural_order(direct, order)
    rank = {n: i for i, n in enumerate(natural)}
    counts = collections.Counter()
    for m in re.finditer(r" to (\S+) \[\d+\]: normal symbol", ld_debug(exe, "bindings")):
        counts[os.path.basename(m.group(1))] += 1
    # Precedence: each symbol's natural winner stays ahead of the other libraries defining it.
    conflicts = strong_definitions(order)
    before = collections.defaultdict(set)  # library -> libraries that must come before it
    for symbol, winner in winners(conflicts, rank).items():
        for lib in conflicts[symbol]:
            if lib != winner:
                before[lib].add(winner)
    # Order by lookups, within the precedence above. A library with many lookups can wait behind a
    # predecessor with few (libopenblas behind the libblas.so.3 that wins the BLAS symbols), so
    # each candidate is taken together with its unplaced predecessors, and the group with the most
    # lookups per library goes next (Sidney's rule for ordering under precedence constraints);
    # ties in natural order. The group enters predecessors first, most lookups first among those ready.
    pending = [n for n in natural if n in names[1:]]
    placed, result = set(), []

    def group(n):
        members, stack = {n}, [n]
        while stack:
            for p in before[stack.pop()]:
                if p not in placed and p not in members:
                    members.add(p)
                    stack.append(p)
        return members

    while pending:
        groups = {n: group(n) for n in pending}
        best = max(pending, key=lambda n: (sum(counts[m] for m in groups[n]) / len(groups[n]), -rank[n]))
        members = groups[best]
        while members:
            ready = [m for m in members if before[m] <= placed]
            nxt = max(ready, key=lambda m: (counts[m], -rank[m]))
            result.append(nxt)
            placed.add(nxt)
            members.remove(nxt)
            pending.remove(nxt)
    # Every library is named: naming only some would move the others too (each is loaded where the
    # breadth-first walk first meets it), past the constraints above.
    listed = [n for n in result if not n.startswith("ld-linux")]
    total = sum(counts.values())
    searched_before = sum(c * (names.index(n) + 1) for n, c in counts.items() if n in names)
    new_rank = {n: i + 1 for i, n in enumerate(listed)}
    rest = [n for n in names[1:] if n not in new_rank]
    for i, n in enumerate(rest):
        new_rank[n] = len(listed) + 1 + i
    new_rank[names[0]] = 0
    searched_after = sum(c * (new_rank[n] + 1) for n, c in counts.items() if n in new_rank)
    with open(out_path, "w") as f:
        f.write("# Written by src/python/tools/startup_link_order.py (see there): the shared libraries\n"
                "# flextrack names first, most symbol lookups per library first (with the libraries that\n"
                "# must precede them), each multiply defined strong\n"
                "# symbol's natural definer kept ahead. %d lookups; libraries searched: %d before,\n"
                "# about %d after.\n" % (total, searched_before, searched_after))
        f.write("# natural: " + " ".join(direct) + "\n")
        for n in listed:
            f.write(n + "\n")
    print("%d libraries listed; libraries searched per start-up %d -> about %d" %
          (len(listed), searched_before, searched_after))


def command_check(exe, list_path):
    prefix, direct = set(), None
    with open(list_path) as f:
        for line in f:
            if line.startswith("# natural:"):
                direct = line.split(":", 1)[1].split()
            elif line.strip() and not line.startswith("#"):
                prefix.add(line.strip())
    if direct is None:
        print(list_path + ": no '# natural:' line (the executable's own DT_NEEDED without the list)")
        return 1
    unknown = [n for n in needed(exe) if n not in prefix and n not in direct]
    if unknown:
        print("%s needs %s, which the list's natural order does not know: write the list again "
              "(startup_link_order.py order)" % (exe, " ".join(unknown)))
        return 1
    order = load_order(exe)
    names = [os.path.basename(p) for p in order]
    natural = natural_order(direct, order)
    conflicts = strong_definitions(order)
    now = winners(conflicts, {n: i for i, n in enumerate(names)})
    then = winners(conflicts, {n: i for i, n in enumerate(natural)})
    moved = sorted(s for s in conflicts if now[s] != then[s])
    listed_first = [n for n in names[1:len(prefix) + 1]]
    print("%d libraries loaded, %d of them listed first; %d strong symbols defined more than once" %
          (len(names) - 1, len(prefix & set(names)), len(conflicts)))
    if not prefix & set(listed_first):
        print("the listed libraries are not loaded first: the link order is not in effect")
        return 1
    if moved:
        for s in moved[:20]:
            print("symbol %s: now from %s, naturally from %s" % (s, now[s], then[s]))
        print("%d multiply defined strong symbols bind to another library than in the natural order" % len(moved))
        return 1
    print("every multiply defined strong symbol binds to the library it binds to in the natural order")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 4 or sys.argv[1] not in ("order", "check"):
        sys.exit(__doc__)
    if sys.argv[1] == "order":
        command_order(sys.argv[2], sys.argv[3])
    else:
        sys.exit(command_check(sys.argv[2], sys.argv[3]))
