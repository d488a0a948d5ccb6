"""Which BLAS this process runs on: the reference (netlib) one or an optimised one.

Debian links numpy, scipy and PETSc/MUMPS against `libblas.so.3`, an alternative that points to
the reference BLAS unless an optimised one is installed (the Makefile installs Debian's OpenBLAS,
`libopenblas0-pthread`). Results are the same to rounding either way; speed is not. Level-3
operations (matrix products, triangular solves with many right-hand sides) run ~10x faster on
OpenBLAS (0.0105 s per column for a 30-column MUMPS solve on the paper cage against 0.032 s;
benchmarks/results/reduce_design_loop.md), so the cage reduction's eigensolver is chosen by it
(flexbearing.fem_cage.craig_bampton.fixed_interface_modes): a block method, whose work is
level-3 BLAS, only where that is fast.

The library is read from the process's own memory map (/proc/self/maps: the file the dynamic
linker actually loaded, after the alternatives' symlinks), so it is what runs, not what is installed.
"""
from __future__ import annotations

import ctypes
import os
from typing import NamedTuple

# substrings of a loaded library's path that mark an optimised BLAS (Debian's OpenBLAS is loaded as
# .../openblas-pthread/libblas.so.3, the libblas.so.3 alternative)
OPTIMISED = {"openblas": "OpenBLAS", "libmkl": "MKL", "libblis": "BLIS", "libflexiblas": "FlexiBLAS"}
# Debian's reference (netlib) BLAS and LAPACK folders (libblas3, liblapack3): first on
# LD_LIBRARY_PATH they win over the libblas.so.3 alternative for a child process (how the
# benchmarks and tests run the reference BLAS beside an installed OpenBLAS)
DEBIAN_REFERENCE_BLAS_DIRS = ("/usr/lib/x86_64-linux-gnu/blas", "/usr/lib/x86_64-linux-gnu/lapack")


class BlasInfo(NamedTuple):
    """name: OpenBLAS | MKL | BLIS | FlexiBLAS | reference | unknown (nothing loaded yet);
    path: the loaded library file; threads: OpenBLAS's thread count (None when not OpenBLAS);
    core: the kernel set OpenBLAS chose for this processor (e.g. Haswell; None when not OpenBLAS)."""
    name: str
    path: str | None
    threads: int | None
    core: str | None

    @property
    def optimised(self) -> bool:
        return self.name not in ("reference", "unknown")


def loaded_libraries() -> list[str]:
    """Paths of the shared objects mapped into this process (Linux /proc/self/maps)."""
    try:
        with open("/proc/self/maps") as f:
            return sorted({ln.split()[-1] for ln in f if ".so" in ln and "/" in ln})
    except OSError:
        return []


def blas_info() -> BlasInfo:
    """The BLAS numpy runs on (numpy is imported first: it loads the library)."""
    import numpy  # noqa: F401  (loads libblas.so.3)
    libs = loaded_libraries()
    for path in libs:
        for key, name in OPTIMISED.items():
            if key in path:
                threads, core = _openblas_threads_core(path) if name == "OpenBLAS" else (None, None)
                return BlasInfo(name, path, threads, core)
    for path in libs:
        if os.path.basename(path).startswith("libblas.so"):
            return BlasInfo("reference", path, None, None)
    return BlasInfo("unknown", None, None, None)


# OpenBLAS's thread-count setter as Debian's library and the PyPI wheels (64-bit integer builds,
# symbols suffixed "64_"; numpy >= 2's scipy-openblas also prefixed "scipy_") export it
OPENBLAS_SET_THREADS = ("openblas_set_num_threads", "openblas_set_num_threads64_",
                        "scipy_openblas_set_num_threads64_")
OPENBLAS_GET_THREADS = ("openblas_get_num_threads", "openblas_get_num_threads64_",
                        "scipy_openblas_get_num_threads64_")


def _first_symbol(lib, names):
    """The first of `names` that the library `lib` exports, or None."""
    return next((f for f in (getattr(lib, n, None) for n in names) if f is not None), None)


def set_openblas_threads(n: int) -> int | None:
    """Set the loaded OpenBLAS's thread count to n (its openblas_set_num_threads) and return the
    count now in force (openblas_get_num_threads), None where numpy runs on no OpenBLAS.

    OpenBLAS reads OPENBLAS_NUM_THREADS once, when it loads (at numpy's first import); this is how a
    process that imported numpy before flexbearing still gets the program's one thread
    (flexbearing/__init__.py: a run's rounding must not depend on what its process imported first).
    """
    info = blas_info()
    if info.name != "OpenBLAS":
        return None
    try:
        lib = ctypes.CDLL(info.path)
    except OSError:
        return None
    setter = _first_symbol(lib, OPENBLAS_SET_THREADS)
    if setter is None:
        return None
    setter(ctypes.c_int(int(n)))
    getter = _first_symbol(lib, OPENBLAS_GET_THREADS)
    return None if getter is None else int(getter())


def _openblas_threads_core(path: str):
    """OpenBLAS's own answers (openblas_get_num_threads, openblas_get_corename) from the loaded
    library: dlopen of a loaded library returns the same handle, nothing is loaded twice."""
    try:
        lib = ctypes.CDLL(path)
        lib.openblas_get_corename.restype = ctypes.c_char_p
        return int(lib.openblas_get_num_threads()), lib.openblas_get_corename().decode()
    except (OSError, AttributeError):
        return None, None
