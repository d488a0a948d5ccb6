"""The wall-time budget of a run: say early when a run will take hours, and stop it if asked to.

A run's cost is set by its step size, which the physics chooses: at 0–100 rpm the steps fall to
about 1e-8 s (measured: a 5 ms run took 457,000–576,000 steps, 82–123 s), and a long scene at
such speeds would run for hours without a word. The run
loop calls `WallBudget.update(t, n_steps)` after every sample; from the first sample on (whose
wall time holds the compilation of the kernels), once `warn_after` seconds of wall time have
passed, it predicts the total from the simulated-time rate since the first sample,

    T_total = W + W1·(T − t)/(t − t1)     (W wall time since the start or resume, W1 since the first
                                          sample at t1, T the duration)

and, the first time T_total exceeds `warn_above` (default one hour), issues a `SlowRunWarning`
with the prediction, the step rate and the mean step, and how to stop. With `max_wall_time` set,
a predicted total above it raises `WallTimeExceeded`: the run loop then checkpoints and stops, and
`--resume` continues it (without the limit, or with a larger one). The prediction is linear in
simulated time: a run whose hard part is still ahead (a late impact, a speed ramp down to rest) is
underestimated, one whose start-up transient is the hard part overestimated.
"""
from __future__ import annotations

import time
import warnings

WARN_AFTER_S = 20.0          # wall seconds of integration before the first prediction (a start-up
                             # transient and the first compiled calls are not a rate)
WARN_ABOVE_S = 3600.0        # a predicted total above this deserves a warning


class SlowRunWarning(UserWarning):
    """The run is predicted to take longer than the warning threshold."""


class WallTimeExceeded(RuntimeError):
    """The predicted wall time exceeds the run's max_wall_time (the run stops at a checkpoint)."""


def _hours(s: float) -> str:
    return f"{s / 3600:.1f} h" if s >= 3600 else f"{s / 60:.1f} min" if s >= 60 else f"{s:.0f} s"


class WallBudget:
    def __init__(self, duration: float, t0: float = 0.0, n_steps0: int = 0, name: str = "run",
                 max_wall_time: float | None = None, warn_above: float | None = None,
                 warn_after: float | None = None):
        self.duration, self.t0, self.n_steps0, self.name = duration, t0, n_steps0, name
        self.max_wall_time = max_wall_time
        self.warn_above = WARN_ABOVE_S if warn_above is None else warn_above
        self.warn_after = WARN_AFTER_S if warn_after is None else warn_after
        self.wall0 = time.perf_counter()
        self.warned = False
        self.ref = None                 # (wall, t, steps) at the first sample: the rate is measured from it
        self.predicted = None           # s, the latest prediction of the total wall time

    def update(self, t: float, n_steps: int) -> None:
        now = time.perf_counter()
        if self.ref is None:            # the first sample: its wall time holds the compilation of the
            self.ref = (now, t, n_steps)    # kernels (tens of s on a busy machine), not a step rate
            return
        wall0, t_ref, steps_ref = self.ref
        wall_rate, done = now - wall0, t - t_ref
        if wall_rate < self.warn_after or done <= 0.0:
            return
        wall = now - self.wall0
        total = wall + wall_rate * (self.duration - t) / done
        self.predicted = total
        steps = n_steps - steps_ref
        what = (f"{self.name}: {steps:,} steps in {wall_rate:.0f} s of wall time for {done:.3g} s simulated "
                f"({steps / wall_rate:,.0f} steps/s, mean step {done / max(steps, 1):.2g} s); at this rate the "
                f"run needs about {_hours(total)} in all ({_hours(total - wall)} more) for its "
                f"{self.duration:g} s")
        if self.max_wall_time is not None and total > self.max_wall_time:
            raise WallTimeExceeded(f"{what}, more than the allowed {_hours(self.max_wall_time)} "
                                   f"(max_wall_time = {self.max_wall_time:g} s)")
        if not self.warned and total > self.warn_above:
            self.warned = True
            warnings.warn(f"{what}. Ctrl-C stops it and keeps what was computed (--resume continues); "
                          f"--max-wall-time S stops a run predicted to take longer than S seconds",
                          SlowRunWarning, stacklevel=2)
