#!/usr/bin/env bash
# Benchmark (ctest label "bench"): reduction of a flexible body - a hex20 block clamped on its
# bottom face with a curved boom tied into its top (prm/curved_boom_body.prm), Craig-Bampton with
# 20 normal modes, 6 interface constraint modes and 24 track load modes - at about 1e4, 1e5 and
# 3e5 degrees of freedom, for two block shapes:
#   link:  a slender block 0.1 x 0.1 x L m, 8 x 8 x N cells (a robot or mechanism link);
#   cube:  a compact block 0.1 m, n x n x n cells (the worst case for a direct solver; the
#          3e5 cube needs ~10 GB and ~5 min and is left out).
# Per size: median wall time and peak memory of 3 runs (/usr/bin/time, each into a fresh folder
# so the cache does not hit), the reduction's own step times, and - from one more run with
# 'Check modes = 10' - the largest relative difference of the 10 lowest reduced frequencies
# against the full FE model and the time of that full eigen solve (the baseline).
# Target (issue 4): 1e5 dofs reduced in under 20 s.
set -euo pipefail
exe=$(realpath "${1:?usage: body_reduction.sh FLEXTRACK_EXE [WORKDIR]}")
work=${2:-bench_body_reduction}
src=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
mkdir -p "$work"
cd "$work"
py=/usr/bin/python3

scene() { # name size cells check -> name.prm
  sed "s/set Size  = 0.1, 0.1, 0.1      # m/set Size = $2/; s/set Cells = 4, 4, 4/set Cells = $3/; s/set Damping ratio          = 0.01/set Damping ratio = 0.01\n  set Check modes = $4/" \
    "$src/prm/curved_boom_body.prm" > "$1.prm"
}

printf '%-6s %9s %10s %10s %10s %10s %10s %10s %12s %12s\n' shape dofs "wall[s]" "peak[MiB]" assemble clamp eigen static "max rel.err" "full eig[s]"
case_run() { # shape tag size cells
  local shape=$1 tag=$2
  for r in 1 2 3; do
    scene "${tag}_r$r" "$3" "$4" 0
    rm -rf "out_${tag}_r$r"
    /usr/bin/time -v "$exe" reduce "${tag}_r$r.prm" -o "out_${tag}_r$r" > "${tag}_r$r.log" 2> "${tag}_r$r.time" ||
      { echo "run $tag failed:"; cat "${tag}_r$r.log" "${tag}_r$r.time"; exit 1; }
  done
  scene "${tag}_check" "$3" "$4" 10
  rm -rf "out_${tag}_check"
  "$exe" reduce "${tag}_check.prm" -o "out_${tag}_check" > "${tag}_check.log"
  "$py" - "$shape" "$tag" <<'PY'
import json, re, sys
shape, tag = sys.argv[1], sys.argv[2]
runs = []
for r in (1, 2, 3):
    t = open(f"{tag}_r{r}.time").read()
    m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\d+):([\d.]+)", t)
    wall = int(m.group(1)) * 60 + float(m.group(2))
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1024
    s = json.load(open(f"out_{tag}_r{r}/summary.json"))
    # The reduction's steps, timed by the command ("reduce: ..."); the Cholesky factor is made
    # on first use, inside the eigen solve (the clamp step restricts K and M).
    steps = {k[len("reduce: "):]: v for k, v in s["wall_time_s"].items() if k.startswith("reduce: ")}
    runs.append((wall, rss, s, steps))
runs.sort(key=lambda x: x[0])
wall, rss, s, steps = runs[1]
c = json.load(open(f"out_{tag}_check/summary.json"))["check_against_full_model"]
dofs = int(re.search(r"body: (\d+) dofs", open(f"{tag}_r1.log").read()).group(1))
print("%-6s %9d %10.2f %10.0f %10.2f %10.2f %10.2f %10.2f %12.2e %12.2f" % (shape, dofs, wall, rss,
      s["wall_time_s"]["assemble body (K, M, ties)"], steps["clamp and factorise"], steps["eigen solve"],
      steps["static modes"], c["max_relative_frequency_difference"], c["full_model_eigen_solve_wall_time_s"]))
PY
}
case_run link link_1e4 "0.1, 0.1, 0.1375" "8, 8, 11"
case_run link link_1e5 "0.1, 0.1, 1.3625" "8, 8, 109"
case_run link link_3e5 "0.1, 0.1, 4.0875" "8, 8, 327"
case_run cube cube_1e4 "0.1, 0.1, 0.1" "9, 9, 9"
case_run cube cube_1e5 "0.1, 0.1, 0.1" "20, 20, 20"
