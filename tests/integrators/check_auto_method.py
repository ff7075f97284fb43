#!/usr/bin/env python3
"""'Method = auto' (issue 24, item 3): a scene with elastic modes and no Integrator subsection
runs with Radau IIA, and says so in the log and summary.json.

  check_auto_method.py FLEXTRACK_EXE SCENE OUTPUT_FOLDER

Also asserts that the run completes with its energy balance closed to 1e-3 of the run's energy
scale (the monitor's own measure; an unstable or wrongly damped integration of the elastic modes
breaks it). Prints 'FAILED' on a failed check.
"""
import json
import os
import shutil
import subprocess
import sys


def main():
    exe, scene, out = sys.argv[1:4]
    shutil.rmtree(out, ignore_errors=True)
    run = subprocess.run([exe, "run", scene, "-o", out], capture_output=True, text=True)
    print(run.stdout[-3000:])
    assert run.returncode == 0, f"exit status {run.returncode}: {run.stderr}"
    assert "method Radau IIA of order 5" in run.stdout, "the log does not say that Radau IIA was chosen"
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    method = summary["integrator"]["method"]
    print(f"summary.json: integrator method {method}, {summary['integrator']['steps']} steps")
    assert method == "radau", f"method {method}, expected radau"
    balance = summary["max_over_output_rows"]["relative_energy_balance_error"]
    print(f"energy balance error {balance:.2e} of the energy scale (at most 1e-3)")
    assert balance <= 1e-3, "the energy balance does not close"
    print("auto method checked")


if __name__ == "__main__":
    try:
        main()
    except (AssertionError, OSError, KeyError, ValueError) as e:
        print(f"check_auto_method: FAILED: {e}")
        sys.exit(1)
