"""A steady solve started from the dynamics' own flow: `settle_then_solve`.

Newton-type solvers (MINPACK's hybrid method, damped Newton) reach a fixed point F(u) = 0 of the
equations of motion only from a start inside its basin. Where the quasi-static start lies outside
it (measured on the cold-oil runs of the slip-rate uncertainty study: the ball spin, a stiff
first-order balance of the traction at two contacts, jumps between iterates and the solve ends
far from any root), the start is moved along the system's own trajectory instead: the equations
of motion are integrated in time from the quasi-static state, and after every chunk of simulated
time the solve is tried again from the state reached. This is the faithful form of the time-
accurate first phase of pseudo-transient continuation (Kelley & Keyes, "Convergence analysis of
pseudo-transient continuation", SIAM J. Numer. Anal. 35(2):508–523, 1998: march the transient
until the iterate is in the root's basin, then let Newton converge): the pseudo-time is the real
time and the flow the real dynamics, second-order positions included (a first-order flow
du/dt = F(u) on accelerations is not their flow and can be unstable where the dynamics are
stable). A stable equilibrium is the limit of the trajectories that start in its basin (Seydel,
*Practical Bifurcation and Stability Analysis*, 3rd ed., Springer 2010, ch. 1), so the root
found this way is one the dynamics head to; the solve only needs the fast variables settled, not
the slow ones (the cage speed), which the root then gives directly.
"""
from __future__ import annotations

from typing import Any, Callable, NamedTuple

import numpy as np


class SettledRoot(NamedTuple):
    """What `settle_then_solve` found: root (the solve's result, None where no chunk gave one),
    settled_time (simulated time integrated before the solve that converged, or in all, s), chunks
    (the number of chunks integrated), state (the state the last solve started from)."""
    root: Any
    settled_time: float
    chunks: int
    state: np.ndarray


def settle_then_solve(advance: Callable[[np.ndarray, float, float], np.ndarray],
                      solve: Callable[[np.ndarray], Any], y0: np.ndarray, chunk: float,
                      max_chunks: int) -> SettledRoot:
    """Integrate the dynamics y' = f(t, y) from y0 in chunks of `chunk` (s) of simulated time,
    `advance(y, t0, t1)` returning the state at t1, and after every chunk try `solve(y)` (the
    steady solve started from the state reached; it returns its root, or None where it does not
    converge). Returns the first root (module docstring), or root None after max_chunks chunks."""
    if not chunk > 0.0 or max_chunks < 1:
        raise ValueError(f"settle_then_solve: chunk = {chunk!r} s must be > 0 and max_chunks = {max_chunks!r} >= 1")
    y, t = np.array(y0, dtype=float), 0.0
    for k in range(1, max_chunks + 1):
        y = np.asarray(advance(y, t, t + chunk), dtype=float)
        t += chunk
        root = solve(y)
        if root is not None:
            return SettledRoot(root, t, k, y)
    return SettledRoot(None, t, max_chunks, y)
