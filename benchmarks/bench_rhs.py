"""Cost of one right-hand side evaluation (flexbearing.multibody.dynamics.rhs) at a settled state of a scene.

The scene's model (rigid or flexible cage, flexbearing.simulation.run.default_backend) is integrated 2 ms from its
initial state, then `rhs` is evaluated N times in a compiled loop (no Python dispatch per call);
the best of 5 repetitions of CPU time per evaluation is printed. The code measured is the one on
PYTHONPATH (a checkout of another commit for an A/B; alternate the two, the machine's load moves
the numbers by ±10 %).

    PYTHONPATH=. .venv/bin/python benchmarks/bench_rhs.py scenes/paper_steady.toml 2000
"""
import math
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    sys.path.insert(0, os.environ.get("PYTHONPATH", "").split(os.pathsep)[0] or ROOT)
    from numba import njit
    from flexbearing.simulation.scene import load_scene
    from flexbearing.simulation import run as R
    from flexbearing.multibody import dynamics as D, integrator as I
    sc = load_scene(argv[0])
    N = int(argv[1]) if len(argv) > 1 else 2000
    be = R.default_backend(sc)
    model = be.build_model(sc.bearing, sc.oil, dict(sc.model_options))
    sp, ld, imp = sc.speed_table, sc.load_table, sc.impacts
    y = be.initial_state(model, sp[0, 1], ld[0, 1], math.hypot(ld[0, 2], ld[0, 3]), load=tuple(ld[0, 1:4]))
    ws = I.Workspace(model)
    y, t, h, _, _ = I.advance(model, y, 0.0, 2e-3, sp, ld, imp, 1e-6, 1e-7, ws)
    rhs = D.rhs

    @njit
    def loop(n, t, y, dydt, p, flags, htab, ttab, sp, ld, imp, work, cage):
        for i in range(n):
            rhs(t, y, dydt, p, flags, htab, ttab, sp, ld, imp, work, cage)

    dydt = np.zeros_like(y)
    args = (t, y, dydt, model.p, model.flags, model.hertz_table, model.traction_table, sp, ld, imp, ws.work,
            model.cage)
    loop(1, *args)
    best = 1e9
    for rep in range(5):
        c0 = time.process_time()
        loop(N, *args)
        best = min(best, (time.process_time() - c0) / N)
    print(f"{argv[0]}: rhs {best * 1e6:.2f} us per evaluation (best of 5 x {N}), load {os.getloadavg()[0]:.1f}")
    return best


if __name__ == "__main__":
    main()
