"""Pseudo-arclength continuation of a branch of roots of F(v, lambda) = 0 around its turning points.

Natural-parameter continuation (lambda stepped, v solved at each lambda) cannot pass a turning point
(fold) of the branch: there lambda reaches an extremum and F_v is singular. Keller's pseudo-arclength
method (Keller, "Numerical solution of bifurcation and nonlinear eigenvalue problems", in
*Applications of Bifurcation Theory*, Academic Press 1977, pp. 359–384; Allgower & Georg,
*Introduction to Numerical Continuation Methods*, SIAM 2003, ch. 2 and §6.1; Seydel, *Practical
Bifurcation and Stability Analysis*, 3rd ed., Springer 2010, §4.5) parametrises the branch by its
arclength s instead. With w = (v, lambda) in R^(n+1) and H(w) = F(v, lambda):

    tangent     t:  H'(w_k)·t = 0,  |t| = 1,  oriented so that t·t_(k-1) > 0
                    (solved as [H'(w_k); t_(k-1)^T]·x = [0; 1], t = x/|x|: the bordered system is
                    regular at a simple turning point, where H'(w_k) has full rank n although F_v
                    is singular, Allgower & Georg 2003 §2.1–2.2)
    predictor       w_pred = w_k + ds·t
    corrector       Newton on  [H(w); t^T·(w − w_pred)] = [0; 0]   (Keller 1977)

so each corrected point lies on the hyperplane through the predicted point normal to the tangent.
The step ds is halved where the corrector fails or the tangent turns by more than MAX_TURN between
two points (the step would cut across to another part of the branch, Allgower & Georg 2003 §6.1),
and enlarged by 1.5 after a corrector that converged in at most 3 iterations.

Where lambda passes lambda_target between two points, the point at lambda_target is found by
Newton at fixed lambda from the secant interpolation between them. A turning point is recorded
where the tangent's lambda component changes sign. The branch is followed until it reaches
lambda_target, leaves [lambda_min, lambda_target] below, comes back within one step of its first
point after two turning points (a closed curve, an isola: Seydel 2010 §2.10), the corrector fails at
the smallest step (a kink or an end of the branch: a contact law switching), or max_steps are taken.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

# the largest turn of the tangent between two accepted points, rad (Allgower & Georg 2003, §6.1:
# the predictor's error grows with the branch's curvature; a larger turn is read as a step that
# cut across a bend of the branch)
MAX_TURN = 0.5


@dataclass
class ArclengthResult:
    """What pseudo_arclength found (module docstring)."""
    reached: bool                  # a root at lambda_target was found
    v: np.ndarray                  # the last point's unknowns (the root at lambda_target where reached)
    lam: float                     # its lambda
    residual: float                # max |F| there
    steps: int                     # accepted points
    turning_points: list = field(default_factory=list)   # lambdas where d lambda/ds changed sign
    lam_path: list = field(default_factory=list)         # lambda of every accepted point
    stop: str = ""                 # why it stopped where not reached
    closed: bool = False           # the branch came back to its first point: a closed curve
    nfev: int = 0
    cpu_s: float = 0.0

    def describe(self) -> str:
        """One sentence: where the branch went, with its numbers."""
        turns = ", ".join(f"{x:.4f}" for x in self.turning_points) or "none"
        lo = min(self.lam_path) if self.lam_path else self.lam
        hi = max(self.lam_path) if self.lam_path else self.lam
        head = (f"pseudo-arclength continuation (Keller 1977) followed the branch for {self.steps} points "
                f"over lambda {lo:.4f}–{hi:.4f}, turning at lambda = {turns}")
        if self.reached:
            return f"{head}, and reached lambda = {self.lam:.4f} (residual {self.residual:.2e})"
        return f"{head}, and stopped at lambda = {self.lam:.4f}: {self.stop}"


def _jacobian(residual, w: np.ndarray, f0_out: list, h: float, h_lambda: float) -> np.ndarray:
    """H'(w) (n x (n+1)) by central differences: step h in the scaled unknowns, h_lambda in lambda."""
    n = w.size - 1
    jac = np.empty((n, n + 1))
    v, lam = w[:-1], w[-1]
    e = np.zeros(n)
    for k in range(n):
        e[k] = h
        jac[:, k] = (residual(v + e, lam) - residual(v - e, lam)) / (2.0 * h)
        e[k] = 0.0
    jac[:, n] = (residual(v, lam + h_lambda) - residual(v, lam - h_lambda)) / (2.0 * h_lambda)
    f0_out[0] += 2 * (n + 1)
    return jac


def _tangent(jac: np.ndarray, t_prev: np.ndarray) -> np.ndarray:
    """The unit null vector of jac (n x (n+1)) oriented along t_prev: [jac; t_prev^T]·x = [0; 1]."""
    n = jac.shape[0]
    a = np.vstack([jac, t_prev[None, :]])
    rhs = np.zeros(n + 1)
    rhs[n] = 1.0
    x = np.linalg.lstsq(a, rhs, rcond=None)[0]
    return x / np.linalg.norm(x)


def _correct(residual, w_pred: np.ndarray, normal: np.ndarray, tol: float, count: list, h: float,
             h_lambda: float, max_iter: int = 8):
    """(w, max|F|, iterations, converged): Newton on [H(w); normal·(w − w_pred)] = 0 from w_pred."""
    w = w_pred.copy()
    f = np.asarray(residual(w[:-1], w[-1]), dtype=float)
    count[0] += 1
    for it in range(1, max_iter + 1):
        jac = _jacobian(residual, w, count, h, h_lambda)
        a = np.vstack([jac, normal[None, :]])
        g = np.concatenate([f, [normal @ (w - w_pred)]])
        dw = np.linalg.lstsq(a, -g, rcond=None)[0]
        w_new = w + dw
        f_new = np.asarray(residual(w_new[:-1], w_new[-1]), dtype=float)
        count[0] += 1
        if not np.all(np.isfinite(f_new)) or np.linalg.norm(f_new) > 2.0 * np.linalg.norm(f) + 1e-300 and it > 1:
            return w, float(np.max(np.abs(f))), it, False
        w, f = w_new, f_new
        if np.max(np.abs(f)) <= tol:
            return w, float(np.max(np.abs(f))), it, True
    return w, float(np.max(np.abs(f))), max_iter, False


def _root_at(residual, v0: np.ndarray, lam: float, tol: float, count: list, h: float, h_lambda: float):
    """(v, max|F|, converged): Newton at fixed lambda (the bordering row is e_lambda) from v0."""
    n = v0.size
    normal = np.zeros(n + 1)
    normal[n] = 1.0
    w, res, _, ok = _correct(residual, np.append(v0, lam), normal, tol, count, h, h_lambda)
    return w[:-1], res, ok


def pseudo_arclength(residual, v0, lam0: float, direction, lam_target: float = 1.0, lam_min: float = 0.0,
                     ds: float = 0.05, ds_min: float = 1e-4, ds_max: float = 2.0, max_steps: int = 200,
                     tol: float = 1e-9, h: float = 1e-3, h_lambda: float = 1e-3,
                     cpu_budget_s: float = math.inf) -> ArclengthResult:
    """Follow the branch of F(v, lambda) = residual(v, lambda) = 0 from its root (v0, lam0) by
    pseudo-arclength continuation (module docstring) in the direction (an (n+1)-vector, e.g. the
    secant from the root before) until lambda = lam_target. v scaled so that 1 is a meaningful
    change (as the Jacobian's difference step h); tol on max |F|."""
    t0 = time.process_time()
    w = np.append(np.asarray(v0, dtype=float), float(lam0))
    w_start = w.copy()
    count = [0]
    t = _tangent(_jacobian(residual, w, count, h, h_lambda), np.asarray(direction, dtype=float)
                 / np.linalg.norm(direction))
    f = np.asarray(residual(w[:-1], w[-1]), dtype=float)
    result = ArclengthResult(False, w[:-1].copy(), float(w[-1]), float(np.max(np.abs(f))), 0, [], [float(w[-1])])
    while result.steps < max_steps:
        if time.process_time() - t0 > cpu_budget_s:
            result.stop = f"its CPU budget of {cpu_budget_s:.0f} s was spent"
            break
        w_pred = w + ds * t
        w_new, res, iters, ok = _correct(residual, w_pred, t, tol, count, h, h_lambda)
        t_new = _tangent(_jacobian(residual, w_new, count, h, h_lambda), t) if ok else t
        if not ok or math.acos(min(1.0, abs(float(t_new @ t)))) > MAX_TURN:
            ds *= 0.5
            if ds < ds_min:
                result.stop = (f"the corrector found no point within the smallest step {ds_min:.1e} (residual "
                               f"{res:.2e}): the branch ends or has a kink there (a contact law switching)")
                break
            continue
        if t_new[-1] * t[-1] < 0.0:
            result.turning_points.append(float(w_new[-1] if abs(t_new[-1]) < abs(t[-1]) else w[-1]))
        if w_new[-1] >= lam_target:
            s = (lam_target - w[-1]) / (w_new[-1] - w[-1])
            v, res, ok = _root_at(residual, w[:-1] + s * (w_new[:-1] - w[:-1]), lam_target, tol, count, h, h_lambda)
            if ok:
                result.steps += 1
                result.lam_path.append(float(lam_target))
                result.reached, result.v, result.lam, result.residual = True, v, float(lam_target), res
                break
            ds *= 0.5
            if ds < ds_min:
                result.stop = f"no root at lambda = {lam_target} near the branch (residual {res:.2e})"
                break
            continue
        w, t = w_new, t_new
        result.steps += 1
        result.lam_path.append(float(w[-1]))
        result.v, result.lam, result.residual = w[:-1].copy(), float(w[-1]), res
        if w[-1] < lam_min:
            result.stop = f"the branch went back below lambda = {lam_min}"
            break
        if len(result.turning_points) >= 2 and np.linalg.norm(w - w_start) < ds:
            # back at the first point after two turns: the branch is a closed curve (an isola), every
            # point of it between the smallest and the largest lambda passed
            result.closed = True
            result.stop = "the branch closed on itself (a closed curve through the first point)"
            break
        if iters <= 3:
            ds = min(ds_max, 1.5 * ds)
    else:
        result.stop = f"{max_steps} points taken"
    result.nfev, result.cpu_s = count[0], time.process_time() - t0
    return result


def reduced_slope(jac: np.ndarray, k: int) -> float:
    """d F_k / d v_k along the set where the other n − 1 equations hold: the Schur complement

        s = J_kk − J_k,f · J_ff⁻¹ · J_f,k   (f: every index but k;  s = det J / det J_ff),

    the slope of equation k against unknown k with the other unknowns slaved to it (the implicit
    function theorem on the n − 1 other equations). For the held-cage state with k the cage speed this
    is the slope of the cage's net torque against its speed with the balls, rings and cage centre in
    their own equilibrium: the quasi-static (singular-perturbation) reduction of the slow cage-speed
    mode (Kokotović, Khalil & O'Reilly, *Singular Perturbation Methods in Control*, SIAM 1999, ch. 2),
    stable where it is negative — Harris's skidding criterion, the net cage torque falling as the cage
    speeds up (Harris, J. Lubr. Technol. 93(1):17–24, 1971) — provided the fast subsystem is stable."""
    n = jac.shape[0]
    f = np.r_[0:k, k + 1:n]
    x = np.linalg.solve(jac[np.ix_(f, f)], jac[f, k])
    return float(jac[k, k] - jac[k, f] @ x)
