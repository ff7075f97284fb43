"""Benchmark (ctest label bench): 'flextrack reduce' of large bodies on 1 process and on 2 (issue 27).

The body is prm/curved_boom_body.prm with its block made a slender link 0.1 x 0.1 x L m of
8 x 8 x N hex20 cells (the link of bench/body_reduction.sh, longer): N = 261 gives 2.4e5 dofs,
N = 1089 gives 1.0e6. Per size:
  - serial: `flextrack reduce` (CHOLMOD, 2 BLAS threads);
  - distributed: `mpirun -np 2 flextrack reduce` (MUMPS and PARPACK, 1 BLAS thread each);
  - wall time (/usr/bin/time), peak memory per process (summary.json) and in all, the factor's
    estimated size, and the reduction's stages;
  - the two files compared as in tests/mpi/reduce_matches_serial.py (frequencies 1e-9 relative,
    reduced matrices and inertia invariants 1e-8, modes up to sign or rotation), and the probes
    of a 0.2 s run of prm/flexible_pendulum.prm with either file (1e-9 m).
A size whose factorisation does not fit is refused by the program before it factorises (exit 3):
the bench then prints that message (the estimate and how many machines it needs) and the peak
memory of the refused run, what the estimate rests on.

Usage: distributed_reduction.py EXE MPIRUN SOURCE_DIR WORK [SIZE ...]   (SIZE: 2.4e5, 1e6)
"""
import importlib.util
import json
import os
import re
import shutil
import subprocess
import sys

CELLS = {"2.4e5": 261, "1e6": 1089}


def load_checks(source):
    spec = importlib.util.spec_from_file_location("checks", os.path.join(source, "tests/mpi/reduce_matches_serial.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def timed(args, cwd, env):
    p = subprocess.run(["/usr/bin/time", "-v"] + args, cwd=cwd, env=env, capture_output=True, text=True)
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([\d.]+)", p.stderr)
    seconds = (int(wall.group(1) or 0) * 3600 + int(wall.group(2)) * 60 + float(wall.group(3))) if wall else float("nan")
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr)
    return p, seconds, (int(rss.group(1)) / 1024 if rss else float("nan"))


def main():
    exe, mpirun, source, work = sys.argv[1:5]
    exe, source, work = os.path.abspath(exe), os.path.abspath(source), os.path.abspath(work)
    sizes = sys.argv[5:] or ["2.4e5", "1e6"]
    checks = load_checks(source)
    base = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    rows = []
    for size in sizes:
        n = CELLS[size]
        stem = "link_" + size.replace(".", "p")
        folder = os.path.join(work, stem)
        shutil.rmtree(folder, ignore_errors=True)
        folders = {"serial": os.path.join(folder, "serial"), "mpi": os.path.join(folder, "mpi")}
        for f in folders.values():
            os.makedirs(f)
            text = open(os.path.join(source, "prm/curved_boom_body.prm")).read()
            text = text.replace("set Size  = 0.1, 0.1, 0.1      # m", f"set Size = 0.1, 0.1, {0.0125 * n:.4f}")
            text = text.replace("set Cells = 4, 4, 4", f"set Cells = 8, 8, {n}")
            open(os.path.join(f, stem + ".prm"), "w").write(text)
            scene = open(os.path.join(source, "prm/flexible_pendulum.prm")).read()
            open(os.path.join(f, "scene.prm"), "w").write(scene.replace("curved_boom_body.prm", stem + ".prm"))
        results = {}
        for name, launcher, threads in [("serial", [], "2"), ("mpi", [mpirun, "-np", "2"], "1")]:
            env = dict(base, OPENBLAS_NUM_THREADS=threads)
            p, wall, rss = timed(launcher + [exe, "reduce", stem + ".prm"], folders[name], env)
            print(p.stdout[-3000:], p.stderr[-3000:], flush=True)
            summary_path = os.path.join(folders[name], "output", stem, "summary.json")
            if p.returncode != 0:
                refusal = re.search(r"solver failure: (.*needs about.*)", p.stdout + p.stderr)
                checks.check(refusal is not None and p.returncode == 3, f"{size} {name}: completes or is refused")
                results[name] = dict(status=p.returncode, wall=wall, rss=rss,
                                     message=refusal.group(1) if refusal else "(no message)")
                continue
            summary = json.load(open(summary_path))
            log = p.stdout
            dofs = int(re.search(r"body: (\d+) dofs", log).group(1))
            factor = re.search(r"factorisation: about ([0-9.e+-]+) GiB per process", log)
            peaks = summary.get("peak_memory_per_process_MiB") or [summary["peak_memory_MiB"]]
            stages = {k[len("reduce: "):]: v for k, v in summary["wall_time_s"].items() if k.startswith("reduce: ")}
            results[name] = dict(status=0, wall=wall, dofs=dofs, peaks=peaks, factor=float(factor.group(1)) if factor else 0,
                                 assemble=summary["wall_time_s"]["assemble body (K, M, ties)"], stages=stages)
        for name, r in results.items():
            if r["status"] != 0:
                # /usr/bin/time measures mpirun itself under MPI: what the processes held is in the message.
                held = re.search(r"where the processes hold ([0-9.e+-]+) GiB already", r["message"])
                print(f"{size} {name}: refused (exit {r['status']}) after {r['wall']:.1f} s, the processes of the machine "
                      f"holding {held.group(1) if held else '?'} GiB: {r['message']}")
                continue
            print(f"{size} {name}: {r['dofs']} dofs, wall {r['wall']:.1f} s, peak per process "
                  f"{', '.join(f'{x:.0f}' for x in r['peaks'])} MiB ({sum(r['peaks']):.0f} in all), factor about "
                  f"{r['factor']:.2f} GiB per process, assemble {r['assemble']:.1f} s, "
                  + ", ".join(f"{k} {v:.1f} s" for k, v in r["stages"].items()), flush=True)
        if all(r["status"] == 0 for r in results.values()):
            env = dict(base, OPENBLAS_NUM_THREADS="1")
            checks.compare_bodies(*(os.path.join(folders[x], "output", stem, "reduced_body.h5") for x in ("serial", "mpi")))
            checks.compare_runs(exe, "scene.prm", folders, env)
        rows.append((size, results))
    print("\n| body | processes | dofs | wall [s] | peak per process [MiB] | peak in all [MiB] | factor per process, estimated [GiB] |")
    print("|---|---|---|---|---|---|---|")
    for size, results in rows:
        for name, r in results.items():
            if r["status"] == 0:
                print(f"| {size} | {1 if name == 'serial' else 2} | {r['dofs']} | {r['wall']:.1f} | "
                      f"{max(r['peaks']):.0f} | {sum(r['peaks']):.0f} | {r['factor']:.2f} |")
            else:
                held = re.search(r"where the processes hold ([0-9.e+-]+) GiB already", r["message"])
                need = re.search(r"needs about ([0-9.e+-]+) GiB per process", r["message"])
                print(f"| {size} | {1 if name == 'serial' else 2} | - | refused after {r['wall']:.1f} | - | "
                      f"{float(held.group(1)) * 1024:.0f} held when refused | {need.group(1) if need else '?'} |")


if __name__ == "__main__":
    main()
