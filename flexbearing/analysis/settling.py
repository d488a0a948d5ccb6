"""Has the run settled? The start-up transient and the drift of a phase, against the signal's own scatter.

Per uniform-speed phase of a run and per recorded signal (cage speed, slip, pocket force, guiding
force, the flexible cage's largest von Mises stress), the two tests of
flexbearing.common.stationarity: MSER-5 start-up truncation (White 1997) and the batch-means linear
trend test (Law 2015 §9.5.3; Schmeiser 1982). Its docstring gives the method, the signals and
their drift floors; this module applies it to a run's windows and writes the verdicts into the
report's rows.

Windows: the uniform-speed phases of the speed profile (an acceleration or deceleration is a
transient by design: not tested), and the whole run when it is one such phase.
"""
from __future__ import annotations

import numpy as np

from flexbearing.common.stationarity import ALPHA, MIN_BATCHES, MSER_BATCH, N_BATCHES, SIGNALS, mser, signal_settling


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
