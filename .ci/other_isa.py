"""Print the environment that runs the test suite on another instruction set than this machine's.

A tolerance fitted to one processor's rounding passes here and fails elsewhere (issue 36: three
tests failed on an AVX2 machine and passed on an AVX-512 one). `make test` therefore runs the fast
suite twice: as the machine is, and with
- numba compiling for generic x86-64 (NUMBA_CPU_NAME=generic: SSE2 only, no FMA contraction, no
  wide vectors; numba sets NUMBA_CPU_FEATURES to "" for it), in its own NUMBA_CACHE_DIR, and
- numpy's runtime-dispatched kernels (sums, exp, sin, ...) held to the x86-64 baseline
  (NPY_DISABLE_CPU_FEATURES: every dispatched feature this processor has; numpy refuses, with a
  warning on every import, a name the processor lacks, so only those it has are listed).
OpenBLAS's kernel choice is left as the machine has it: some machines set OPENBLAS_CORETYPE
because older OpenBLAS builds compute wrong results or crash on their processors, and tests and
CI must not change it. (On this machine the fast suite was also run with OPENBLAS_CORETYPE=Prescott,
OpenBLAS's generic SSE3 kernels, in two make test runs on 2026-11-27: 1038 passed both times.)
Every machine CI or a user runs on has more than the baseline, so the second pass always differs
from the first in the last digits of the arithmetic. Prints the numpy feature list;
`.ci/on-other-isa CMD...` runs CMD with both settings.
"""
import numpy.core._multiarray_umath as mu

have = mu.__cpu_features__
dispatched = [f for f in mu.__cpu_dispatch__ if have.get(f)]
print(" ".join(dispatched))
