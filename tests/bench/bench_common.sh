# Shared by the benchmarks against CalculiX (solid_vs_calculix.sh, static_vs_calculix.sh); sourced.

# timed TAG COMMAND...: runs COMMAND under /usr/bin/time -v, its output to TAG.log and the
# report (wall time, peak resident memory) to TAG.time; stops the script if COMMAND fails.
timed() {
  local tag=$1; shift
  /usr/bin/time -v "$@" > "$tag.log" 2> "$tag.time" || { echo "$tag failed:"; tail "$tag.log" "$tag.time"; exit 1; }
}

# job_name PREFIX SIZE: the CalculiX job name of a mesh (ccx reads JOB.inp: no spaces, no dots).
job_name() {
  local name="$1_${2// /x}"
  echo "${name//./p}"
}

# The meshes, into the array `sizes`: BENCH_SIZES, ';'-separated make_block_inp.py arguments
# "nx ny nz [L B H]", e.g. BENCH_SIZES="32 32 8 1 1 0.25" for the plate of issue 12 (1.1e5
# dofs); by default the blocks 1 x 0.1 x 0.1 m of about 2e4, 7e4 and 2e5 dofs.
IFS=';' read -r -a sizes <<< "${BENCH_SIZES:-50 5 5;80 8 8;120 12 12}"
