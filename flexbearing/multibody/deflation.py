"""Deflated Newton: distinct roots of F(u) = 0 from a set of starts, each known root removed.

P. E. Farrell, Á. Birkisson & S. W. Funke, "Deflation techniques for finding distinct solutions of
nonlinear partial differential equations", SIAM J. Sci. Comput. 37(4):A2026–A2045, 2015. With the
roots r_1 … r_k already found, Newton's method is applied to the deflated residual

    G(u) = M(u)·F(u),   M(u) = prod_i ( 1/||u − r_i||^p + sigma ),

(their eq. (3.1) with the shifted deflation operator, their §3.2: p = 2, sigma = 1 are their
defaults). Where F is differentiable with a regular Jacobian at r_i, ||G(u)|| → ∞ as u → r_i for
p >= 1 (their Theorem 3.1: F(u) ~ F_u(r_i)·(u − r_i), so ||G|| ~ ||u − r_i||^(1−p)), so the
iteration cannot converge to a root already found; and G = 0 exactly where F = 0 away from the r_i.
The shift sigma keeps G from vanishing far from every r_i (M → sigma^k, not 0, as ||u|| → ∞: without
it the iterates drift away, their §3.2).

The Jacobian of G is G_u = M·F_u + F·(grad M)^T with grad M = M·sum_i [−p·||e_i||^(−p−2)·e_i /
(||e_i||^(−p) + sigma)], e_i = u − r_i (product rule). F_u comes from the caller's function or
from central differences; each Newton step solves G_u·d = −G (least squares where G_u is
singular), backtracking on ||G|| (Armijo), with a Levenberg–Marquardt step (G_u^T G_u +
mu·diag(G_u^T G_u))·d = −G_u^T·G where the Newton direction does not decrease ||G|| (the same
globalisation as `flexbearing.multibody.steady`'s damped Newton).

Convergence is tested on F itself: max|F| <= tol. With sigma = 1, M >= 1 everywhere, so
max|G| <= tol already implies max|F| <= tol.

What a search proves: the roots it lists are roots. A start that finds nothing proves nothing about
the region it starts in: Newton's basins can be small and fractal. The search is evidence, in
proportion to how well its starts cover the physical range, never a proof that no other root exists.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

DEFLATION_POWER = 2.0       # p of Farrell et al. 2015 (their default)
DEFLATION_SHIFT = 1.0       # sigma of Farrell et al. 2015 (their default)


def deflation_operator(u, roots, power: float = DEFLATION_POWER, shift: float = DEFLATION_SHIFT):
    """(M(u), grad M(u)) of the module docstring for the known roots `roots` (a sequence of vectors)."""
    u = np.asarray(u, dtype=float)
    m = 1.0
    s = np.zeros_like(u)
    for r in roots:
        e = u - np.asarray(r, dtype=float)
        d = float(np.linalg.norm(e))
        if d == 0.0:
            return np.inf, np.full_like(u, np.nan)
        a = d ** (-power)
        m *= a + shift
        s += -power * d ** (-power - 2.0) * e / (a + shift)
    return m, m * s


def _jacobian(residual, u, f, h):
    """F_u by central differences of step h (u scaled so that 1 is a meaningful change)."""
    n = u.size
    jac = np.empty((f.size, n))
    step = np.zeros(n)
    for k in range(n):
        step[k] = h
        jac[:, k] = (residual(u + step) - residual(u - step)) / (2.0 * h)
        step[k] = 0.0
    return jac


@dataclass
class DeflatedNewtonResult:
    """One deflated Newton run from one start."""
    u: np.ndarray                  # where it ended
    residual: float                # max|F(u)| there
    converged: bool                # residual <= tol
    iterations: int
    nfev: int
    stop: str                      # why it stopped


def deflated_newton(residual, u0, roots=(), tol: float = 1e-9, max_iter: int = 40, h: float = 1e-3,
                    jacobian=None, power: float = DEFLATION_POWER, shift: float = DEFLATION_SHIFT,
                    max_step: float | None = None) -> DeflatedNewtonResult:
    """Damped Newton on G = M·F (module docstring) from u0, the roots `roots` deflated. jacobian(u, f):
    F_u at u (default: central differences of step h). max_step: the largest step's infinity norm
    (None: no limit), a trust bound for piecewise laws whose Newton steps overshoot."""
    u = np.array(u0, dtype=float)
    f = np.asarray(residual(u), dtype=float)
    nfev = 1
    for it in range(1, max_iter + 1):
        if np.max(np.abs(f)) <= tol:
            return DeflatedNewtonResult(u, float(np.max(np.abs(f))), True, it - 1, nfev, "converged")
        jf = jacobian(u, f) if jacobian is not None else _jacobian(residual, u, f, h)
        nfev += 0 if jacobian is not None else 2 * u.size
        m, gm = deflation_operator(u, roots, power, shift)
        if not np.isfinite(m):
            return DeflatedNewtonResult(u, float(np.max(np.abs(f))), False, it, nfev, "on a known root")
        g = m * f
        jg = m * jf + np.outer(f, gm)
        norm0 = float(np.linalg.norm(g))
        d = np.linalg.lstsq(jg, -g, rcond=None)[0]
        if max_step is not None and np.max(np.abs(d)) > max_step:
            d *= max_step / np.max(np.abs(d))
        accepted, lam = False, 1.0
        while lam >= 1e-3:
            f_try = np.asarray(residual(u + lam * d), dtype=float)
            nfev += 1
            m_try = deflation_operator(u + lam * d, roots, power, shift)[0]
            if np.isfinite(m_try) and np.linalg.norm(m_try * f_try) < (1.0 - 1e-4 * lam) * norm0:
                accepted = True
                break
            lam *= 0.5
        if not accepted:
            jtj, jtg = jg.T @ jg, jg.T @ g
            diag = np.diag(jtj).copy() + 1e-12
            for mu in 10.0 ** np.arange(-4, 7):
                d = np.linalg.solve(jtj + mu * np.diag(diag), -jtg)
                lam = 1.0
                f_try = np.asarray(residual(u + d), dtype=float)
                nfev += 1
                m_try = deflation_operator(u + d, roots, power, shift)[0]
                if np.isfinite(m_try) and np.linalg.norm(m_try * f_try) < norm0:
                    accepted = True
                    break
        if not accepted:
            return DeflatedNewtonResult(u, float(np.max(np.abs(f))), False, it, nfev,
                                        f"stalled: no step decreases |M·F| ({norm0:.2e})")
        u, f = u + lam * d, f_try
    res = float(np.max(np.abs(f)))
    return DeflatedNewtonResult(u, res, res <= tol, max_iter, nfev,
                                "converged" if res <= tol else f"{max_iter} iterations, residual {res:.2e}")


@dataclass
class DeflatedSearch:
    """A deflated search over a set of starts (`deflated_search`)."""
    roots: list = field(default_factory=list)          # the distinct roots found (the known ones not included)
    root_residuals: list = field(default_factory=list)  # max|F| at each
    root_starts: list = field(default_factory=list)     # the index of the start that found each
    runs: list = field(default_factory=list)            # a DeflatedNewtonResult per start
    starts_tried: int = 0
    nfev: int = 0
    cpu_s: float = 0.0

    def describe(self) -> str:
        stalls = sum(1 for r in self.runs if not r.converged)
        return (f"deflated Newton (Farrell, Birkisson & Funke 2015) from {self.starts_tried} starts found "
                f"{len(self.roots)} new root(s); {stalls} start(s) ended without a root "
                f"({self.nfev} residual evaluations, {self.cpu_s:.1f} CPU-s)")


def deflated_search(residual, starts, known_roots=(), tol: float = 1e-9, max_iter: int = 40, h: float = 1e-3,
                    jacobian=None, accept=None, cpu_budget_s: float = float("inf"), **kw) -> DeflatedSearch:
    """Deflated Newton (module docstring) from every start in turn, every root found so far (and the
    known roots) deflated. accept(u): False rejects a root found (e.g. outside the physical range:
    it is then deflated as well, so that the search does not return to it, but not listed). Stops
    early where cpu_budget_s (process time) is spent."""
    t0 = time.process_time()
    out = DeflatedSearch()
    deflated = [np.asarray(r, dtype=float) for r in known_roots]
    for k, u0 in enumerate(starts):
        if time.process_time() - t0 > cpu_budget_s:
            break
        run = deflated_newton(residual, u0, deflated, tol, max_iter, h, jacobian, **kw)
        out.runs.append(run)
        out.starts_tried += 1
        out.nfev += run.nfev
        if run.converged:
            deflated.append(run.u.copy())
            if accept is None or accept(run.u):
                out.roots.append(run.u.copy())
                out.root_residuals.append(run.residual)
                out.root_starts.append(k)
    out.cpu_s = time.process_time() - t0
    return out
