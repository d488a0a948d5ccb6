"""Progress of a long task made of named stages: one tqdm bar that says what is being done and
how long the rest should take.

A stage's weight is its expected share of the task (e.g. its measured wall time on the paper cage,
s). The bar's total is the sum of the weights and a finished stage advances it by its own weight,
so tqdm's estimate of the time left, elapsed × (weights left / weights done), is the measured
proportions scaled by this machine's speed. Silent when quiet; on stderr, so a command's printed
results (stdout) stay clean.
"""
from __future__ import annotations

import sys
import threading


class Stages:
    """stages = Stages("reduce paper cage", {"mesh": 3, "K and M": 20, ...}); stages("mesh") starts
    a stage (finishing the one before), stages(None) or close() finishes the last."""

    def __init__(self, task: str, stages, quiet: bool = False):
        self.weights = dict(stages) if isinstance(stages, dict) else {s: 1.0 for s in stages}
        self.task = task
        self.current = None
        self.bar = None
        if quiet:
            return
        from tqdm import tqdm
        self.bar = tqdm(total=float(sum(self.weights.values())), desc=task, file=sys.stderr,
                        mininterval=0.5, dynamic_ncols=True,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}]")
        # a stage can last minutes without an update: redraw the clock every second meanwhile
        # (a daemon thread; it waits while a compiled solver holds the GIL)
        self._stop = threading.Event()
        threading.Thread(target=self._tick, daemon=True).start()

    def _tick(self) -> None:
        while not self._stop.wait(1.0):
            bar = self.bar
            if bar is not None:
                bar.refresh()

    def __call__(self, stage: str | None) -> None:
        if self.current is not None and self.bar is not None:
            self.bar.update(self.weights.get(self.current, 0.0))
        self.current = stage
        if stage is None:
            self.close()
        elif self.bar is not None:
            i = list(self.weights).index(stage) + 1 if stage in self.weights else "?"
            self.bar.set_description_str(f"{self.task}: {stage} ({i}/{len(self.weights)})")

    def close(self) -> None:
        if self.bar is not None:
            self._stop.set()
            bar, self.bar = self.bar, None
            bar.close()

    def __enter__(self) -> "Stages":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def steps(task: str, stages, quiet: bool = False) -> Stages:
    """Stages(task, stages, quiet)."""
    return Stages(task, stages, quiet)
