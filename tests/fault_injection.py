"""Fault injection for the results file (issue 36): kill a run at a random instant or let its disk
fill up, then check that nothing the last checkpoint covers was lost and that the resumed file
equals an uninterrupted run's, bit for bit.

Used by tests/test_fault_injection.py (a few kills, fast suite) and benchmarks/fault_injection.py
(>= 100 kills across the commands, and ENOSPC on a small tmpfs). The run is the fake backend of
tests/test_run.py (deterministic adaptive RK4) with one wide output (90 values a sample, so that
its blocks fill many chunks), slowed down by a sleep per integrator call so that a kill can land in
every phase of a run: imports, setup, integration, a block being written, a checkpoint, the final
compression.

    python tests/fault_injection.py run OUT.h5 [SLEEP_S]     # the run, in a process of its own
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))

SCENE = """
name = "fault_injection"
[operation]
duration = 0.3
[operation.speed]
phases = [{kind = "ramp", duration = 0.1, start_rpm = 1000, end_rpm = 4000},
          {kind = "uniform", duration = 0.2, rpm = 4000}]
[operation.load]
points = [{t = 0.0, axial_load = 100.0, radial_load = 50.0}, {t = 0.13, axial_load = 300.0, radial_load = 80.0}]
[[operation.load.impacts]]
t_center = 0.15
duration = 0.004
magnitude = 1000.0
shape = "half-sine"
[integrator]
tolerance = 1e-9
initial_step = 1e-5
[output]
sample_interval = 1e-3
record = ["cage_speed", "kinematics"]
checkpoint_every = 7
"""


def scene():
    from flexbearing.simulation.scene import loads_scene
    return loads_scene(SCENE, "fault_injection.toml")


def backend(sleep: float = 0.0):
    """tests/test_run.py's fake backend plus `kinematics_field` (30 x 3 values a sample, a
    deterministic function of the state); `sleep` s per integrator call."""
    from test_run import fake_advance, fake_backend, fake_outputs

    def outputs(model, t, y, outputs=(), speed_table=None):
        out = fake_outputs(model, t, y, outputs, speed_table)
        if "kinematics" in outputs:
            out["kinematics_field"] = np.sin(y[0] * np.arange(1, 91)).reshape(30, 3) * y[2]
        return out

    def advance(*a, **k):
        if sleep:
            time.sleep(sleep)
        return fake_advance(*a, **k)

    b = fake_backend(advance=advance, evaluate_outputs=outputs)
    b.output_units = {**b.output_units, "kinematics_field": "m"}
    return b


def run(out, sleep: float = 0.0, resume: bool = False):
    from flexbearing.simulation.run import run_scene
    return run_scene(scene(), out, resume=resume, quiet=True, backend=backend(sleep))


def start(out, sleep: float = 0.02) -> subprocess.Popen:
    """The run in a process (and session) of its own."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(HERE), str(HERE.parent)]))
    return subprocess.Popen([sys.executable, str(Path(__file__)), "run", str(out), str(sleep)], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)


def _session_members(sid: int) -> list[int]:
    """The processes of session `sid` (a command's Dask workers included, whatever their group)."""
    pids = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                if os.getsid(int(entry)) == sid:
                    pids.append(int(entry))
            except OSError:
                pass
    return pids


def kill_after(proc: subprocess.Popen, delay: float) -> bool:
    """SIGKILL the process's whole session (its group and any worker processes) after `delay` s,
    and wait until every one of them is gone (a worker still dying holds its files' HDF5 locks);
    False if the process had ended before."""
    try:
        proc.wait(timeout=delay)
        landed = False
    except subprocess.TimeoutExpired:
        landed = True
    deadline = time.monotonic() + 30.0
    while True:
        members = _session_members(proc.pid)
        for pid in members:
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass
        if proc.poll() is None:
            proc.wait()
        if not [p for p in members if os.path.exists(f"/proc/{p}") and _alive(p)] or time.monotonic() > deadline:
            return landed
        time.sleep(0.05)


def _alive(pid: int) -> bool:
    """False for a zombie (dead, not yet reaped by its parent) or a vanished process."""
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@dataclass
class Check:
    """What a killed (or disk-full) run left: the samples its last checkpoint covers, how many of
    them could not be read back or differ from the uninterrupted run, whether the file opened."""
    opened: bool
    n_checkpoint: int
    lost: int
    status: str


def check_file(out, reference: dict) -> Check:
    """Read every row the newest valid checkpoint covers (each chunk decompressed, if compressed)
    and compare it bit for bit with the uninterrupted run's `reference` (read_outputs)."""
    import h5py

    from flexbearing.simulation.results import read_checkpoint
    out = Path(out)
    if not out.exists() or out.stat().st_size == 0 or not h5py.is_hdf5(out):
        return Check(opened=False, n_checkpoint=0, lost=0, status="no file yet")
    try:
        f = h5py.File(out, "r")
    except OSError as exc:
        return Check(opened=False, n_checkpoint=-1, lost=-1, status=f"cannot open: {exc}")
    with f:
        status = str(f.attrs.get("status", ""))
        try:
            cp = read_checkpoint(f)
        except Exception as exc:                       # noqa: BLE001 - the harness reports it
            return Check(True, -1, -1, f"checkpoint unreadable: {exc}")
        n = 0 if cp is None else cp["n_samples"]
        lost = 0
        for name, ref in reference.items():
            if n == 0:
                break
            try:
                rows = f["outputs"][name][:n]
                bad = int(np.count_nonzero(~np.all((rows == ref[:n]).reshape(n, -1), axis=1)))
            except Exception:                          # noqa: BLE001 - unreadable rows are lost
                bad = n
            lost = max(lost, bad)
        return Check(True, n, lost, status)


def same_results(a, b) -> bool:
    """Every dataset of two results files equal bit for bit (and the same set of datasets)."""
    from flexbearing.simulation.results import read_outputs
    ra, rb = read_outputs(a), read_outputs(b)
    return sorted(ra) == sorted(rb) and all(
        ra[k].dtype == rb[k].dtype and ra[k].shape == rb[k].shape and ra[k].tobytes() == rb[k].tobytes()
        for k in ra)


def leftover_temporaries(folder) -> list[str]:
    """Temporaries (flexbearing.common.safe_files) a SIGKILL left in a folder."""
    return sorted(p.name for p in Path(folder).iterdir() if p.name.startswith(".") and p.name.endswith(
        (".tmp", ".finishing.h5")))


if __name__ == "__main__":
    if sys.argv[1] == "run":
        run(sys.argv[2], float(sys.argv[3]) if len(sys.argv) > 3 else 0.02)
