#!/bin/bash
# Starts 8 'flextrack run' processes at once (issue 9, item 7: parallel starts used to fail in
# OpenMPI's singleton start-up) and requires every one to succeed and write its results.
# Usage: eight_at_once.sh EXE SCENE OUT
exe=$1 scene=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
pids=()
for i in 1 2 3 4 5 6 7 8; do
  "$exe" run "$scene" -o "$out/run_$i" >"$out/log_$i.txt" 2>&1 &
  pids+=($!)
done
failed=0
for i in 1 2 3 4 5 6 7 8; do
  if ! wait "${pids[$((i - 1))]}"; then
    echo "FAIL: run $i exited non-zero:"; cat "$out/log_$i.txt"; failed=1
  elif [ ! -s "$out/run_$i/probes.csv" ] || ! grep -q '"status": "completed"' "$out/run_$i/summary.json"; then
    echo "FAIL: run $i wrote no complete results"; failed=1
  fi
done
[ $failed = 0 ] && echo "ok: 8 simultaneous runs succeeded"
exit $failed
