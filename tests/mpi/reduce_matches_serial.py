"""'mpirun -np 2 flextrack reduce' against the serial 'flextrack reduce' of the same body (issue 27).

The distributed reduction factorises with MUMPS and solves the eigenproblem with PARPACK on the
rows each process owns; the serial one with CHOLMOD and ARPACK on the standard form. Both reduce
the same finite element model, so the reference of the distributed file is the serial file:

- frequencies of the reduced model to 1e-9 relative;
- the modes equal up to sign, or up to a rotation within a group of repeated frequencies: the
  transformation T that maps the serial modes onto the distributed ones (least squares on the
  drawn displacement fields) must be orthogonal to 1e-7 (a check of the fit) and reproduce them
  to 1e-8 of their largest entry;
- reduced stiffness and mass, and every inertia invariant, equal after that transformation
  (K_2 = T^T K_1 T, I3_2 = I3_1 T, P_2,k = sum_j T_jk P_1,j, Q_2,kl = sum T_jk T_ml Q_1,jm) to
  1e-8 of the largest entry of each;
- a 'run' of a scene with either file gives the same probes to 1e-9 m (SCENE_PRM '-': no run);
- a body that will not fit (FLEXTRACK_MEMORY_LIMIT set to 0.01 GiB, below what the process
  holds already) is refused before it starts (its assembly if it has a solid, else its
  factorisation), serially and on 2 processes: exit status 3 (a solver failure), a message with
  the estimate and what to do, and no reduced body written.

Usage: reduce_matches_serial.py EXE MPIRUN BODY_PRM SCENE_PRM OUT
"""
import csv
import json
import os
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np


def check(condition, message):
    print(("ok:   " if condition else "FAIL: ") + message, flush=True)
    if not condition:
        sys.exit(1)


def run(args, cwd, env):
    p = subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True)
    print(p.stdout)
    print(p.stderr, file=sys.stderr)
    check(p.returncode == 0, " ".join(args[:4]) + f"... exits 0 (got {p.returncode})")
    return p.stdout


def body(path):
    with h5py.File(path, "r") as f:
        return {name: np.array(f[name]) for name in
                ["reduced/frequencies_hz", "reduced/stiffness", "reduced/mass", "drawing/mode_displacements",
                 "inertia/mass", "inertia/first_moment", "inertia/inertia_origin", "inertia/I3", "inertia/I4",
                 "inertia/P", "inertia/Q"]}


def relative(a, b, bound=0.0):
    """Largest difference over the largest entry, or over @p bound where that is larger: a
    quantity that vanishes (I3 of a mean-axis frame) is compared with its possible size."""
    scale = max(np.max(np.abs(a)), np.max(np.abs(b)), bound, 1e-300)
    return float(np.max(np.abs(a - b)) / scale)


def compare_bodies(serial_file, mpi_file):
    """The checks of the module text on two reduced body files."""
    a, b = body(serial_file), body(mpi_file)

    fa, fb = a["reduced/frequencies_hz"], b["reduced/frequencies_hz"]
    check(fa.shape == fb.shape, f"both have {fa.size} modes")
    worst = float(np.max(np.abs(fa - fb) / np.abs(fa)))
    check(worst <= 1e-9, f"frequencies equal to 1e-9 relative (largest difference {worst:.2e})")

    # The transformation from the serial to the distributed modes.
    A = a["drawing/mode_displacements"].reshape(fa.size, -1).T
    B = b["drawing/mode_displacements"].reshape(fb.size, -1).T
    T = np.linalg.lstsq(A, B, rcond=None)[0]
    # T comes from a fit on the drawn points, which weigh the modes otherwise than M does: its
    # orthogonality checks the fit (both bases are M-orthonormal, so the exact T is orthogonal).
    orthogonal = float(np.max(np.abs(T.T @ T - np.eye(fa.size))))
    check(orthogonal <= 1e-7, f"the modes map onto each other orthogonally (|T^T T - 1| = {orthogonal:.2e})")
    mapped = relative(A @ T, B)
    check(mapped <= 1e-8, f"modes equal up to sign or rotation among repeated frequencies ({mapped:.2e})")
    # Round T to what it must be where the frequencies are distinct (a sign), so that the
    # comparisons below test the files, not the least-squares fit.
    n_rotated = 0
    for k in range(fa.size):
        group = np.abs(fa - fa[k]) <= 1e-6 * fa[k]
        if group.sum() == 1:
            T[:, k] = 0
            T[k, k] = np.sign(B[:, k] @ A[:, k])
        else:
            n_rotated += 1
    print(f"{fa.size - n_rotated} modes compared up to sign, {n_rotated} up to a rotation")

    # Bounds of the invariants of mass-normalised modes (int rho |phi|^2 = 1), by Cauchy-Schwarz:
    # |I3| <= sqrt(m), |I4| and |P| <= sqrt(int rho |x|^2) = sqrt(tr J_O / 2), |Q| <= 1.
    m = float(a["inertia/mass"][0])
    r = float(np.sqrt(np.trace(a["inertia/inertia_origin"]) / 2))
    for name, transform, bound in [
        ("reduced/stiffness", lambda x: T.T @ x @ T, 0),
        ("reduced/mass", lambda x: T.T @ x @ T, 0),
        ("inertia/mass", lambda x: x, 0),
        ("inertia/first_moment", lambda x: x, 0),
        ("inertia/inertia_origin", lambda x: x, 0),
        ("inertia/I3", lambda x: x @ T, np.sqrt(m)),
        ("inertia/I4", lambda x: x @ T, r),
        ("inertia/P", lambda x: np.einsum("jk,jab->kab", T, x), r),
        ("inertia/Q", lambda x: np.einsum("jk,ml,jmab->klab", T, T, x), 1.0),
    ]:
        d = relative(transform(a[name]), b[name], bound)
        check(d <= 1e-8, f"{name} equal to 1e-8 of its largest entry or of its bound ({d:.2e})")
    # The geometric stiffness of the 12 unit inertial loads, where the body has it.
    with h5py.File(serial_file, "r") as fs, h5py.File(mpi_file, "r") as fm:
        name = "reduced/geometric_stiffness"
        if name in fs or name in fm:
            check(name in fs and name in fm, f"both files have {name}")
            d = relative(np.einsum("jk,cjm,ml->ckl", T, np.array(fs[name]), T), np.array(fm[name]))
            check(d <= 1e-8, f"{name} equal to 1e-8 of its largest entry ({d:.2e})")


def compare_runs(exe, scene_prm, folders, env):
    """Runs @p scene_prm for 0.2 s in each folder (with the reduced body in its ./output/) and
    compares the probe positions."""
    # A run with either file: the scene finds the body in ./output/ of its working folder. With
    # generalised-alpha at its fixed step, both runs take the same steps and differ by what the
    # files differ. An adaptive step sequence amplifies those round-off differences to the
    # integration error: IDA at rtol 1e-6 took 953 and 998 steps on the 2.4e5-dof body of
    # tests/bench/distributed_reduction.py, and the tips differed by 2.0e-6 m (1.0e-12 m here).
    probes = {}
    for name, folder in folders.items():
        log = run([exe, "run", scene_prm, "-o", "run", "--set", "Multibody/End time=0.2",
                   "--set", "Multibody/Integrator/Method=generalized_alpha"], folder, env)
        check("reduced body is up to date" in log, f"the run uses the {name} reduction's file")
        with open(os.path.join(folder, "run", "probes.csv")) as f:
            rows = list(csv.DictReader(f))
        probes[name] = np.array([[float(v) for v in r.values()] for r in rows])
        columns = list(rows[0].keys())
    position = [i for i, c in enumerate(columns) if c.endswith(("_x_m", "_y_m", "_z_m"))]
    check(len(position) > 0 and probes["serial"].shape == probes["mpi"].shape, "both runs wrote the same probes")
    d = float(np.max(np.abs(probes["serial"][:, position] - probes["mpi"][:, position])))
    check(d <= 1e-9, f"probe positions of the two runs equal to 1e-9 m (largest difference {d:.2e} m)")


def main():
    exe, mpirun, body_prm, scene_prm, out = sys.argv[1:6]
    shutil.rmtree(out, ignore_errors=True)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OPENBLAS_NUM_THREADS="1")  # two processes on two cores: one BLAS thread each
    folders = {}
    for name, launcher in [("serial", []), ("mpi", [mpirun, "-np", "2", "--oversubscribe"])]:
        folders[name] = os.path.join(out, name)
        os.makedirs(folders[name])
        log = run(launcher + [exe, "reduce", body_prm], folders[name], env)
        if name == "mpi":
            check("distributed over 2 processes" in log, "the log says the reduction is distributed")
    stem = os.path.splitext(os.path.basename(body_prm))[0]
    files = {n: os.path.join(folders[n], "output", stem, "reduced_body.h5") for n in folders}
    with open(os.path.join(folders["mpi"], "output", stem, "summary.json")) as f:
        check(json.load(f)["mpi_processes"] == 2, "summary.json: mpi_processes = 2")
    compare_bodies(files["serial"], files["mpi"])

    if scene_prm != "-":
        compare_runs(exe, scene_prm, folders, env)

    # The estimates are not absurd: with twice what the uncapped runs used at their peak (at least
    # 1 GiB; a Release build holds about 0.2 GiB per process, a Debug build with AddressSanitizer
    # about 0.7 GiB) for the program on this machine, the small body is reduced, on one and on two
    # processes. The cap is for all processes of the machine together.
    for name, launcher in [("serial", []), ("mpi", [mpirun, "-np", "2", "--oversubscribe"])]:
        with open(os.path.join(folders[name], "output", stem, "summary.json")) as f:
            summary = json.load(f)
        used_mib = sum(summary.get("peak_memory_per_process_MiB", [summary["peak_memory_MiB"]]))
        cap_gib = max(1.0, 2.0 * used_mib / 1024.0)
        print(f"{name}: capped at {cap_gib:.2f} GiB (the uncapped run peaked at {used_mib:.0f} MiB in all)")
        folder = os.path.join(out, "capped_" + name)
        os.makedirs(folder)
        run(launcher + [exe, "reduce", body_prm], folder, dict(env, FLEXTRACK_MEMORY_LIMIT=f"{cap_gib:.3f}"))
        check(os.path.exists(os.path.join(folder, "output", stem, "reduced_body.h5")), f"{name}: reduced within 1 GiB")

    # A body that does not fit is refused before it is assembled, on one and on two processes
    # (the factorisation's own check, which comes later, is tested in
    # SparseFactorization.refuses_a_factor_that_does_not_fit).
    limited = dict(env, FLEXTRACK_MEMORY_LIMIT="0.01")
    for name, launcher in [("serial", []), ("mpi", [mpirun, "-np", "2", "--oversubscribe"])]:
        folder = os.path.join(out, "refused_" + name)
        os.makedirs(folder)
        p = subprocess.run(launcher + [exe, "reduce", body_prm], cwd=folder, env=limited, capture_output=True,
                           text=True)
        print(p.stdout, p.stderr)
        check(p.returncode == 3, f"{name}: exit status 3 when the body does not fit (got {p.returncode})")
        processes = "2 processes" if name == "mpi" else "1 process"
        text = open(body_prm).read()
        solid = "subsection Solid" in text and not re.search(r"set Solid *= *false", text)
        step = r"assembling the body model \(\d+ solid dofs" if solid else r"factorisation.* of the \d+-dof matrix"
        check(re.search(step + r".* needs about [0-9.e-]+ GiB per process with " + processes +
                        r".*only 0 GiB are available there; it was not started.*coarser mesh", p.stderr) is not None,
              f"{name}: the message gives the estimate and what to do")
        check(not os.path.exists(os.path.join(folder, "output", stem, "reduced_body.h5")),
              f"{name}: no reduced body written")

if __name__ == "__main__":
    main()
