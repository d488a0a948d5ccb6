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
