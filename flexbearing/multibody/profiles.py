"""Operating spectra as arrays: inner-ring speed and external load on the inner ring versus time.

The dynamics right-hand side calls these at every evaluation, so they are numba-compiled,
allocation-free and branch on plain float arrays (built once by `flexbearing.simulation.scene`).

Speed spectrum: ``speed_table`` float64 (n, 2) of (t [s], omega [rad/s]), times
strictly increasing, piecewise linear between the points and constant outside them:

    omega(t) = omega_0                                         t <= t_0
    omega(t) = omega_k + (omega_{k+1} − omega_k)·(t − t_k)/(t_{k+1} − t_k)   t_k <= t <= t_{k+1}
    omega(t) = omega_{n−1}                                     t >= t_{n−1}

    d omega/dt = (omega_{k+1} − omega_k)/(t_{k+1} − t_k) inside a segment, 0 outside; at a knot
    the slope of the segment to the right is returned (right derivative, so a phase that starts
    at t_k has its own acceleration from t_k on).

Load spectrum: ``load_table`` float64 (n, 4) of (t, Fx, Fy, Fz) [s, N], same interpolation rule,
plus ``impacts`` float64 (m, 6) of (t_start, duration, Fx_amp, Fy_amp, Fz_amp, shape):

    shape 0 (half-sine):    F(t) = F_amp·sin(pi·(t − t0)/T)   for t0 <= t <= t0 + T
    shape 1 (rectangular):  F(t) = F_amp                       for t0 <= t <  t0 + T
    0 elsewhere; impacts add to the table load (paper §4.2: 50 kN, 0.02 s impacts).

Frame: x along the shaft axis, y horizontal, z vertical. Forces act on the inner ring.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

HALF_SINE = 0
RECTANGULAR = 1


@njit(cache=True)
def _segment(t, table):
    """Index k with table[k, 0] <= t < table[k+1, 0]; -1 before the first knot, n-1 after the last."""
    n = table.shape[0]
    if t < table[0, 0]:
        return -1
    if t >= table[n - 1, 0]:
        return n - 1
    lo = 0
    hi = n - 1
    # bisection: table[lo, 0] <= t < table[hi, 0]
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if table[mid, 0] <= t:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True)
def speed_at(t, speed_table):
    """Inner-ring angular speed omega(t) [rad/s], piecewise linear in `speed_table` (module doc)."""
    n = speed_table.shape[0]
    k = _segment(t, speed_table)
    if k < 0:
        return speed_table[0, 1]
    if k >= n - 1:
        return speed_table[n - 1, 1]
    t0 = speed_table[k, 0]
    t1 = speed_table[k + 1, 0]
    w0 = speed_table[k, 1]
    w1 = speed_table[k + 1, 1]
    return w0 + (w1 - w0) * (t - t0) / (t1 - t0)


@njit(cache=True)
def speed_derivative_at(t, speed_table):
    """Inner-ring angular acceleration d omega/dt [rad/s²] (right derivative at knots, 0 outside)."""
    n = speed_table.shape[0]
    k = _segment(t, speed_table)
    if k < 0 or k >= n - 1:
        return 0.0
    return (speed_table[k + 1, 1] - speed_table[k, 1]) / (speed_table[k + 1, 0] - speed_table[k, 0])


@njit(cache=True)
def speed_angle_at(t, speed_table):
    """Inner-ring rotation angle phi(t) = integral of omega from 0 to t [rad] (exact for the
    piecewise-linear omega: trapezoids over whole segments plus the partial one)."""
    n = speed_table.shape[0]
    if t <= 0.0:
        return speed_at(0.0, speed_table) * t
    phi = 0.0
    a = 0.0
    w_a = speed_at(0.0, speed_table)
    for k in range(n):
        tk = speed_table[k, 0]
        if tk <= a:
            continue
        if tk >= t:
            break
        w_k = speed_table[k, 1]
        phi += 0.5 * (w_a + w_k) * (tk - a)
        a = tk
        w_a = w_k
    phi += 0.5 * (w_a + speed_at(t, speed_table)) * (t - a)
    return phi


@njit(cache=True)
def impact_factor(t, t_start, duration, shape):
    """Shape function s(t) of one impact: sin(pi·(t − t0)/T) (half-sine) or 1 (rectangular)
    inside the impact, 0 outside."""
    if t < t_start or t > t_start + duration:
        return 0.0
    if shape == RECTANGULAR:
        if t < t_start + duration:
            return 1.0
        return 0.0
    return math.sin(math.pi * (t - t_start) / duration)


@njit(cache=True)
def load_at(t, load_table, impacts, out3):
    """External force on the inner ring at time t: out3[:] = (Fx, Fy, Fz) [N].

    Table load (piecewise linear, constant outside) plus the sum of the active impacts
    (module doc). Writes into `out3` (length-3 float64), allocates nothing.
    """
    n = load_table.shape[0]
    k = _segment(t, load_table)
    if k < 0:
        for j in range(3):
            out3[j] = load_table[0, j + 1]
    elif k >= n - 1:
        for j in range(3):
            out3[j] = load_table[n - 1, j + 1]
    else:
        t0 = load_table[k, 0]
        t1 = load_table[k + 1, 0]
        s = (t - t0) / (t1 - t0)
        for j in range(3):
            out3[j] = load_table[k, j + 1] + (load_table[k + 1, j + 1] - load_table[k, j + 1]) * s
    for i in range(impacts.shape[0]):
        f = impact_factor(t, impacts[i, 0], impacts[i, 1], int(impacts[i, 5]))
        if f != 0.0:
            for j in range(3):
                out3[j] += f * impacts[i, 2 + j]


def breakpoints(speed_table: np.ndarray, load_table: np.ndarray, impacts: np.ndarray) -> np.ndarray:
    """Sorted unique times where a spectrum has a kink or a jump (table knots, impact edges).

    The run loop stops the integrator at these so that no step straddles a discontinuity.
    """
    times = [speed_table[:, 0], load_table[:, 0]]
    if impacts.shape[0]:
        times += [impacts[:, 0], impacts[:, 0] + impacts[:, 1]]
    return np.unique(np.concatenate(times))
