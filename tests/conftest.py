import json
import os

import flexbearing  # noqa: F401  (first: sets one BLAS thread before numpy loads it)
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp


ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(autouse=True, scope="session")
def _isolated_cache(tmp_path_factory):
    """Tests never touch the user's cache unless FLEXBEARING_CACHE is set explicitly."""
    if "FLEXBEARING_CACHE" not in os.environ:
        os.environ["FLEXBEARING_CACHE"] = str(tmp_path_factory.mktemp("flexbearing-cache"))
    yield


def _spring_chain(n, seed):
    """Free chain of springs, 3 DOF per node (null space: 3 translations), SPD lumped M."""
    rng = np.random.default_rng(seed)
    rows, cols, vals = [], [], []
    for i in range(n // 3 - 1):
        k = rng.random() + 0.5
        for c in range(3):
            a, b = 3 * i + c, 3 * (i + 1) + c
            rows += [a, b, a, b]; cols += [a, b, b, a]; vals += [k, k, -k, -k]
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n)), sp.diags(rng.random(n) + 1.0).tocsr()


@pytest.fixture
def spring_chain():
    """spring_chain(n, seed) -> (K, M) of a free 3-DOF-per-node spring chain (algebra tests)."""
    return _spring_chain


@pytest.fixture(scope="session")
def paper_reduced_cage():
    """The paper's reduced cage (default mesh, P3, Craig–Bampton): from the test cache, else built
    with dolfinx once per session (a few minutes; slow tests only)."""
    import flexbearing.mesh.cage_mesh as cm
    from flexbearing.mesh.cage_geometry import PAPER_CAGE
    from flexbearing.fem_cage.reduction import build
    from flexbearing.fem_cage import reduced_cage as rcf
    key = rcf.cache_key(PAPER_CAGE, cm.DEFAULT_MESH_SIZE, cm.DEFAULT_ORDER, cm.DEFAULT_POCKET_SIZE,
                        rcf.DEFAULT_COUPLING, rcf.DEFAULT_N_FIXED, cm.DEFAULT_DEGREE, True)
    path = rcf.find_cached(key)       # the run's own cache entry (flexbearing.coupling.flexible_cage), if any
    if path is None:
        path, _, _ = build(PAPER_CAGE, cm.DEFAULT_MESH_SIZE, cm.DEFAULT_ORDER, cm.DEFAULT_POCKET_SIZE,
                           rcf.DEFAULT_COUPLING, rcf.DEFAULT_N_FIXED, degree=cm.DEFAULT_DEGREE)
    return rcf.read(path)


# The flexible paper bearing through one short, hard impact: 14,000 rpm, 55 kN / 4 kN, 3 ms with a
# 1 ms, 50 kN half-sine at 1.5 ms, sampled every 0.1 ms (30 samples). Long enough for a pocket
# collision and a stress peak between samples, short enough for a slow test.
SHORT_FLEXIBLE_IMPACT = """
name = "{name}"
[cage]
model = "flexible"
[operation]
duration = 0.003
[operation.speed]
phases = [{{ kind = "uniform", duration = 0.003, rpm = 14000 }}]
[operation.load]
axial_load = 55e3
radial_load = 4e3
[[operation.load.impacts]]
t_center = 0.0015
duration = 0.001
magnitude = 50e3
[output]
sample_interval = 1e-4
record = {record}
"""


@pytest.fixture
def short_flexible_impact():
    """Factory (name, record list) -> Scene of SHORT_FLEXIBLE_IMPACT."""
    import json
    from flexbearing.simulation.scene import loads_scene

    def make(name, record):
        return loads_scene(SHORT_FLEXIBLE_IMPACT.format(name=name, record=json.dumps(record)),
                           f"{name}.toml")
    return make


class DaskCluster:
    """A scheduler and `n` single-thread worker processes, each its own subprocess, as on a cluster
    (`python -m distributed.cli.dask_scheduler` / `dask_worker`: the `dask scheduler` and `dask
    worker` commands run by this environment's Python, which has flexbearing installed)."""

    def __init__(self, folder: Path, n: int = 2):
        self.folder = folder
        self.procs = []
        try:
            self._start(folder, n)
        except BaseException:
            self.close()
            raise

    def _start(self, folder: Path, n: int):
        env = dict(os.environ, PYTHONPATH=str(ROOT))    # FLEXBEARING_CACHE too
        sched_file = folder / "scheduler.json"
        log = (folder / "scheduler.log").open("w")
        self.procs.append(subprocess.Popen(
            [sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0",
             "--no-dashboard", "--scheduler-file", str(sched_file)], stdout=log, stderr=log, env=env))
        deadline = time.monotonic() + 60
        while not sched_file.exists() and time.monotonic() < deadline:
            time.sleep(0.2)
        time.sleep(0.2)
        self.address = json.loads(sched_file.read_text())["address"]
        for i in range(n):
            wlog = (folder / f"worker{i}.log").open("w")
            self.procs.append(subprocess.Popen(
                [sys.executable, "-m", "distributed.cli.dask_worker", self.address, "--nthreads", "1",
                 "--nworkers", "1", "--no-dashboard", "--memory-limit", "0", "--name", f"w{i}",
                 "--local-directory", str(folder / f"w{i}")], stdout=wlog, stderr=wlog, env=env))
        if n:
            from distributed import Client
            with Client(self.address, timeout="60s") as c:
                c.wait_for_workers(n, timeout=120)

    def close(self):
        for p in reversed(self.procs):
            p.terminate()
        for p in reversed(self.procs):
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()


@pytest.fixture(scope="session")
def dask_cluster(tmp_path_factory):
    """A Dask cluster of separate processes: a scheduler and two single-thread workers."""
    cluster = DaskCluster(tmp_path_factory.mktemp("dask"))
    yield cluster
    cluster.close()


# the fake physics of tests/test_run.py behind the command line, for the tests of what commands
# write and print (test_output_paths, test_one_line_errors)
@pytest.fixture
def fake_runs(monkeypatch):
    """`flexbearing run` / `study` with the fake physics of tests/test_run.py (no numba compilation)."""
    import functools
    import flexbearing.simulation.run as simulation_run
    from test_run import fake_backend
    real = simulation_run.run_scene
    monkeypatch.setattr(simulation_run, "run_scene", functools.partial(real, backend=fake_backend()))


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    """A finished fake run's results file, made once per module."""
    import flexbearing.simulation.run as simulation_run
    from test_run import fake_backend, fake_scene
    out = tmp_path_factory.mktemp("run") / "r.h5"
    simulation_run.run_scene(fake_scene(), out, quiet=True, backend=fake_backend())
    return out
