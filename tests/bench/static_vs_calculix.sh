#!/usr/bin/env bash
# Benchmark (ctest label "bench"): linear statics of hex20 cantilever blocks of about 2e4, 7e4
# and 2e5 degrees of freedom, FlexTrack (`flextrack static`) and CalculiX (ccx, *STATIC) on the
# identical .inp mesh and nodal loads in the same run: clamped at x = 0 (node set FIX), a total
# force on the tip face x = L (node set TIP) as a uniform traction, i.e. the consistent hex20
# nodal loads (FlexTrack: `Node set forces`; CalculiX: the same loads written as *CLOAD by
# make_block_inp.py --static). Prints the median wall time of BENCH_REPEAT (default 3) runs
# (/usr/bin/time -v) and the peak resident memory of each code, their ratios, and the relative
# difference |u_ft - u_ccx| / |u_ccx| of the tip face's mean displacement (mean over its nodes).
# Target (issue 12): FlexTrack at or below CalculiX's wall time and memory (ratios <= 1.0).
# Fails only if the tip displacements differ by more than 1e-6 (a wrong load or mesh).
# BENCH_SIZES selects other meshes, e.g. BENCH_SIZES="50 5 5" (bench_common.sh).
set -euo pipefail
exe=$(realpath "${1:?usage: static_vs_calculix.sh FLEXTRACK_EXE WORKDIR}")
work=${2:-bench_static}
repeat=${BENCH_REPEAT:-3}
force="100 1000 -500" # total tip force Fx Fy Fz [N]
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source=bench_common.sh
source "$here/bench_common.sh" # timed, job_name, sizes (BENCH_SIZES)
mkdir -p "$work" && cd "$work"
py=/usr/bin/python3
command -v ccx > /dev/null || { echo "ccx (Debian package calculix-ccx) is not installed"; exit 1; }

echo "tip force $force N on the face x = L of a 1 x 0.1 x 0.1 m steel block; median of $repeat runs"
printf '%9s %10s %10s %10s %10s %9s %9s %12s\n' dofs "ccx[s]" "ccx[MiB]" "ft[s]" "ft[MiB]" "t ratio" "m ratio" "tip rel.diff"
for size in "${sizes[@]}"; do
  tag=$(job_name static "$size")
  # shellcheck disable=SC2086
  "$py" "$here/make_block_inp.py" $size --static $force > "$tag.inp"
  cat > "$tag.prm" <<PRM
set Model = solid
subsection Solid
  set Mesh = file
  set Mesh file = $tag.inp
  set Supports = FIX: x, y, z
end
subsection Static
  set Load cases = tip
  set Node sets = TIP
end
subsection Load case tip
  set Node set forces = TIP: $force
end
PRM
  for r in $(seq "$repeat"); do
    timed "${tag}_ccx_$r" ccx "$tag"
    cp "$tag.dat" "${tag}_ccx_$r.dat"
    timed "${tag}_ft_$r" "$exe" static "$tag.prm" -o "out_${tag}_$r"
  done
  "$py" - "$tag" "$repeat" "$here" <<'PY'
import csv, json, math, sys
tag, repeat = sys.argv[1], int(sys.argv[2])
sys.path.insert(0, sys.argv[3])
from gnu_time import measure
cw, cm, _ = measure(tag, "ccx", repeat)
fw, fm, fr = measure(tag, "ft", repeat)
# CalculiX: the mean of the TIP nodes' displacements from *NODE PRINT (the .dat file).
rows, table = [], False
for line in open(f"{tag}_ccx_1.dat"):
    if "displacements (vx,vy,vz) for set TIP" in line: table = True; continue
    p = line.split()
    if table and len(p) == 4 and p[0].isdigit(): rows.append([float(v) for v in p[1:]])
    elif table and rows and not p: break
ccx = [sum(r[d] for r in rows) / len(rows) for d in range(3)]
# FlexTrack: static.csv's mean displacement of TIP.
row = next(r for r in csv.DictReader(open(f"out_{tag}_1/static.csv")) if r["node_set"].upper() == "TIP")
ft = [float(row[f"mean_u{c}_m"]) for c in "xyz"]
diff = math.dist(ft, ccx) / math.hypot(*ccx)
s = json.load(open(f"out_{tag}_{fr}/summary.json"))
print(f'{s["degrees_of_freedom"]:9d} {cw:10.2f} {cm:10.1f} {fw:10.2f} {fm:10.1f} {fw / cw:9.2f} {fm / cm:9.2f} {diff:12.2e}')
print(f'          tip mean u [m]: ccx {ccx[0]:.6e} {ccx[1]:.6e} {ccx[2]:.6e} ({len(rows)} nodes), '
      f'ft {ft[0]:.6e} {ft[1]:.6e} {ft[2]:.6e}')
if not diff < 1e-6:  # CalculiX prints 7 digits; the codes agree to about 5e-8
    sys.exit(f"benchmark failed: the tip displacements differ by {diff:.2e} (bound 1e-6)")
# FlexTrack's stages of its median run (stdout: summary.json is written before its output stage ends).
stages = [l.strip() for l in open(f"{tag}_ft_{fr}.log") if l.strip().startswith("wall time [s]:")]
if stages:
    print(f"          ft run {fr}: {stages[0]}; peak {s.get('peak_memory_MiB', float('nan')):.1f} MiB")
PY
done
