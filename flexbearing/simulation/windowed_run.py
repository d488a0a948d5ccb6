"""Run a model in windows until the caller's test says it has settled: the run loop of the steady
validations (flexbearing.studies.validation.slip_rate), which keep no results file.

From t = 0 the state is advanced sample by sample (flexbearing.multibody.integrator.advance, one
call per sample interval `sample_dt`, the last one of a window shortened to end on it); at each
sample the caller's `sample(outputs)` reduces the outputs (flexbearing.multibody.outputs
.evaluate_outputs) to a few numbers, and at the end of each window of `window` seconds their means
over the window are appended to the window means. After each window `stop(t, means)` decides
whether the run has settled; at `t_max` it stops regardless. The scene runs' loop
(flexbearing.simulation.run.RunLoop) streams every sample to a file instead; this one keeps only
the window means, which is all a steady-state validation reads.
"""
from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np

from flexbearing.multibody import integrator as I, outputs as O


class WindowedRun(NamedTuple):
    """Where `run_in_windows` stopped: the state y at time t, the means of each window (one tuple
    per window, in the order `sample` returns its numbers), whether `stop` ended it (False: t_max),
    and the integrator's accepted and rejected steps."""
    y: np.ndarray
    t: float
    window_means: list[tuple[float, ...]]
    stopped: bool
    n_steps: int
    n_rejected: int


def run_in_windows(model, y, speed_table, load_table, impacts, tol: float, window: float, t_max: float,
                   sample_dt: float, sample: Callable[[dict], tuple],
                   stop: Callable[[float, list], bool], h: float = 1e-6) -> WindowedRun:
    """Advance `y` from t = 0 in windows (module docstring) until `stop(t, window_means)` is true
    after a window, or t reaches t_max. `y` is advanced in place."""
    ws = I.Workspace(model)
    t = 0.0
    n_steps = n_rejected = 0
    means: list[tuple[float, ...]] = []
    stopped = False
    while t < t_max - 1e-12:
        values = []
        t_w_end = t + window
        while t < t_w_end - 1e-12:
            y, t, h, a, b = I.advance(model, y, t, min(t + sample_dt, t_w_end), speed_table, load_table,
                                      impacts, tol, h, ws)
            n_steps += a
            n_rejected += b
            values.append(sample(O.evaluate_outputs(model, t, y, speed_table, load_table, impacts)))
        means.append(tuple(float(np.mean(column)) for column in zip(*values)))
        if stop(t, means):
            stopped = True
            break
    return WindowedRun(y, t, means, stopped, n_steps, n_rejected)
