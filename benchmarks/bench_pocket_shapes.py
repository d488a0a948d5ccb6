"""Cost of one right-hand side (flexbearing.multibody.dynamics.rhs) per pocket shape, and its value
against another checkout: the paper bearing, rigid cage, at its initial state (14,000 rpm, 55 kN /
4 kN), cylindrical, spherical, conical (0.14 rad) and elliptical (23 mm round) pockets.

The best of 7 repetitions of 3000 calls (CPU time per call). The code measured is the one on
PYTHONPATH; for an A/B, run it with another checkout too (its own NUMBA_CACHE_DIR, so no cache is
written into that checkout) and compare the dy/dt files (`--save DIR`):

    PYTHONPATH=. .venv/bin/python benchmarks/bench_pocket_shapes.py --save /tmp/ab/new
    PYTHONPATH=/tmp/old NUMBA_CACHE_DIR=/tmp/nb-old .venv/bin/python benchmarks/bench_pocket_shapes.py \
        --save /tmp/ab/old --shapes cylindrical spherical
"""
import argparse
import time
from pathlib import Path

import numpy as np

SHAPES = {"cylindrical": {}, "spherical": {}, "conical": {"pocket_cone_angle": 0.14},
          "elliptical": {"pocket_circumferential_diameter": 23e-3}}


def rhs_time(shape: str, n: int = 3000, repeats: int = 7):
    from flexbearing.multibody import dynamics as D
    from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
    from flexbearing.multibody.initial import initial_state
    from flexbearing.multibody.model import build_model
    cage = PAPER_BEARING.cage.with_(pocket_shape=shape, **SHAPES[shape])
    m = build_model(PAPER_BEARING.with_(cage=cage), PAPER_OIL)
    w = 14000 * np.pi / 30
    y = initial_state(m, w, 55e3, 4e3)
    dydt, work = np.zeros_like(y), D.new_work(m)
    args = (m.p, m.flags, m.hertz_table, m.traction_table, np.array([[0.0, w]]),
            np.array([[0.0, 55e3, 0.0, -4e3]]), np.zeros((0, 6)), work, m.cage)
    D.rhs(0.0, y, dydt, *args)                       # compile
    best = np.inf
    for _ in range(repeats):
        t0 = time.process_time()
        for _ in range(n):
            D.rhs(0.0, y, dydt, *args)
        best = min(best, (time.process_time() - t0) / n)
    return best, dydt.copy()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--shapes", nargs="+", default=list(SHAPES), choices=list(SHAPES))
    ap.add_argument("--save", help="write dydt_<shape>.npy here")
    a = ap.parse_args()
    for shape in a.shapes:
        t, dydt = rhs_time(shape)
        print(f"{shape:12s} rhs {t * 1e6:7.2f} us per call", flush=True)
        if a.save:
            Path(a.save).mkdir(parents=True, exist_ok=True)
            np.save(Path(a.save) / f"dydt_{shape}.npy", dydt)


if __name__ == "__main__":
    main()
