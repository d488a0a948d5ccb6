"""Has the run settled? The start-up transient and the drift of a phase, against the signal's own scatter.

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


def settling_signals(outputs) -> dict[str, np.ndarray]:
    """The tested signals (module docstring), (n,) SI arrays, from a mapping of recorded outputs
    (an h5py group or a dict); absent ones left out."""
    def get(name):
        return np.asarray(outputs[name][...], dtype=np.float64) if name in outputs else None
    out = {}
    cs = get("cage_speed")
    if cs is not None:
        out["cage_speed"] = cs.reshape(len(cs), -1)[:, 0]
    slip = get("slip_rate")
    if slip is not None:
        out["slip_rate"] = slip.reshape(len(slip), -1)[:, 0]
    pf = get("pocket_force")
    if pf is not None:
        out["pocket_force"] = np.abs(pf.reshape(pf.shape[0], -1)).mean(axis=1)
    land = get("cage_land_force_magnitude")
    if land is None and "cage_land_force" in outputs:
        lf = get("cage_land_force")
        land = np.hypot(lf[:, 0], lf[:, 1])
    if land is not None:
        out["guiding_force"] = land.reshape(-1)
    vm = get("von_mises_max")
    if vm is not None:
        out["von_mises_max"] = vm.reshape(-1)
    return out


def window_settling(t, signals: dict, mask, alpha: float = ALPHA) -> dict:
    """The window's verdict (module docstring): {settled (True/False/None), verdict ("settled",
    "not settled", "undecided"), transient_end (s, the latest over the signals), signals (name ->
    signal_settling), reason (the drifting signals, or why undecided), method}."""
    idx = np.flatnonzero(mask)
    tw = np.asarray(t)[idx]
    names = [n for n in SIGNALS if n in signals]
    # the bearing is one system: its running state starts where the last signal's start-up ends
    # (MSER-5 of each signal in its first half); every signal's drift is tested from there
    ends = []
    for n in names:
        x = np.asarray(signals[n])[idx]
        ok = np.isfinite(x)
        if ok.sum() >= MIN_BATCHES * MSER_BATCH:
            ms = mser(x[ok])
            if ms.in_first_half:
                ends.append(float(tw[ok][ms.truncation]))
    t_from = max(ends) if ends else None
    per = {n: signal_settling(n, tw, np.asarray(signals[n])[idx], len(names), alpha, t_from) for n in names}
    verdicts = [v["settled"] for v in per.values()]
    if not per:
        settled, reason = None, "no cage speed, slip or cage force recorded"
    elif any(v is False for v in verdicts):
        settled = False
        reason = "; ".join(v["reason"] for v in per.values() if v["settled"] is False)
    elif all(v is True for v in verdicts):
        settled, reason = True, ""
    else:
        settled = None
        reason = "; ".join(v["reason"] for v in per.values() if v["settled"] is None)
    ends = [v["transient_end"] for v in per.values() if v["transient_end"] is not None]
    return {"settled": settled, "verdict": {True: "settled", False: "not settled", None: "undecided"}[settled],
            "transient_end": max(ends) if ends else None, "signals": per, "reason": reason,
            "method": METHOD}


METHOD = (f"MSER-5 start-up truncation (White 1997) and a batch-means linear trend test "
          f"({N_BATCHES} batches, Student-t, false-alarm rate {ALPHA:g} per window), flexbearing.analysis.settling")


def tested(row: dict, n_phases: int) -> bool:
    """Whether a report window is tested: a uniform-speed phase, or the whole run of a run that is
    one such phase (module docstring)."""
    return row.get("kind") == "uniform speed" or (row.get("kind") == "run" and n_phases == 1)


def attach_settling(rows: list[dict], masks: list, t, signals: dict, n_phases: int) -> list[dict]:
    """rows (flexbearing.analysis.windows.phase_rows, with their sample masks) each given
    "settling": window_settling, or None where the window is not tested (`tested`)."""
    for row, mask in zip(rows, masks):
        row["settling"] = window_settling(t, signals, mask) if tested(row, n_phases) else None
    return rows


def startup_end(t, signals: dict, t_stop: float | None = None) -> dict:
    """The start-up transient of a run (the fatigue duty cycle's default cut): MSER-5 on each
    signal over [t_0, t_stop] (the first phase; the whole run without t_stop), the latest
    truncation over the signals, and the trend test after it. window_settling's dict."""
    t = np.asarray(t)
    mask = np.ones(len(t), bool) if t_stop is None else t <= t_stop + 1e-9 * max(abs(t_stop), 1.0)
    return window_settling(t, signals, mask)


def run_startup(run, until: float | None = None) -> dict:
    """`startup_end` of a results file (or an open flexbearing.simulation.results.Run) over its
    first speed phase (the whole run without a scene), samples after `until` left out; with
    t_first, t_last (s) the window tested."""
    from flexbearing.analysis.windows import speed_phases
    from flexbearing.simulation.results import opened
    with opened(run) as r:
        t = np.asarray(r.t, dtype=float)
        signals = settling_signals(r.outputs)
        stop = speed_phases(r.scene)[0]["t_end"] if r.scene is not None else None
    if until is not None:
        stop = until if stop is None else min(stop, until)
    out = startup_end(t, signals, stop)
    out["t_first"] = float(t[0]) if len(t) else None
    out["t_last"] = float(t[t <= stop + 1e-9][-1]) if stop is not None and len(t) else (float(t[-1]) if len(t) else None)
    return out


def unsettled(row: dict) -> bool:
    """A report window (a row with "settling") that was tested and did not settle."""
    st = row.get("settling")
    return bool(st) and st.get("settled") is False


MARK = "†"
MARK_NOTE = (f"{MARK} not settled in this window: the cage speed, slip or a cage force still drifts against its own "
             "scatter, or its start-up transient fills more than half of it (flexbearing.analysis.settling); the "
             "mean and percentile are those of a transient, not of the running state: run longer.")


def summary_text(rows: list[dict]) -> str | None:
    """The summary block's line on the run's settling (the tested phases' verdicts), None when no
    window was tested."""
    tested_rows = [r for r in rows if r.get("settling") and r.get("kind") != "run"]
    if not tested_rows:
        tested_rows = [r for r in rows if r.get("settling")]
    if not tested_rows:
        return None
    parts = []
    for r in tested_rows:
        st = r["settling"]
        where = f"{r['t_start']:g}–{r['t_end']:g} s {r.get('label', '')}".strip()
        end = st.get("transient_end")
        if st["settled"] is True:
            text = f"{where}: **settled**"
            if end is not None and end > r["t_start"] + 1e-12:
                text += (f"; start-up transient to t = {end:.4g} s (MSER-5), inside the tables' window "
                         f"(`--settle {end:.4g}` leaves it out)")
        elif st["settled"] is False:
            text = f"{where}: **NOT settled** ({st['reason']}); its means and p99 are marked {MARK}"
        else:
            text = f"{where}: undecided ({st['reason']})"
        parts.append(text)
    return "; ".join(parts) + f". Method: {METHOD.split(', flexbearing')[0]}."
