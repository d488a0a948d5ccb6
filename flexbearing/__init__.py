"""flexbearing: a finite-element-centric flexible multibody simulator for aero-engine main-shaft
ball bearings with a flexible cage.

The package is a stack of layers, each importing only the ones below it (docs/architecture.md):

    physics core: common < mesh < fem_cage < multibody < coupling
    application:  simulation < analysis < studies < cli

`python -m flexbearing` runs the command line (flexbearing.cli.main). `flexbearing.verification`
holds the independent checks that tests and benchmarks run; the program never imports it.
"""

import os as _os

# One BLAS thread per process unless the user sets OPENBLAS_NUM_THREADS: the program's parallelism
# is processes (Dask workers, one per core), and OpenBLAS threads on top of them oversubscribe the
# cores (measured, the paper cage's reduction alone on 2 cores: 2 threads were 1.0 s faster of
# 33 s for 57 % more CPU time; in a study's two workers, four spinning threads on two cores). One
# thread also keeps a run's rounding independent of the machine's core count. Read by OpenBLAS
# when it loads, i.e. at numpy's first import: flexbearing is imported first by the command line
# and the test suite (tests/conftest.py).
_os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
