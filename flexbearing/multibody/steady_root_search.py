"""Other held-cage roots where the steady solver found none: a deflated Newton search over physical
starts, and a scan of the cage's torque balance over the cage speed.

`flexbearing.multibody.steady.steady_held_cage_state` follows one branch of the frozen-azimuth
held-cage equations F(u; lambda) = 0 (lambda scales the radial load and the weight) from the
symmetric thrust state. Where that branch folds below lambda = 1, the fold proves only that this
branch has no root at the full load. Two searches here look for a root on any other branch:

1. **Deflated Newton** (`flexbearing.multibody.deflation`; Farrell, Birkisson & Funke, SIAM J. Sci.
   Comput. 37(4):A2026–A2045, 2015) on F(u; 1) = 0 from a set of starts that covers the physical
   range (`physical_starts`): the cage speed omega_c on a grid of fractions of the inner-ring speed,
   each ball's spin from the pure-rolling law on the outer race (omega_b ∝ omega_c, the race at rest)
   or on the inner race (omega_b − omega_i·e_x ∝ omega_c − omega_i, the race turning), and each
   ball's pocket offset against either wall; the ball positions, ring and cage displacements of a
   reference state (the branch's last root). The caller adds the branch's own roots and states of
   the settled dynamics. Every root found is deflated; a root found is a real result.

2. **The cage-speed reduction** (`cage_speed_scan`). For fixed omega_c the 6Z + 10 equations
   other than the cage's torque balance (every ball, the inner ring, the cage's translations and
   tilts) are solved for their 6Z + 10 unknowns (damped Newton, warm-started from the nearest
   cage speed already solved); g(omega_c) is the cage's torque balance there, the cage's angular
   acceleration scaled as in the solver (N per ball relative to the axial load per ball). A root of
   the full system is a root of g with a solved sub-problem and conversely. `flexbearing.multibody.
   sign_scan` reads g on the grid: a sign change proves a root of g (then the full system is solved
   from there); no sign change with every interval excluded by the slope test and every sub-problem
   solved shows that no held-cage root exists on the part of the branch of sub-problem solutions
   the scan followed — it says nothing about sub-problem solutions on other branches at the same
   omega_c (the sub-problem can itself have several roots), nor about a g steeper than the slope
   estimate.

Neither proves that no steady state exists: the frozen-azimuth equations neglect the balls' lag
along their orbit (steady.py), so the running state may be periodic at the ball-pass frequency, and
the cage may whirl instead of being held.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from flexbearing.multibody.deflation import DeflatedSearch, deflated_search
from flexbearing.multibody.sign_scan import SignScan, sign_scan
from flexbearing.multibody.steady import _held_cage_equations, _newton, _held_cage_solve
from flexbearing.multibody.steady_search_starts import load_at, model_at
from flexbearing.multibody.steady_hold import cage_hold_check

@dataclass
class RootSearch:
    """What `held_cage_root_search` found at one lambda."""
    lam: float
    search: DeflatedSearch
    roots: list = field(default_factory=list)        # per new root: dict(unknowns, residual, cage_speed, slip, held, hold)
    cpu_s: float = 0.0

    def describe(self) -> str:
        found = "; ".join(f"root {k}: cage {r['cage_speed']:.1f} rad/s, slip {100 * r['slip']:.2f} %, residual "
                          f"{r['residual']:.1e}, {r['hold'].describe()}" for k, r in enumerate(self.roots))
        return f"at lambda = {self.lam:g}, {self.search.describe()}" + (f": {found}" if found else "")


def held_cage_root_search(model, speed_rad_s: float, load, u_ref: np.ndarray, starts, lam: float = 1.0,
                          phase: float = 0.0, known_roots=(), tol: float = 1e-9, max_iter: int = 30,
                          cpu_budget_s: float = math.inf, hold_check: bool = True) -> RootSearch:
    """Deflated Newton (module docstring, item 1) on the held-cage equations at lambda from `starts`
    (unknown vectors, the solve's layout), scaled about u_ref (the solver's scaling), the roots
    `known_roots` deflated; a root is kept where its cage speed lies in (0, omega_i]. Each new root is
    re-solved by the solver's own Newton (its outputs) and checked in the dynamics (steady_hold)."""
    t0 = time.process_time()
    m_l, load_l = model_at(model, lam), load_at(load, lam)
    residual, _, scale_u = _held_cage_equations(m_l, speed_rad_s, load_l, phase, u_ref)
    nb = 6 * model.n_balls
    to_v = lambda u: (np.asarray(u, dtype=float) - u_ref) / scale_u
    accept = lambda v: 0.0 < u_ref[nb] + v[nb] * scale_u[nb] <= speed_rad_s
    search = deflated_search(residual, [to_v(u) for u in starts], [to_v(r) for r in known_roots], tol=tol,
                             max_iter=max_iter, accept=accept, cpu_budget_s=cpu_budget_s)
    out = RootSearch(lam, search)
    for v in search.roots:
        u = u_ref + v * scale_u
        y, info = _held_cage_solve(m_l, speed_rad_s, load_l, phase, tol, start=u)
        hold = cage_hold_check(m_l, speed_rad_s, load_l, y) if hold_check else None
        out.roots.append(dict(unknowns=u, residual=info["residual"], cage_speed=info["cage_speed"],
                              slip=float(info["outputs"]["slip_rate"]), converged=info["converged"],
                              held=None if hold is None else hold.held, hold=hold,
                              eccentricity=info["cage_eccentricity_ratio"]))
    out.cpu_s = time.process_time() - t0
    return out


@dataclass
class CageSpeedScan:
    """`cage_speed_scan`'s result: the sign scan of g(omega_c / omega_i) and the roots it led to."""
    lam: float
    scan: SignScan
    roots: list                 # per bracket: dict(unknowns, residual, converged, cage_speed)
    cpu_s: float

    def describe(self) -> str:
        return f"at lambda = {self.lam:g}, the cage torque balance g over omega_c/omega_i: {self.scan.describe()}"


class _ReducedProblem:
    """The held-cage equations with the cage speed fixed (module docstring, item 2), scaled about u_ref:
    solve(lam, omega_c, u_start) -> (unknowns, g) or None where the damped Newton does not converge."""

    def __init__(self, model, speed_rad_s: float, load, phase: float, u_ref: np.ndarray, tol: float):
        self.model, self.speed, self.load, self.phase, self.u_ref, self.tol = model, speed_rad_s, load, phase, u_ref, tol
        self.nb = 6 * model.n_balls
        self.keep = np.arange(u_ref.size) != self.nb
        self.equations = {}

    def residual(self, lam):
        if lam not in self.equations:
            if len(self.equations) > 4:
                self.equations.clear()
            self.equations[lam] = _held_cage_equations(model_at(self.model, lam), self.speed, load_at(self.load, lam),
                                                       self.phase, self.u_ref)
        return self.equations[lam]

    def solve(self, lam: float, omega_c: float, u_start: np.ndarray):
        residual, _, scale_u = self.residual(lam)
        v0 = (np.asarray(u_start, dtype=float) - self.u_ref) / scale_u
        v0[self.nb] = (omega_c - self.u_ref[self.nb]) / scale_u[self.nb]
        keep = self.keep

        def sub(w):
            v = v0.copy()
            v[keep] += w
            return residual(v)[keep]
        w, fw, _, _ = _newton(sub, int(keep.sum()), self.tol)
        if np.max(np.abs(fw)) > self.tol:
            return None
        v = v0.copy()
        v[keep] += w
        return self.u_ref + v * scale_u, float(residual(v)[self.nb])

    def continue_in_lambda(self, lam0: float, lam1: float, omega_c: float, u0: np.ndarray, min_step: float = 1 / 256):
        """(unknowns, g) at lam1 by natural continuation in lambda of the reduced problem at fixed omega_c
        from its solution u0 at lam0 (step 0.25, halved on failure down to min_step, x1.5 on success)."""
        lam, u, step, out = lam0, u0, 0.25, (u0, math.nan)
        while lam < lam1:
            trial = min(lam1, lam + step)
            got = self.solve(trial, omega_c, u)
            if got is None:
                step *= 0.5
                if step < min_step:
                    return None
                continue
            lam, (u, g) = trial, got
            out = (u, g)
            step *= 1.5
        return out


def _sweep(problem: _ReducedProblem, lam: float, start: tuple, targets, min_share: float = 1.0 / 64.0) -> dict:
    """{omega_c: (unknowns, g)} along `targets` (cage speeds in order away from start's) by natural
    continuation in omega_c: each target approached from the last point solved in steps that are halved
    on failure (down to min_share of the way) and enlarged by 1.5 on success; a target not reached ends
    the sweep (the reduced problem's branch ends, or its steps cannot cross a kink)."""
    out = {}
    omega, u = start
    for target in targets:
        share = 1.0
        while omega != target:
            trial = omega + min(1.0, share) * (target - omega) if share < 1.0 else target
            got = problem.solve(lam, trial, u)
            if got is None:
                share *= 0.5
                if share < min_share:
                    return out
                continue
            omega, u = trial, got[0]
            share = min(1.0, 1.5 * share)
            if omega == target:
                out[target] = got
    return out


def _root_in_bracket(problem: _ReducedProblem, lam: float, a: tuple, b: tuple, tol: float, max_solves: int = 30):
    """(omega_c, unknowns, g) with |g| <= tol (a root of the full equations: the reduced ones solved and the
    cage torque balanced) by the Illinois variant of regula falsi (Dowell & Jarratt, BIT 11:168–174, 1971) on
    g in the bracket a = (omega_a, (unknowns, g_a)), b likewise, g_a·g_b < 0, each reduced solve started
    from the nearer end; None where a reduced solve fails or max_solves are spent."""
    (wa, (ua, ga)), (wb, (ub, gb)) = a, b
    side = 0
    for _ in range(max_solves):
        w = (wa * gb - wb * ga) / (gb - ga)
        got = problem.solve(lam, w, ua if abs(w - wa) <= abs(wb - w) else ub)
        if got is None:
            return None
        u, g = got
        if abs(g) <= tol:
            return w, u, g
        if g * gb < 0.0:
            wa, ua, ga = wb, ub, gb
            side = 0
        elif side == 1:
            ga *= 0.5
        side = 1
        wb, ub, gb = w, u, g
    return None


def cage_speed_scan(model, speed_rad_s: float, load, u_ref: np.ndarray, lam_ref: float, lam: float = 1.0,
                    phase: float = 0.0, fractions=np.linspace(0.05, 0.8, 16), tol: float = 1e-9,
                    max_refine: int = 3) -> CageSpeedScan:
    """The reduction of the module docstring, item 2: g(f), f = omega_c/omega_i on `fractions`. u_ref is a
    root at lam_ref (e.g. the branch's last root): the reduced problem at its cage speed is continued in
    lambda from lam_ref to lam (it need not fold where the full one does: the cage speed is held), then
    swept outward over the grid on both sides, each point from its neighbour. g = nan where the reduced
    problem is not solved. Each sign change is then solved in full from the sub-solution nearer to it."""
    t0 = time.process_time()
    problem = _ReducedProblem(model, speed_rad_s, load, phase, u_ref, tol)
    nb = problem.nb
    omega_ref = float(u_ref[nb])
    first = problem.continue_in_lambda(lam_ref, lam, omega_ref, u_ref) if lam > lam_ref else \
        problem.solve(lam, omega_ref, u_ref)
    grid = [float(f) for f in fractions]
    solved = {}
    if first is not None:
        up = [f for f in grid if f * speed_rad_s >= omega_ref]
        down = [f for f in reversed(grid) if f * speed_rad_s < omega_ref]
        for side in (up, down):
            got = _sweep(problem, lam, (omega_ref, first[0]), [f * speed_rad_s for f in side])
            solved.update({f: got[f * speed_rad_s] for f in side if f * speed_rad_s in got})

    def g(f):
        if f not in solved:
            if not solved:
                return math.nan
            near = min(solved, key=lambda s: abs(s - f))
            got = _sweep(problem, lam, (near * speed_rad_s, solved[near][0]), [f * speed_rad_s])
            if not got:
                return math.nan
            solved[f] = got[f * speed_rad_s]
        return solved[f][1]
    scan = sign_scan(g, grid, max_refine=max_refine)
    roots = []
    m_l, load_l = model_at(model, lam), load_at(load, lam)
    for a, b in scan.brackets:
        found = _root_in_bracket(problem, lam, (a * speed_rad_s, solved[a]), (b * speed_rad_s, solved[b]), tol)
        if found is None:
            roots.append(dict(converged=False, bracket=(a, b)))
            continue
        _, info = _held_cage_solve(m_l, speed_rad_s, load_l, phase, tol, start=found[1])
        roots.append(dict(unknowns=info["unknowns"], residual=info["residual"], converged=info["converged"],
                          cage_speed=info["cage_speed"], slip=float(info["outputs"]["slip_rate"]), bracket=(a, b)))
    return CageSpeedScan(lam, scan, roots, time.process_time() - t0)


def follow_to_full_load(model, speed_rad_s: float, load, u0: np.ndarray, lam0: float = 0.0, phase: float = 0.0,
                        tol: float = 1e-9, first_step: float = 0.25, min_step: float = 1.0 / 256.0,
                        cpu_budget_s: float = 60.0) -> dict:
    """Natural-parameter continuation in lambda (Allgower & Georg, *Introduction to Numerical
    Continuation Methods*, SIAM 2003, ch. 1–2; the held-cage solver's own scheme without its
    arclength) from a root u0 at lambda0 (another branch's start, e.g. a second root at lambda = 0
    found by deflation) towards lambda = 1: secant predictor through the last two roots, then the
    last root; a failed step halved down to min_step, a converged one enlarged by 1.5. Returns
    dict(lam (the last lambda solved), reached (lambda = 1), unknowns, info (the solve's info there),
    path, cpu_s)."""
    t0 = time.process_time()
    lam, u, step, prev, path, info = lam0, np.asarray(u0, dtype=float), first_step, None, [lam0], None
    while lam < 1.0 and time.process_time() - t0 < cpu_budget_s:
        trial = min(1.0, lam + step)
        starts = ([u + (trial - lam) / (lam - prev[0]) * (u - prev[1])] if prev is not None else []) + [u]
        for s in starts:
            _, info_t = _held_cage_solve(model_at(model, trial), speed_rad_s, load_at(load, trial), phase, tol, start=s)
            if info_t["converged"]:
                break
        if info_t["converged"]:
            prev, lam, u, info = (lam, u), trial, info_t["unknowns"], info_t
            path.append(lam)
            step *= 1.5
            continue
        step *= 0.5
        if step < min_step:
            break
    return dict(lam=lam, reached=lam >= 1.0, unknowns=u, info=info, path=path, cpu_s=time.process_time() - t0)
