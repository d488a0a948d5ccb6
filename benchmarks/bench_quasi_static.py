"""Work–precision of the quasi-static solver (flexbearing.multibody.quasi_static) on the paper's steady case.

14,000 rpm, Fa = 55 kN (+X), Fr = 4 kN (−Z), paper bearing (Pd = 0, assumed alphaD = 30°), free tilts.
For each ring tolerance: wall time and the error of the maximum outer/inner contact loads and
contact angles against a tol = 1e-12 solution. Then the bearing stiffness (flexbearing.multibody.quasi_static.
bearing_stiffness, kinematics updated) against its difference step: wall time and the error of
the diagonal against a Richardson extrapolation of steps 1e-7/5e-8 m (1e-6/5e-7 rad). Also prints
the paper-case table (MPa, degrees).

    .venv/bin/python benchmarks/bench_quasi_static.py [--quiet]
"""
import math
import sys
import time

import numpy as np

from flexbearing.multibody import quasi_static as qs
from flexbearing.multibody.bearing import PAPER_BEARING


def run(tol, control="outer", **kw):
    g = qs.grooves_from_bearing(PAPER_BEARING)
    t = time.perf_counter()
    r = qs.solve_quasi_static(g, 14000 * math.pi / 30, fx=55000.0, fz=-4000.0, tol=tol, control=control, **kw)
    return r, time.perf_counter() - t


def main():
    run(1e-6)                                   # compile / warm the numba cache
    ref, _ = run(1e-12)
    print("tol      time_s   err_Qmax_rel   err_alpha_rad")
    for tol in (1e-3, 1e-4, 1e-6, 1e-8, 1e-10):
        r, dt = run(tol)
        eq = np.max(np.abs(r.load - ref.load)) / ref.load.max()
        ea = np.max(np.abs(r.contact_angle - ref.contact_angle))
        print(f"{tol:7.0e}  {dt:7.3f}  {eq:12.2e}  {ea:12.2e}")
    ref_r, _ = run(1e-12, control="jones")
    g = qs.grooves_from_bearing(PAPER_BEARING)
    k1 = qs.bearing_stiffness(g, ref_r, step=(1e-7, 1e-6))
    k2 = qs.bearing_stiffness(g, ref_r, step=(5e-8, 5e-7))
    k_ref = np.diag((4.0 * k2 - k1) / 3.0)
    print("\nstiffness step_m   step_rad  time_s   max_rel_err_diag")
    for hs in (1e-6, 1e-7, 1e-8, 1e-9, 1e-10):
        t = time.perf_counter()
        k = qs.bearing_stiffness(g, ref_r, step=(hs, 10 * hs))
        dt = time.perf_counter() - t
        print(f"          {hs:7.0e}  {10 * hs:7.0e}  {dt:6.3f}  {np.max(np.abs(np.diag(k) / k_ref - 1)):12.2e}")
    sweep()
    if "--quiet" not in sys.argv:
        for label, kw in (("outer-race control", {}), ("inner-race control", {"control": "inner"}),
                          ("no gyroscopic moment", {"gyroscopic": False}),
                          ("zero speed", None)):
            if kw is None:
                g = qs.grooves_from_bearing(PAPER_BEARING)
                r = qs.solve_quasi_static(g, 0.0, fx=55000.0, fz=-4000.0)
            else:
                r, _ = run(1e-10, **kw)
            print(f"\n== paper steady case, {label} ==")
            print(r.summary())


def sweep():
    """The profile of scenes/paper_unsteady_rigid.toml at 61 instants (flexbearing.simulation.quasi_static_scene.sweep_scene): each
    solve warm-started from the previous one, against cold solves; the largest difference of the
    contact loads (relative to the largest load) between the two."""
    from flexbearing.simulation.scene import load_scene
    from flexbearing.simulation.quasi_static_scene import solve_scene, sweep_scene
    scene = load_scene("scenes/paper_unsteady_rigid.toml")
    times = np.linspace(0.0, 0.6, 61)
    t = time.perf_counter()
    rows = sweep_scene(scene, times)
    warm = time.perf_counter() - t
    t = time.perf_counter()
    cold = [solve_scene(scene, float(x))[0] for x in times]
    cold_s = time.perf_counter() - t
    diff = max(np.max(np.abs(r["max_load"] - c.load.max(axis=0))) / c.load.max() for r, c in zip(rows, cold))
    print(f"\nprofile sweep, paper_unsteady_rigid, 61 instants: warm-started {warm:.3f} s, cold {cold_s:.3f} s, "
          f"max load difference {diff:.1e}")


if __name__ == "__main__":
    main()
