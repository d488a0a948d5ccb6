"""Has a series settled? The start-up transient and the drift of a signal, against its own scatter.

The statistics behind a run's settling verdict (flexbearing.analysis.settling, per phase of a run) and
behind the steady solver's settled mean of the dynamics (flexbearing.multibody.steady_mean): one
method, written once.

A run starts from a quasi-static (or steady) initial state, not from the state the dynamics
settle to: the cage speed, the slip and the cage forces approach their running level over a
start-up transient whose length depends on the bearing, the oil and the load (milliseconds to
seconds). Means, percentiles and the fatigue duty cycle of a window that holds part of it are
biased. Two tests decide it, per uniform-speed phase and per signal:

1. Start-up transient: MSER-5 (White, K. P., "An effective truncation heuristic for bias
   reduction in simulation output", Simulation 69(6):323–334, 1997; White, Cobb & Spratt,
   "A comparison of five steady-state truncation heuristics for simulation", Proc. Winter
   Simulation Conference 2000, 755–760). The window's n samples are averaged in k = n // 5
   batches Z_1..Z_k of 5; the truncation d* (in batches) minimises the marginal standard error

       MSER(d) = 1/(k − d)² · sum_{j > d} (Z_j − Zbar_d)²,    Zbar_d = mean of Z_{d+1..k},
       d = 0 .. k/2 − 1

   (the rule is not applied beyond half the window: there it would pick the last few batches,
   whose scatter is small because they are few). A minimum in the last admissible batches
   (d* >= k/2 − 1) means that the transient runs past half of the window: no settled part.
   For a transient x(t) = A·exp(−t/tau) on noise of batch-mean standard deviation sigma_b, the
   minimum lies where A·exp(−t/tau) ≈ sigma_b (dMSER/dd = 0 with the remaining bias's sum small
   against the variance): t* ≈ tau·ln(A/sigma_b) (tests/test_settling.py checks it).

2. Drift after the transient (from the latest transient end over the window's signals: the
   bearing is one system): a linear trend test on batch means (the batch-means method: Law,
   *Simulation Modeling and Analysis*, 5th ed., 2015, §9.5.3; Schmeiser, "Batch size effects in
   the analysis of simulation output", Operations Research 30(3):556–568, 1982, 10–30 batches).
   The samples after the truncation are cut into b = min(20, n/5) batches (at least 8, each of
   at least 5 samples); the least-squares slope beta of the batch means Y_i against their mid
   times c_i and its standard error

       beta = sum (c_i − cbar)(Y_i − Ybar) / Sxx,   SE = sqrt( sum r_i² / (b − 2) / Sxx ),   Sxx = sum (c_i − cbar)²

   (r_i the fit's residuals) give T = beta / SE, Student-t with b − 2 degrees of freedom when the
   batch means are independent and normal with a constant mean. The test is made twice: over
   the whole part after the transient, and over its second half (a drift that starts late, e.g.
   the cage changing its motion near the end, is diluted in the whole part's slope). The signal
   drifts when either |T| > t_{1 − alpha/(2m), b − 2}, m = 2 × the number of signals tested in
   the window (Bonferroni: the window's false-alarm rate is at most ALPHA = 1 %), and the drift
   over the tested part,
   |beta|·T_w, exceeds the signal's floor DRIFT_FLOOR (a drift below it does not change a reported
   digit: 1e-4 of the mean cage speed, 0.01 slip points, 1e-3 of the mean force; without it a
   run at a fixed point would be "drifting" at the integrator's noise).

The window is settled when no signal drifts and the transient ends in its first half. The
batch means are independent only when a batch is long against the signal's correlation time:
a cage whirl or a load cycle slower than about a twentieth of the window makes the test see
drift where there is a slow oscillation (it then says "not settled": run longer).

Signals (each when recorded): cage speed (rad/s), cage slip rate (1), pocket force (mean over the
balls of |F|, N), guiding force (land film force magnitude, N), the flexible cage's largest von
Mises stress (Pa). Windows: the uniform-speed phases
of the speed profile (an acceleration or deceleration is a transient by design: not tested), and
the whole run when it is one such phase.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

MSER_BATCH = 5             # samples per batch of MSER-5 (White 1997)
N_BATCHES = 20             # batches of the trend test (Schmeiser 1982: 10-30)
MIN_BATCHES = 8            # fewer batches: too short to decide
ALPHA = 0.01               # false-alarm rate of a window (Bonferroni over its signals)

# name: (label, unit shown, scale SI -> shown, floor kind, floor value) -- module docstring
SIGNALS = {
    "cage_speed": ("cage speed", "rpm", 60.0 / (2.0 * math.pi), "relative", 1e-4),
    "slip_rate": ("slip rate", "points", 100.0, "absolute", 1e-4),
    "pocket_force": ("pocket force", "N", 1.0, "relative", 1e-3),
    "guiding_force": ("guiding force", "N", 1.0, "relative", 1e-3),
    "von_mises_max": ("cage's max. von Mises stress", "MPa", 1e-6, "relative", 1e-3),
}


class Mser(NamedTuple):
    """MSER-5 on a series (module docstring): `truncation` samples to leave out (a multiple of
    the batch size), whether the minimum lies in the admissible first half (`in_first_half`:
    False means the transient runs past half of the series), the batches k."""
    truncation: int
    in_first_half: bool
    n_batches: int


class Trend(NamedTuple):
    """The batch-means trend test of a series (module docstring): slope (unit/s) and its standard
    error, t = slope/SE, degrees of freedom, batches, the standard deviation of the batch means
    about the fit (the scatter), the duration tested (s)."""
    slope: float
    standard_error: float
    t: float
    dof: int
    n_batches: int
    scatter: float
    duration: float


def mser(x, batch: int = MSER_BATCH) -> Mser:
    """MSER-m truncation of the series x (module docstring, step 1); NaNs are not allowed."""
    x = np.asarray(x, dtype=float)
    k = len(x) // batch
    if k < 4:
        return Mser(0, True, k)
    z = x[:k * batch].reshape(k, batch).mean(axis=1)
    # sums over the tail j >= d, for every d, by reversed cumulative sums
    s1 = np.cumsum(z[::-1])[::-1]
    s2 = np.cumsum((z * z)[::-1])[::-1]
    m = k - np.arange(k)
    half = k // 2
    ss = s2[:half] - s1[:half] ** 2 / m[:half]               # sum (Z_j - Zbar_d)^2, j >= d
    stat = np.maximum(ss, 0.0) / m[:half] ** 2
    d = int(np.argmin(stat))
    return Mser(d * batch, d < half - 1, k)


def trend(t, x, n_batches: int = N_BATCHES) -> Trend | None:
    """The batch-means trend test of x(t) (module docstring, step 2); None when the series holds
    fewer than MIN_BATCHES batches of MSER_BATCH samples."""
    t, x = np.asarray(t, dtype=float), np.asarray(x, dtype=float)
    b = min(n_batches, len(x) // MSER_BATCH)
    if b < MIN_BATCHES:
        return None
    m = len(x) // b
    sl = slice(len(x) - b * m, len(x))             # whole batches, the last samples kept
    y = x[sl].reshape(b, m).mean(axis=1)
    c = t[sl].reshape(b, m).mean(axis=1)
    cc = c - c.mean()
    sxx = float(cc @ cc)
    beta = float(cc @ (y - y.mean())) / sxx
    r = y - y.mean() - beta * cc
    s2 = float(r @ r) / (b - 2)
    se = math.sqrt(s2 / sxx)
    tt = beta / se if se > 0.0 else (0.0 if beta == 0.0 else math.copysign(math.inf, beta))
    dt = (t[-1] - t[0]) / max(len(t) - 1, 1)
    return Trend(beta, se, tt, b - 2, b, math.sqrt(s2), float(t[sl][-1] - t[sl][0] + dt))


def t_critical(dof: int, n_signals: int, alpha: float = ALPHA) -> float:
    """Two-sided Student-t limit at the window's false-alarm rate alpha, Bonferroni over n_signals."""
    from scipy.stats import t as student_t          # scipy: only when a report is made
    return float(student_t.ppf(1.0 - alpha / (2.0 * max(n_signals, 1)), dof))


def drift_floor(name: str, x) -> float:
    """The smallest drift over a window that counts (SI; module docstring)."""
    kind, value = SIGNALS[name][3], SIGNALS[name][4]
    return value * abs(float(np.mean(x))) if kind == "relative" else value


def signal_settling(name: str, t, x, n_signals: int = 1, alpha: float = ALPHA, t_from: float | None = None) -> dict:
    """The verdict on one signal over a window (module docstring): {signal, settled (True/False/
    None: too short to decide), transient_end (s: the first sample after the MSER-5
    truncation), transient_past_half, slope (SI/s), standard_error, t, t_limit, drift (slope ×
    tested duration, SI), floor, scatter (SI), n_batches, mean_after (SI: the mean over the tested
    part, after the start-up), reason}. The drift is tested from the
    signal's own transient end, or from t_from where that is later (the window's common one)."""
    t, x = np.asarray(t, dtype=float), np.asarray(x, dtype=float)
    ok = np.isfinite(x)
    t, x = t[ok], x[ok]
    out = {"signal": name, "settled": None, "transient_end": None, "transient_past_half": None,
           "slope": None, "standard_error": None, "t": None, "t_limit": None, "drift": None,
           "floor": None, "scatter": None, "n_batches": 0, "mean_after": None, "reason": ""}
    if len(x) < MIN_BATCHES * MSER_BATCH:
        out["reason"] = f"{len(x)} samples: too few to decide (at least {MIN_BATCHES * MSER_BATCH})"
        return out
    ms = mser(x)
    out["transient_end"] = float(t[ms.truncation])
    out["transient_past_half"] = not ms.in_first_half
    cut = ms.truncation
    if t_from is not None:
        cut = max(cut, int(np.searchsorted(t, t_from - 1e-9 * max(abs(t_from), 1.0))))
    tt, xx = t[cut:], x[cut:]
    half = len(xx) // 2
    tests = [("", trend(tt, xx)), (" in its second half", trend(tt[half:], xx[half:]))]
    tests = [(w, tr) for w, tr in tests if tr is not None]
    if not tests:
        out["reason"] = "too few samples after the start-up transient to decide"
        return out
    label, unit, scale = SIGNALS[name][:3]
    floor = drift_floor(name, xx)
    verdicts = []
    for where, tr in tests:
        lim = t_critical(tr.dof, 2 * n_signals, alpha)         # two tests per signal (Bonferroni)
        drift = tr.slope * tr.duration
        verdicts.append((abs(tr.t) > lim and abs(drift) > floor, abs(tr.t) / lim, where, tr, lim, drift))
    # the report's numbers: the failing test, else the whole part's
    drifts, _, where, tr, lim, drift = max(verdicts, key=lambda v: (v[0], v[1])) if any(v[0] for v in verdicts) \
        else verdicts[0]
    out.update(slope=tr.slope, standard_error=tr.standard_error, t=tr.t if math.isfinite(tr.t) else None,
               t_limit=lim, drift=drift, floor=floor, scatter=tr.scatter, n_batches=tr.n_batches,
               mean_after=float(np.mean(xx)))
    if not ms.in_first_half:
        out["settled"] = False
        out["reason"] = f"{label}: start-up transient past half of the window (MSER-5)"
    elif drifts:
        out["settled"] = False
        out["reason"] = (f"{label} drifts {drift * scale:+.3g} {unit} over {tr.duration:.3g} s{where} "
                         f"(|t| = {abs(tr.t):.2f} > {lim:.2f})")
    else:
        out["settled"] = True
        out["reason"] = f"{label} settled (|t| <= {lim:.2f} or drift below {floor * scale:.2g} {unit})"
    return out
