"""Warm and cold starts of the quasi-static solver over the test suite's bearings and a grid of speeds
and loads (issue 42): converged?, ring Newton iterations, |u_warm − u_cold| against the bound from the
solver's residuals and the tangent stiffness (|K⁻¹|₂·F·sqrt(n)·(r_warm + r_cold)), the Jacobian's
condition. Run it under each numerical environment to compare the iteration counts:

    python benchmarks/quasi_static_roots.py                                  # the machine's BLAS
    LD_LIBRARY_PATH=/usr/lib/x86_64-linux-gnu/blas:/usr/lib/x86_64-linux-gnu/lapack \\
        python benchmarks/quasi_static_roots.py                              # Debian's reference BLAS
    .ci/on-other-isa python benchmarks/quasi_static_roots.py                 # generic x86-64
"""
import math
import time

import numpy as np

import flexbearing  # noqa: F401  (one BLAS thread)
from flexbearing.common.blas import blas_info
from flexbearing.multibody import quasi_static as qs
from flexbearing.multibody.bearing import PAPER_BEARING
from flexbearing.studies.validation.slip_rate import design_clearance

DW, DM, Z, F, A0 = 22.23e-3, 125.3e-3, 16, 0.5232, math.radians(40.0)


def main():
    info = blas_info()
    print(f"BLAS: {info.name} {info.core or ''}")
    b218 = qs.angular_contact_grooves(DM, DW, Z, F, F, A0)
    paper0 = qs.grooves_from_bearing(PAPER_BEARING.with_(radial_clearance=0.0))
    design = qs.grooves_from_bearing(PAPER_BEARING.with_(radial_clearance=design_clearance(PAPER_BEARING)))
    cases = [("b218", b218, 4450.0, 2000.0, True), ("paper Pd=0", paper0, 55e3, 4e3, False),
             ("paper design Pd", design, 55e3, 4e3, False)]
    worst, t0 = 0.0, time.time()
    tot = {"cold it": 0, "warm it": 0, "cold cpu": 0.0, "warm cpu": 0.0}
    print("bearing          rpm      Fr  cold it  warm it   |du| m     bound m   ratio  cond  cold ms  warm ms")
    for name, g, fa, fr, fix_tilt in cases:
        free = [0, 1, 2] if fix_tilt else [0, 1, 2, 3, 4]
        previous = qs.solve_quasi_static(g, 0.0, fx=fa, fix_tilt=fix_tilt)
        for rpm in (0.0, 6000.0, 10000.0, 14000.0):
            for fz in (0.0, -fr):
                w = rpm * math.pi / 30
                c0 = time.process_time()
                cold = qs.solve_quasi_static(g, w, fx=fa, fz=fz, fix_tilt=fix_tilt)
                c1 = time.process_time()
                warm = qs.solve_quasi_static(g, w, fx=fa, fz=fz, fix_tilt=fix_tilt, initial=previous)
                c2 = time.process_time()
                tot["cold it"] += cold.iterations
                tot["warm it"] += warm.iterations
                tot["cold cpu"] += c1 - c0
                tot["warm cpu"] += c2 - c1
                k = qs.bearing_stiffness(g, cold)[np.ix_(free, free)]
                bound = np.linalg.norm(np.linalg.inv(k), 2) * max(fa, abs(fz)) * math.sqrt(len(free)) * \
                    (warm.residual_ring + cold.residual_ring)
                du = float(np.max(np.abs(warm.ring_displacement - cold.ring_displacement)[free]))
                worst = max(worst, du / bound)
                print(f"{name:15s} {rpm:6.0f} {abs(fz):7.0f} {cold.iterations:8d} {warm.iterations:8d} {du:10.2e} "
                      f"{bound:10.2e} {du / bound:6.2f} {cold.jacobian_condition:6.1f} {1e3 * (c1 - c0):8.1f} "
                      f"{1e3 * (c2 - c1):8.1f}")
                previous = cold
    n = 8 * len(cases)
    print(f"largest |du|/bound {worst:.2f}; {time.time() - t0:.1f} s; iterations cold {tot['cold it']} "
          f"warm {tot['warm it']}; CPU per solve cold {1e3 * tot['cold cpu'] / n:.1f} ms, "
          f"warm {1e3 * tot['warm cpu'] / n:.1f} ms (after the first compiled call)")


if __name__ == "__main__":
    main()
