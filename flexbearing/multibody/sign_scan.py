"""The roots of a scalar function g(x) on [a, b] from its values on a grid, with what lies between the
grid points bounded by its slope.

Used for a one-dimensional reduction of a steady solve: with one unknown x fixed (the cage speed)
all the other equations are solved, and g(x) is the one equation left (the cage's torque balance).

What a scan shows, for a g continuous on [a, b]:

1. A sign change g(x_k)·g(x_k+1) < 0 proves a root in (x_k, x_k+1) (the intermediate value theorem).
2. Where g is Lipschitz on [x_k, x_k+1] with constant L, |g(x_k)| <= L·(x* − x_k) and |g(x_k+1)| <=
   L·(x_k+1 − x*) at any root x* between them, so

       |g(x_k)| + |g(x_k+1)| > L·(x_k+1 − x_k)   excludes a root in [x_k, x_k+1].

   L is not known; it is estimated as SLOPE_SAFETY times the largest secant slope measured,
   |g(x_k+1) − g(x_k)|/(x_k+1 − x_k) over the whole grid. A secant slope is a lower bound of the local
   Lipschitz constant (mean-value theorem), so this is an estimate, not a bound: a narrow spike of g
   between two points can break it. Intervals where the test fails and g does not change sign are
   bisected (up to `max_refine` times), which either finds the sign change or passes the test on
   the halves.
3. Where g cannot be evaluated at a point (the reduced sub-problem has no solution there, g = nan),
   nothing is claimed for the intervals next to it.

So "no sign change, every interval excluded, every point evaluated" means: no root of g on [a, b]
for any g whose slope stays below the estimated L — evidence as good as the slope estimate, not a
proof.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

SLOPE_SAFETY = 2.0      # the Lipschitz estimate: twice the largest measured secant slope


@dataclass(frozen=True)
class SignScan:
    """The scan of g (module docstring) over its grid, ascending."""
    x: np.ndarray                   # the grid, refinements included
    g: np.ndarray                   # g there (nan: not evaluated, the sub-problem unsolved)
    brackets: tuple                 # (x_k, x_k+1) with a sign change: each holds a root
    unexcluded: tuple               # (x_k, x_k+1) neither bracketing nor excluded by the slope test
    unsolved: tuple                 # x where g could not be evaluated
    lipschitz: float                # the slope estimate L (module docstring, item 2)

    @property
    def g_range(self) -> tuple[float, float]:
        ok = np.isfinite(self.g)
        return (float(np.min(self.g[ok])), float(np.max(self.g[ok]))) if ok.any() else (math.nan, math.nan)

    @property
    def no_root(self) -> bool:
        """No sign change, every interval excluded by the slope test and every point evaluated."""
        return not self.brackets and not self.unexcluded and not self.unsolved

    def describe(self, unit: str = "") -> str:
        lo, hi = self.g_range
        head = (f"{len(self.x)} points over [{self.x[0]:.4g}, {self.x[-1]:.4g}]{unit}: g from {lo:.3g} to {hi:.3g}, "
                f"slope estimate L = {self.lipschitz:.3g}")
        if self.brackets:
            return head + f"; sign change(s) in {', '.join(f'[{a:.4g}, {b:.4g}]' for a, b in self.brackets)}"
        if self.no_root:
            return head + "; no sign change, and |g(x_k)| + |g(x_k+1)| > L·h on every interval: no root for a slope below L"
        return (head + f"; no sign change, {len(self.unexcluded)} interval(s) not excluded by the slope test, "
                f"{len(self.unsolved)} point(s) where g could not be evaluated")


def _excluded(g0: float, g1: float, width: float, lipschitz: float) -> bool:
    """|g0| + |g1| > L·width (module docstring, item 2)."""
    return abs(g0) + abs(g1) > lipschitz * width


def _slope(x: np.ndarray, g: np.ndarray) -> float:
    """SLOPE_SAFETY × the largest secant slope between neighbouring evaluated points."""
    s = 0.0
    for k in range(len(x) - 1):
        if np.isfinite(g[k]) and np.isfinite(g[k + 1]):
            s = max(s, abs(g[k + 1] - g[k]) / (x[k + 1] - x[k]))
    return SLOPE_SAFETY * s


def sign_scan(g, grid, max_refine: int = 3) -> SignScan:
    """g (a callable of one float returning a float, nan where it cannot be evaluated) on the ascending
    `grid`, intervals neither bracketing a root nor excluded by the slope test bisected up to
    max_refine times (module docstring)."""
    x = [float(v) for v in grid]
    vals = {v: float(g(v)) for v in x}
    for _ in range(max_refine + 1):
        xs = np.array(sorted(vals))
        gs = np.array([vals[v] for v in xs])
        lip = _slope(xs, gs)
        brackets, open_, unsolved = [], [], [float(v) for v, w in zip(xs, gs) if not np.isfinite(w)]
        for k in range(len(xs) - 1):
            g0, g1 = gs[k], gs[k + 1]
            if not (np.isfinite(g0) and np.isfinite(g1)):
                continue
            if g0 == 0.0 or g0 * g1 < 0.0:
                brackets.append((float(xs[k]), float(xs[k + 1])))
            elif not _excluded(g0, g1, xs[k + 1] - xs[k], lip):
                open_.append((float(xs[k]), float(xs[k + 1])))
        if not open_ or _ == max_refine:
            break
        for a, b in open_:
            m = 0.5 * (a + b)
            vals[m] = float(g(m))
    return SignScan(xs, gs, tuple(brackets), tuple(open_), tuple(unsolved), float(lip))
