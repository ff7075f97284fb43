#!/bin/bash
# Starts 8 flextrack processes at once (issue 9, item 7: parallel starts used to fail in Open
# MPI's singleton start-up, exit 1 "A call to mkdir was unable to create the desired
# directory") and requires every one to succeed and write its summary.json.
# Usage: eight_at_once.sh EXE COMMAND SCENE OUT
exe=$1 command=$2 scene=$3 out=$4
rm -rf "$out" && mkdir -p "$out"
pids=()
for i in 1 2 3 4 5 6 7 8; do
  "$exe" "$command" "$scene" -o "$out/run_$i" >"$out/log_$i.txt" 2>&1 &
  pids+=($!)
done
failed=0
for i in 1 2 3 4 5 6 7 8; do
  if ! wait "${pids[$((i - 1))]}"; then
    echo "FAIL: $command $i exited non-zero:"; cat "$out/log_$i.txt"; failed=1
  elif [ ! -s "$out/run_$i/summary.json" ]; then
    echo "FAIL: $command $i wrote no summary.json"; failed=1
  elif [ "$command" = run ] && ! grep -q '"status": "completed"' "$out/run_$i/summary.json"; then
    echo "FAIL: run $i did not complete"; failed=1
  fi
done
[ $failed = 0 ] && echo "ok: 8 simultaneous '$command' processes succeeded"
exit $failed
