"""Progress of a long task made of named stages: one tqdm bar that says what is being done and
how long the rest should take.

A stage's weight is its measured wall time on a reference case (s: the paper cage, the demo's
runs). The bar's total is the sum of the weights and a finished stage advances it by its own
weight. The estimate of the time left is the weights still to do divided by this machine's speed
against the reference,

    speed = (weights of the finished stages) / (wall time they took)      (1 before any finished)
    left  = max(w_current / speed - time in the current stage, 0) + (weights after it) / speed,

redrawn every second, so it counts down inside a stage that lasts minutes (tqdm's own estimate
would stand still between updates). Silent when quiet; on stderr, so a command's printed results
(stdout) stay clean.
"""
from __future__ import annotations

import sys
import threading
import time
from tqdm import tqdm


def time_left(weights: dict, done: list[str], current: str | None, elapsed_done: float,
              in_stage: float) -> float:
    """Seconds left (module doc): `done` the finished stages, which took `elapsed_done` s,
    `current` the running one, `in_stage` s in it."""
    w_done = sum(weights[s] for s in done)
    speed = w_done / elapsed_done if w_done > 0 and elapsed_done > 0 else 1.0
    after = [s for s in weights if s not in done and s != current]
    left = sum(weights[s] for s in after) / speed
    if current is not None:
        left += max(weights.get(current, 0.0) / speed - in_stage, 0.0)
    return left


def _clock(seconds: float) -> str:
    s = int(round(seconds))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}" if s >= 3600 else f"{s // 60}:{s % 60:02d}"


class Stages:
    """stages = Stages("reduce the cage", {"mesh": 3, "K and M": 7, ...}); stages("mesh") starts
    a stage (finishing the one before), stages(None) or close() finishes the last."""

    def __init__(self, task: str, stages, quiet: bool = False):
        self.weights = dict(stages) if isinstance(stages, dict) else {s: 1.0 for s in stages}
        self.task = task
        self.current = None
        self.done: list[str] = []
        self.t0 = self.t_stage = time.perf_counter()
        self.bar = None
        if quiet:
            return
        self.bar = tqdm(total=float(sum(self.weights.values())), desc=task, file=sys.stderr,
                        mininterval=0.5, dynamic_ncols=True,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| {elapsed} elapsed{postfix}")
        # a stage can last minutes without an update: redraw the clock every second meanwhile
        # (a daemon thread; it waits while a compiled solver holds the GIL)
        self._stop = threading.Event()
        threading.Thread(target=self._tick, daemon=True).start()

    def left(self) -> float:
        """Estimated seconds left (module doc)."""
        now = time.perf_counter()
        return time_left(self.weights, self.done, self.current, self.t_stage - self.t0, now - self.t_stage)

    def _tick(self) -> None:
        while not self._stop.wait(1.0):
            bar = self.bar
            if bar is not None:
                bar.set_postfix_str(f"about {_clock(self.left())} left", refresh=True)

    def __call__(self, stage: str | None) -> None:
        finished, self.current = self.current, stage
        if finished is not None:
            self.done.append(finished)
        self.t_stage = time.perf_counter()
        if self.bar is not None:
            if stage is not None:
                i = list(self.weights).index(stage) + 1 if stage in self.weights else "?"
                self.bar.set_description_str(f"{self.task}: {stage} ({i}/{len(self.weights)})", refresh=False)
                self.bar.set_postfix_str(f"about {_clock(self.left())} left", refresh=False)
            if finished is not None:
                self.bar.update(self.weights.get(finished, 0.0))
        if stage is None:
            self.close()

    def close(self) -> None:
        if self.bar is not None:
            self._stop.set()
            if self.current is not None:        # closed inside a stage (an error): count it
                self.done.append(self.current)
                self.current = None
            bar, self.bar = self.bar, None
            bar.set_description_str(self.task, refresh=False)
            bar.set_postfix_str("done", refresh=False)
            bar.close()

    def __enter__(self) -> "Stages":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
