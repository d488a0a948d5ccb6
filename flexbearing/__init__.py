"""flexbearing: a finite-element-centric flexible multibody simulator for aero-engine main-shaft
ball bearings with a flexible cage.

The package is a stack of layers, each importing only the ones below it (docs/architecture.md):

    physics core: common < mesh < fem_cage < multibody < coupling
    application:  simulation < analysis < studies < cli

`python -m flexbearing` runs the command line (flexbearing.cli.main). `flexbearing.verification`
holds the independent checks that tests and benchmarks run; the program never imports it.
"""

import os as _os
import sys as _sys

# One BLAS thread per process unless the user sets OPENBLAS_NUM_THREADS: the program's parallelism
# is processes (Dask workers, one per core), and OpenBLAS threads on top of them oversubscribe the
# cores (measured, the paper cage's reduction alone on 2 cores: 2 threads were 1.0 s faster of
# 33 s for 57 % more CPU time; in a study's two workers, four spinning threads on two cores). One
# thread also keeps a run's rounding independent of the machine's core count. Read by OpenBLAS
# when it loads, i.e. at numpy's first import: flexbearing is imported first by the command line
# and the test suite (tests/conftest.py). A process that imported numpy before flexbearing (a user's
# script that starts with `import numpy`) has OpenBLAS running on every core already; the thread
# count is then set in the loaded library. Without this a run's result depended on its script's
# import order: the uncertainty study's point 47 case 11 ended at residual 0.019501583945619867
# after `import numpy` and at 0.01943452654461777 without, on 2 cores (numpy.linalg's LAPACK calls,
# e.g. the held-cage Newton's least-squares step: a 64×64 lstsq already rounds differently on 1 and
# 2 threads).
_BLAS_THREADS_GIVEN = "OPENBLAS_NUM_THREADS" in _os.environ
_os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
if not _BLAS_THREADS_GIVEN and "numpy" in _sys.modules:
    from flexbearing.common.blas import set_openblas_threads as _set_openblas_threads

    _set_openblas_threads(1)
