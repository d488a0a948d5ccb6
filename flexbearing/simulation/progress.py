"""Progress of a run: a tqdm bar over simulated time with steps/s and ETA; silent when quiet."""
from __future__ import annotations

import sys
import time

from tqdm import tqdm


class RunProgress:
    """Bar whose total is the scene duration [s of simulated time]; ETA from the simulated-time rate."""

    def __init__(self, duration: float, t0: float = 0.0, quiet: bool = False, desc: str = "run",
                 n_steps0: int = 0):
        self.bar = None
        self.t = t0
        self.n_steps0 = n_steps0
        self.wall0 = time.perf_counter()
        if quiet:
            return
        self.bar = tqdm(total=duration, initial=t0, desc=desc, unit="s", file=sys.stderr,
                        mininterval=0.5, dynamic_ncols=True,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| t = {n:.4f}/{total:.4f} s "
                                   "simulated [{elapsed}<{remaining}{postfix}]")

    def update(self, t: float, n_steps: int) -> None:
        if self.bar is None:
            return
        dt = t - self.t
        self.t = t
        wall = time.perf_counter() - self.wall0
        rate = (n_steps - self.n_steps0) / wall if wall > 0 else 0.0
        self.bar.set_postfix_str(f"{rate:,.0f} steps/s", refresh=False)
        self.bar.update(dt)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None
