#!/usr/bin/env bash
# Benchmark (ctest label "bench"): the slewing beam (Wu & Haug, parameters of Project Chrono 10's
# demo_MOD_slewing_beam; REFERENCES.md section 7). Runs bench_slewing_beam (tests/bench/
# slewing_beam.cc: a converged reference, its convergence check, then a work-precision table of
# IDA rtol 1e-3 ... 1e-10 for 4, 6 and 10 normal modes, integration wall time and error side by
# side) and plots error against wall time (work_precision.png, if gnuplot is installed).
# Target (issue 9): under 0.11 s of integration wall time at under 0.15 % of the peak tip
# deflection; the program prints "target met" or "target missed".
set -euo pipefail
exe=$(realpath "${1:?usage: slewing_beam.sh BENCH_SLEWING_BEAM_EXE WORKDIR}")
work=${2:-bench_slewing_beam_output}
mkdir -p "$work"
cd "$work"
"$exe" . | tee slewing_beam.log
if command -v gnuplot > /dev/null; then
  gnuplot <<'GP'
set terminal pngcairo size 800,560 noenhanced
set output "work_precision.png"
set datafile separator ","
set logscale xy
set xlabel "integration wall time [s]"
set ylabel "max |v_tip - v_ref| / peak"
set title "Slewing beam, 50 s: FlexTrack (IDA rtol 1e-3 ... 1e-10)"
set key top right
set arrow from 0.11, graph 0 to 0.11, graph 1 nohead dt 2
set arrow from graph 0, first 1.5e-3 to graph 1, first 1.5e-3 nohead dt 2
$chrono << EOD
5.5,2.9e-2
EOD
plot for [m in "4 6 10"] "work_precision.csv" using ($1 == real(m) ? $3 : 1/0):6 with linespoints title m." modes", \
     $chrono using 1:2 with points pt 7 ps 1.5 title "Chrono 10, CB 12 modes (REFERENCES.md 7)"
GP
  echo "plot: $PWD/work_precision.png"
fi
