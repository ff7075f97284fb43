"""FlexTrack from Python: run a scene or a study and get its results as numpy arrays and dicts.

Pure Python on numpy and h5py (Debian: python3-numpy, python3-h5py); it starts the flextrack
program with an argument vector (no shell sees a file name or a value) and reads the files the
run writes. doc/python.md has an example.

    import flextrack
    r = flextrack.run("prm/laser_robot.prm", set={"Multibody/End time": 2})
    r.probes["head_x_m"]            # numpy array, one value per output time (r.probes["time_s"])
    r.summary["integrator"]["steps"]
    r.results["coordinates"]        # the state in results.h5, with r.results.names["coordinates"]

    s = flextrack.sweep("prm/laser_robot_study.prm", jobs=2)
    s.table["max(head_deviation_m)"]    # numpy array, one value per case
    s.case(3).probes                    # the results of case 3

The program is found as the environment variable FLEXTRACK, else 'flextrack' on PATH, else the
build/flextrack of the source tree this module sits in; `executable=` chooses one.
"""
import csv
import json
import os
import shutil
import subprocess

import numpy as np

__all__ = ["run", "sweep", "read_run", "read_sweep", "RunResults", "SweepResults", "FlexTrackError"]


class FlexTrackError(RuntimeError):
    """flextrack ended with a non-zero exit status: 2 bad input, 3 solver failure, 4 internal error,
    128 + N a signal. `status` is that number, `message` its error line, `log` its whole output,
    `output` the results folder (a solver failure keeps the rows computed up to it there)."""

    def __init__(self, status, message, log, output):
        super().__init__(f"flextrack exited with status {status}: {message}")
        self.status, self.message, self.log, self.output = status, message, log, output


def _executable(executable=None):
    if executable:
        return executable
    if os.environ.get("FLEXTRACK"):
        return os.environ["FLEXTRACK"]
    found = shutil.which("flextrack")
    if found:
        return found
    tree = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", ".."))
    candidate = os.path.join(tree, "build", "flextrack")
    if os.path.exists(candidate):
        return candidate
    raise FileNotFoundError("no flextrack program: set FLEXTRACK, put it on PATH, or build it in build/")


def _value_text(value):
    """A Python value as the text of a parameter: numbers exactly (repr), booleans as deal.II's
    true/false, sequences as comma lists (vectors)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple, np.ndarray)):
        return ", ".join(_value_text(v) for v in value)
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    return str(value)


def _set_arguments(entries):
    """{"Multibody/End time": 2, "Body arm:Reduction/Number of normal modes": 8} -> --set ..."""
    arguments = []
    for entry, value in (entries or {}).items():
        arguments += ["--set", f"{entry}={_value_text(value)}"]
    return arguments


def _start(arguments, output, executable, quiet, mpi_processes=None):
    command = [_executable(executable)] + arguments
    if mpi_processes:
        command = [shutil.which("mpirun") or "mpirun", "-np", str(mpi_processes)] + command
    p = subprocess.run(command, capture_output=True, text=True)
    log = p.stdout + p.stderr
    if not quiet:
        print(p.stdout, end="")
    if p.returncode != 0:
        lines = [line for line in p.stderr.splitlines() if line.strip()]
        raise FlexTrackError(p.returncode, lines[-1] if lines else "(no message)", log, output)
    return log


def _read_csv(path):
    """A CSV file of FlexTrack as {column: numpy array}: float arrays where every cell is a
    number (an empty cell is NaN), else arrays of str."""
    if not os.path.exists(path):
        return {}
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    header, body = rows[0], rows[1:]
    table = {}
    for k, name in enumerate(header):
        cells = [r[k] if k < len(r) else "" for r in body]
        try:
            table[name] = np.array([float(c) if c != "" else np.nan for c in cells])
        except ValueError:
            table[name] = np.array(cells, dtype=str)
    return table


class Results(dict):
    """The datasets of results.h5 as numpy arrays (a dict by dataset path, e.g. "time", "coordinates",
    "reactions/slide/force"), with `names` (the column names of each dataset that has them) and
    `units` (each dataset's unit attribute)."""

    def __init__(self, path):
        super().__init__()
        self.names, self.units = {}, {}
        if not os.path.exists(path):
            return
        import h5py  # only needed here: a sweep without results.h5 needs no h5py

        def visit(name, item):
            if isinstance(item, h5py.Dataset):
                self[name] = item[()]
                if "names" in item.attrs:
                    self.names[name] = [n.decode() if isinstance(n, bytes) else str(n) for n in item.attrs["names"]]
                if "unit" in item.attrs:
                    u = item.attrs["unit"]
                    self.units[name] = u.decode() if isinstance(u, bytes) else str(u)

        with h5py.File(path, "r") as f:
            f.visititems(visit)


class RunResults:
    """The results of one run, read from its folder: `summary` (dict of summary.json), `probes`,
    `monitors`, `deviation` ({column: numpy array} of the CSV files), `results` (results.h5, read
    when first used), `folder`, `log` (the program's output, if it was run from here)."""

    def __init__(self, folder, log=""):
        self.folder, self.log = folder, log
        with open(os.path.join(folder, "summary.json")) as f:
            self.summary = json.load(f)
        self.probes = _read_csv(os.path.join(folder, "probes.csv"))
        self.monitors = _read_csv(os.path.join(folder, "monitors.csv"))
        self.deviation = _read_csv(os.path.join(folder, "deviation.csv"))
        self._results = None

    @property
    def results(self):
        if self._results is None:
            self._results = Results(os.path.join(self.folder, "results.h5"))
        return self._results

    @property
    def status(self):
        return self.summary.get("status")


class SweepResults:
    """The results of a study: `table` ({column of sweep.csv: numpy array}, one value per case),
    `rows` (the same as one dict per case), `folder`, `log`, and `case(n)` (the RunResults of
    case n, 1-based)."""

    def __init__(self, folder, log=""):
        self.folder, self.log = folder, log
        path = os.path.join(folder, "sweep.csv")
        self.table = _read_csv(path)
        with open(path, newline="") as f:
            self.rows = list(csv.DictReader(f))

    def case(self, number):
        names = [n for n in os.listdir(self.folder) if n.startswith("case_") and int(n[5:]) == number]
        if not names:
            raise KeyError(f"no case {number} in {self.folder}")
        return RunResults(os.path.join(self.folder, names[0]))


def run(scene, set=None, output=None, executable=None, quiet=True):
    """Runs `flextrack run SCENE` with the entries of `set` ({entry: value}, as --set takes them)
    into `output` (default: the program's rule, output/<scene name>/) and returns its RunResults.
    Raises FlexTrackError on a non-zero exit status."""
    arguments = ["run", os.fspath(scene)] + _set_arguments(set)
    if output is not None:
        arguments += ["-o", os.fspath(output)]
    log = _start(arguments, output, executable, quiet)
    folder = output if output is not None else _folder_from_log(log)
    return RunResults(folder, log)


def sweep(study, set=None, output=None, jobs=None, mpi_processes=None, executable=None, quiet=True):
    """Runs `flextrack sweep STUDY` (`jobs` cases at once, default one per core, or under
    `mpirun -np mpi_processes`)
    with the entries of `set` applied to the study file, into `output`; returns SweepResults. A
    failed case is a row of the table (its 'status'), not an exception."""
    arguments = ["sweep", os.fspath(study)] + _set_arguments(set)
    if output is not None:
        arguments += ["-o", os.fspath(output)]
    if not mpi_processes and jobs is not None:
        arguments += ["-j", str(int(jobs))]
    log = _start(arguments, output, executable, quiet, mpi_processes)
    folder = output if output is not None else _folder_from_log(log)
    return SweepResults(folder, log)


def read_run(folder):
    """The RunResults of a run folder written earlier."""
    return RunResults(folder)


def read_sweep(folder):
    """The SweepResults of a study folder written earlier."""
    return SweepResults(folder)


def _folder_from_log(log):
    """The results folder the program names in its last line ("results in DIR/ (...)")."""
    for line in reversed(log.splitlines()):
        line = line.strip()
        if line.startswith("results in "):
            return line[len("results in "):].split("/ (")[0]
    raise FlexTrackError(0, "the program did not say where its results are", log, None)
