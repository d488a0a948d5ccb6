"""Fatigue damage of a stress history: rainflow cycles, mean-stress correction, S–N, Palmgren–Miner.

A scalar stress history x_0 .. x_{T-1} (Pa; a signed equivalent or the normal stress on a plane,
flexbearing.analysis.stress_equivalent) is counted by the rainflow method of ASTM E1049-85 (2017),
§5.4.4, with the `rainflow` package (3.2.0: that section's three-point algorithm, exact ranges, no
binning, half cycles and the indices where each cycle starts and ends). A history that repeats
(the duty cycle: the run's block again and again) is first rotated to start and end at its
largest |x| (E1049 §5.4.4 note; Dowling 2013 §9.9.2): the residue then closes and every cycle of
the repeated block is counted once, including the one across the block's seam.

Each cycle i (range dS_i, mean S_m,i, count c_i = 1 or 1/2) has the amplitude S_a,i = dS_i / 2, the
fully reversed amplitude S_ar,i of the mean-stress correction (flexbearing.analysis.mean_stress) and
the life N_i of the S–N curve (flexbearing.analysis.sn_curves). Palmgren–Miner (Palmgren 1924,
Miner 1945):

    D_block = sum_i c_i / N_i,      damage rate d = D_block * blocks_per_hour,   life = 1 / d

Safety factor: the factor lambda on the whole stress history (every cycle's amplitude and mean)
at which the damage over the target life reaches 1, D_block(lambda) * blocks = 1. Without a mean
correction or with SWT the damage is homogeneous, D_block(lambda) = lambda^k D_block(1) with the
S–N slope k = -1/b, so lambda = (blocks D_block(1))^(-1/k); with Goodman or Gerber it is found by
bisection on log(lambda) (D_block grows monotonically with lambda). The damage and the safety
factor are compiled loops over the cycles (numba, allocation-free): the report evaluates them at
thousands of nodes.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit
import rainflow

from flexbearing.analysis.mean_stress import (CORRECTIONS, check_correction, equivalent_amplitude,
                                              equivalent_amplitude_of)
from flexbearing.analysis.sn_curves import damage_per_cycle


class Cycles(NamedTuple):
    """Rainflow cycles of a history: range (Pa), mean (Pa), count (1 or 0.5), start and end
    (sample indices of the original history where the cycle's two reversals are)."""
    range: np.ndarray
    mean: np.ndarray
    count: np.ndarray
    start: np.ndarray
    end: np.ndarray


def rainflow_cycles(history, repeated: bool = False) -> Cycles:
    """ASTM E1049 §5.4.4 rainflow cycles of the history (module doc); repeated: the history is one
    block of a repeated loading (rotated to begin and end at its largest |value| first)."""
    x = np.asarray(history, dtype=np.float64)
    if x.size < 2:
        return Cycles(*(np.zeros(0) for _ in range(3)), np.zeros(0, np.int64), np.zeros(0, np.int64))
    index = np.arange(x.size)
    if repeated:
        k = int(np.argmax(np.abs(x)))
        index = np.r_[index[k:], index[:k + 1]]
        x = x[index]
    # peak-valley filter first (the package's own reversal filter, in numpy): same cycles, less Python
    d = np.diff(x)
    nz = np.flatnonzero(d != 0.0)
    if nz.size == 0:
        return Cycles(*(np.zeros(0) for _ in range(3)), np.zeros(0, np.int64), np.zeros(0, np.int64))
    keep = np.r_[0, nz[1:][d[nz[1:]] * d[nz[:-1]] < 0.0], x.size - 1]
    cyc = np.array(list(rainflow.extract_cycles(x[keep])), dtype=np.float64).reshape(-1, 5)
    return Cycles(cyc[:, 0], cyc[:, 1], cyc[:, 2], index[keep[cyc[:, 3].astype(np.int64)]],
                  index[keep[cyc[:, 4].astype(np.int64)]])


def cycle_damage(cycles: Cycles, curve, correction: str, scale: float = 1.0) -> np.ndarray:
    """c_i / N_i of every cycle (module doc) with the history scaled by `scale`."""
    s_ar = equivalent_amplitude(0.5 * scale * cycles.range, scale * cycles.mean, correction,
                                curve.ultimate_strength)
    with np.errstate(divide="ignore"):
        return cycles.count / curve.cycles_to_failure(s_ar)


@njit(cache=True)
def _block_damage(rng, mean, count, scale, code, u, coef, slope):
    d = 0.0
    for i in range(rng.shape[0]):
        d += count[i] * damage_per_cycle(equivalent_amplitude_of(0.5 * scale * rng[i], scale * mean[i], code, u),
                                         coef, slope)
    return d


def _args(cycles: Cycles, curve, correction: str):
    return (cycles.range, cycles.mean, cycles.count, CORRECTIONS.index(check_correction(correction)),
            curve.ultimate_strength, curve.fatigue_strength_coefficient, curve.slope)


def block_damage(cycles: Cycles, curve, correction: str, scale: float = 1.0) -> float:
    """Miner sum of one block (compiled, allocation-free)."""
    r, m, c, code, u, coef, k = _args(cycles, curve, correction)
    return float(_block_damage(r, m, c, float(scale), code, u, coef, k))


@njit(cache=True)
def _safety_factor(rng, mean, count, code, u, coef, slope, blocks):
    """lambda with blocks * D_block(lambda) = 1 by bisection on log(lambda) (D grows with lambda);
    the homogeneous estimate starts the bracket. Relative accuracy 1e-12."""
    d1 = _block_damage(rng, mean, count, 1.0, code, u, coef, slope)
    if not d1 > 0.0:
        return math.inf
    x0 = -math.log(blocks * d1) / slope
    if code >= 2:                       # swt, none: homogeneous of degree k
        return math.exp(x0)
    target = -math.log(blocks)
    lo, hi = x0 - 0.5, x0 + 0.5
    while math.log(_block_damage(rng, mean, count, math.exp(lo), code, u, coef, slope)) > target:
        hi = lo
        lo -= 1.0
    while True:
        d = _block_damage(rng, mean, count, math.exp(hi), code, u, coef, slope)
        if d > 0.0 and math.log(d) >= target:
            break
        lo = hi
        hi += 1.0
    while hi - lo > 1e-12:
        mid = 0.5 * (lo + hi)
        d = _block_damage(rng, mean, count, math.exp(mid), code, u, coef, slope)
        if d > 0.0 and math.log(d) >= target:
            hi = mid
        else:
            lo = mid
    return math.exp(0.5 * (lo + hi))


def safety_factor(cycles: Cycles, curve, correction: str, blocks: float) -> float:
    """lambda with blocks * D_block(lambda) = 1 (module doc); inf for a history without damage."""
    r, m, c, code, u, coef, k = _args(cycles, curve, correction)
    return float(_safety_factor(r, m, c, code, u, coef, k, float(blocks)))
