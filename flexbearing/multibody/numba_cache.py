"""The guard of the compiled kernels' on-disk numba cache (imported first by every module of `rhs`).

numba keys the cache of a function on its own source file only, but `rhs` inlines and links the
compiled code of other modules; `_invalidate_stale_numba_cache` (run once, at import) removes the
package's cached kernels when any of their sources changed.
"""
from __future__ import annotations

import glob
import hashlib
import os


def _invalidate_stale_numba_cache() -> None:
    """Drop the compiled kernels' numba cache when any source they link changed.

    numba's on-disk cache of a function is keyed on its own source file only, but `rhs` links in
    the compiled code of other modules (geometry, traction, profiles, hertz, the floating frame,
    ...), the integrator links `rhs` and the stress monitor (which links flexbearing.fem_cage.von_mises): an
    edit there would otherwise leave a stale kernel in the cache. A hash of every source of this
    package and of flexbearing/fem_cage/von_mises.py is kept next to the cache; on mismatch the cached entries
    of every module of the package are removed.
    """
    here = os.path.dirname(os.path.abspath(__file__))
    sources = sorted(glob.glob(os.path.join(here, "*.py")))
    sources.append(os.path.join(here, "..", "fem_cage", "von_mises.py"))
    h = hashlib.sha1()
    for path in sources:
        try:
            with open(path, "rb") as f:
                h.update(os.path.basename(path).encode())
                h.update(f.read())
        except OSError:
            pass
    cache = os.environ.get("NUMBA_CACHE_DIR") or os.path.join(here, "__pycache__")
    stamp = os.path.join(cache, "flexbearing_rhs_sources.sha1")
    try:
        with open(stamp) as f:
            if f.read().strip() == h.hexdigest():
                return
    except OSError:
        pass
    try:
        os.makedirs(cache, exist_ok=True)
        for path in sources[:-1]:
            stem = os.path.splitext(os.path.basename(path))[0]
            for fn in glob.glob(os.path.join(cache, "**", f"{stem}.*.nb[ic]"), recursive=True):
                os.remove(fn)
        with open(stamp, "w") as f:
            f.write(h.hexdigest())
    except OSError:
        pass


_invalidate_stale_numba_cache()
