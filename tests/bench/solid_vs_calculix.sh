#!/usr/bin/env bash
# Benchmark (ctest label "bench"): hex20 cantilever blocks of about 2e4, 7e4 and 2e5 degrees of
# freedom, 10 modes, FlexTrack and CalculiX (ccx) on the identical .inp mesh in the same run.
# Prints the median wall time of 3 runs (/usr/bin/time -v) and the peak resident memory of
# each code, their ratios, and the largest relative frequency difference.
# Target (issue 3): FlexTrack at or below CalculiX's wall time and memory on every size.
# BENCH_SIZES selects other meshes (bench_common.sh), BENCH_MODES the number of modes (10),
# BENCH_REPEAT the number of runs.
set -euo pipefail
exe=$(realpath "${1:?usage: solid_vs_calculix.sh FLEXTRACK_EXE WORKDIR}")
work=${2:-bench_solid}
repeat=${BENCH_REPEAT:-3}
modes=${BENCH_MODES:-10}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source=bench_common.sh
source "$here/bench_common.sh" # timed, job_name, sizes (BENCH_SIZES)
mkdir -p "$work" && cd "$work"
py=/usr/bin/python3
command -v ccx > /dev/null || { echo "ccx (Debian package calculix-ccx) is not installed"; exit 1; }

printf '%9s %10s %10s %10s %10s %9s %9s %12s\n' dofs "ccx[s]" "ccx[MiB]" "ft[s]" "ft[MiB]" "t ratio" "m ratio" "max rel.diff"
for size in "${sizes[@]}"; do
  tag=$(job_name block "$size")
  "$py" "$here/make_block_inp.py" $size --modes "$modes" > "$tag.inp"
  cat > "$tag.prm" <<PRM
set Model = solid
subsection Solid
  set Mesh = file
  set Mesh file = $tag.inp
  set Supports = FIX: x, y, z
end
subsection Modal analysis
  set Number of modes = $modes
end
subsection Output
  set Mode shapes = false
end
PRM
  for r in $(seq "$repeat"); do
    timed "${tag}_ccx_$r" ccx "$tag"
    timed "${tag}_ft_$r" "$exe" modes "$tag.prm" -o "out_$tag"
  done
  "$py" - "$tag" "$repeat" "$here" <<'PY'
import json, sys
tag, repeat = sys.argv[1], int(sys.argv[2])
sys.path.insert(0, sys.argv[3])
from gnu_time import measure
cw, cm, _ = measure(tag, "ccx", repeat)
fw, fm, _ = measure(tag, "ft", repeat)
ccx, table = [], False
for line in open(f"{tag}.dat"):
    if "E I G E N V A L U E   O U T P U T" in line: table = True; continue
    if "P A R T I C I P A T I O N" in line: break
    p = line.split()
    if table and len(p) == 5 and p[0].isdigit(): ccx.append(float(p[3]))
s = json.load(open(f"out_{tag}/summary.json"))
diff = max(abs(a - b) / b for a, b in zip(s["frequencies_Hz"], ccx))
print(f'{s["degrees_of_freedom"]:9d} {cw:10.2f} {cm:10.1f} {fw:10.2f} {fm:10.1f} {fw / cw:9.2f} {fm / cm:9.2f} {diff:12.2e}')
PY
done
