"""Which BLAS runs (flexbearing.common.blas), read from the process's memory map, against what the
dynamic linker was told to load: Debian's reference BLAS put first on LD_LIBRARY_PATH, and the
libblas.so.3 alternative (OpenBLAS when the Makefile could install it)."""
import json
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


def _run_child(code: str) -> str:
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    env["LD_LIBRARY_PATH"] = ""
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True,
                         cwd=Path(__file__).resolve().parents[1])
    return out.stdout.strip().splitlines()[-1]


@pytest.mark.skipif(not OPENBLAS.exists(), reason="libopenblas0-pthread is not installed")
def test_one_blas_thread_also_when_numpy_was_imported_first():
    """A script that imports numpy before flexbearing: OpenBLAS has read its thread count (every
    core) before flexbearing could set OPENBLAS_NUM_THREADS; flexbearing then sets it in the loaded
    library (flexbearing/__init__.py). A value the user sets still wins."""
    code = "import numpy; " + CHILD
    assert json.loads(_run_child(code))[2] == 1
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    out = subprocess.run([sys.executable, "-c", code], env=dict(env, LD_LIBRARY_PATH="", OPENBLAS_NUM_THREADS="2"),
                         capture_output=True, text=True, check=True)
    assert json.loads(out.stdout.strip().splitlines()[-1])[2] == 2


# a 64x64 least-squares solve (LAPACK gelsd, as the held-cage Newton's step) of a fixed system, its
# bits in hex: OpenBLAS on 1 and on 2 threads rounds it differently (measured on 2 cores)
LSTSQ = ("import numpy as np; rng = np.random.default_rng(1); a = rng.standard_normal((64, 64)); "
         "b = rng.standard_normal(64); print(np.linalg.lstsq(a, b, rcond=None)[0].tobytes().hex())")


def test_a_linear_solve_s_bits_do_not_depend_on_what_was_imported_first():
    """The program's runs are reproducible bit for bit whatever the calling script imported first:
    the same least-squares solve after `import numpy; import flexbearing` and after
    `import flexbearing` alone (before the fix the first ran on every core's OpenBLAS threads and
    differed in its last bits on a machine of 2 or more cores; on one core it cannot differ)."""
    assert _run_child("import numpy; import flexbearing; " + LSTSQ) == _run_child("import flexbearing; " + LSTSQ)


@pytest.mark.slow
def test_an_uncertainty_row_does_not_depend_on_what_was_imported_first():
    """The study's point 47 case 11 (cold oil: its path runs the quasi-static start, the thrust state from
    the settled dynamics and the continuation, a long chain of roundings) in two fresh processes, one
    that imported numpy first: the same end state bit for bit (before the fix, on 2 cores, when the run
    still had no root: residual 0.019501583945619867 after `import numpy`, 0.01943452654461777 without)."""
    row = ("from flexbearing.studies.uncertainty import load_unknowns, sample_points, steady_case_slip; "
           "from flexbearing.studies.validation.slip_rate import slip_rate_cases; "
           "points = sample_points(load_unknowns('scenes/slip_rate_unknowns.toml')); "
           "r = steady_case_slip(points[47], slip_rate_cases()[10]); "
           "print(repr((r['residual'], r['cage_speed'], r['slip_pct'])))")
    assert _run_child("import numpy; " + row) == _run_child(row)
