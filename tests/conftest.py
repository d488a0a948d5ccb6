import os

import numpy as np
import pytest
import scipy.sparse as sp


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
    import mesh.cage_mesh as cm
    from mesh.cage_geometry import PAPER_CAGE
    from fem_cage.reduction import build
    from fem_cage import reduced_cage as rcf
    key = rcf.cache_key(PAPER_CAGE, cm.DEFAULT_MESH_SIZE, cm.DEFAULT_ORDER, cm.DEFAULT_POCKET_SIZE,
                        rcf.DEFAULT_COUPLING, rcf.DEFAULT_N_FIXED, cm.DEFAULT_DEGREE, True)
    path = rcf.find_cached(key)       # the run's own cache entry (coupling.flexible_cage), if any
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
    from coupling.scene import loads_scene

    def make(name, record):
        return loads_scene(SHORT_FLEXIBLE_IMPACT.format(name=name, record=json.dumps(record)),
                           f"{name}.toml")
    return make
