"""Cost per call of the contact/lubrication models inside a compiled loop (work–precision).

Run: .venv/bin/python benchmarks/bench_contact_models.py
Prints ns per call and, for Hertz, the max relative error against the scipy reference
(hertz_exact) over Ry/Rx = 1..100.
"""
import time

import numpy as np
from numba import njit

from flexbearing.multibody.film import film_thickness
from flexbearing.multibody.hertz import hertz_exact, hertz_point_contact, hertz_point_contact_hb
from flexbearing.multibody.traction import sliced_traction, traction_coefficients

RHO = np.geomspace(1.0, 100.0, 64)


@njit(cache=True)
def loop_hertz(rho, n, hb):
    s = 0.0
    for i in range(n):
        r = rho[i % rho.size]
        if hb:
            a, b, p, d = hertz_point_contact_hb(0.01, 0.01 * r, 2.3e11, 1000.0 + i % 7)
        else:
            a, b, p, d = hertz_point_contact(0.01, 0.01 * r, 2.3e11, 1000.0 + i % 7)
        s += d
    return s


@njit(cache=True)
def loop_traction(n, n_slices):
    s = 0.0
    for i in range(n):
        A, B, C, D = traction_coefficients(3000.0 + i % 5, 43.1, 0.0097, 2.3e11, 0.055, 373.0, 0.0966)
        tx, ty, mz = sliced_traction(3000.0, 2.6e-3, 43.1, 0.5 + 1e-3 * (i % 3), -400.0, 0.0, 0.0,
                                     A, B, C, D, n_slices, False)
        s += tx
    return s


@njit(cache=True)
def loop_film(n):
    s = 0.0
    for i in range(n):
        h1, h2 = film_thickness(0.0097, 0.286, 2.3e11, 3000.0 + i % 5, 43.1, 0.055, 1.85e-8)
        s += h1
    return s


def timed(fn, args, n):
    fn(*args)   # compile / warm
    best = 1e9
    for _ in range(3):
        t = time.perf_counter()
        fn(*args)
        best = min(best, time.perf_counter() - t)
    return best / n * 1e9


def main():
    n = 200_000
    err_exact, err_hb = 0.0, 0.0
    for r in RHO:
        ref = hertz_exact(0.01, 0.01 * r, 2.3e11, 1000.0)
        for name, v in zip(("a", "b", "p0", "delta"), hertz_point_contact(0.01, 0.01 * r, 2.3e11, 1000.0)):
            err_exact = max(err_exact, abs(v / ref[name] - 1))
        for name, v in zip(("a", "b", "p0", "delta"), hertz_point_contact_hb(0.01, 0.01 * r, 2.3e11, 1000.0)):
            err_hb = max(err_hb, abs(v / ref[name] - 1))
    print(f"hertz_point_contact (Newton + A&S): {timed(loop_hertz, (RHO, n, False), n):7.1f} ns/call, "
          f"max rel. error {err_exact:.1e}")
    print(f"hertz_point_contact_hb            : {timed(loop_hertz, (RHO, n, True), n):7.1f} ns/call, "
          f"max rel. error {err_hb:.1e}")
    for ns in (1, 10, 20, 40):
        print(f"traction_coefficients + sliced_traction n={ns:2d}: {timed(loop_traction, (n, ns), n):7.1f} ns/call")
    print(f"film_thickness                    : {timed(loop_film, (n,), n):7.1f} ns/call")


if __name__ == "__main__":
    main()
