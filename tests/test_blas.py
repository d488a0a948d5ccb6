"""Which BLAS runs (flexbearing.common.blas), read from the process's memory map, against what the
dynamic linker was told to load: Debian's reference BLAS put first on LD_LIBRARY_PATH, and the
libblas.so.3 alternative (OpenBLAS when the Makefile could install it)."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

from flexbearing.common.blas import DEBIAN_REFERENCE_BLAS_DIRS as REFERENCE_DIRS
OPENBLAS = Path("/usr/lib/x86_64-linux-gnu/openblas-pthread/libblas.so.3")
CHILD = ("import flexbearing, json; from flexbearing.common.blas import blas_info; "
         "i = blas_info(); print(json.dumps([i.name, i.path, i.threads, i.optimised]))")


def _child(env_extra: dict):
    import json
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    env.update(env_extra)
    out = subprocess.run([sys.executable, "-c", CHILD], env=env, capture_output=True, text=True,
                         check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.skipif(not Path(REFERENCE_DIRS[0], "libblas.so.3").exists(),
                    reason="Debian's reference BLAS (libblas3) is not installed")
def test_reference_blas_first_on_the_library_path_is_seen_as_reference():
    name, path, threads, optimised = _child({"LD_LIBRARY_PATH": ":".join(REFERENCE_DIRS)})
    assert name == "reference" and not optimised
    assert path.startswith(REFERENCE_DIRS[0])
    assert threads is None


@pytest.mark.skipif(not OPENBLAS.exists(), reason="libopenblas0-pthread is not installed")
def test_openblas_alternative_is_seen_with_one_thread_by_default():
    """flexbearing sets OPENBLAS_NUM_THREADS=1 before numpy loads the library (flexbearing/__init__);
    a value the user sets wins."""
    env = {"LD_LIBRARY_PATH": ""}
    name, path, threads, optimised = _child(env)
    assert name == "OpenBLAS" and optimised and "openblas" in path
    assert threads == 1
    assert _child(dict(env, OPENBLAS_NUM_THREADS="2"))[2] == 2
