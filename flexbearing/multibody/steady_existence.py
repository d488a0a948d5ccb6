"""What a failed steady solve proves: a certified turning point of the held-cage branch, and the
traction–drag bound that could prove that no steady state exists.

Two verdicts are possible for a (speed, load) where `flexbearing.multibody.steady` finds no root:

1. **A turning point (fold) of the branch** followed by the held-cage continuation in the load
   parameter lambda (the radial load and the weight scaled by lambda, `_held_cage_continuation`).
   Second-order test at the branch's last root (u_k, lambda_k) (Keller, "Numerical solution of
   bifurcation and nonlinear eigenvalue problems", in *Applications of Bifurcation Theory*, Academic
   Press 1977, pp. 359–384; Allgower & Georg, *Introduction to Numerical Continuation Methods*, SIAM
   2003, §2.3 and §8.1; Seydel, *Practical Bifurcation and Stability Analysis*, 3rd ed., Springer
   2010, §5.5). With F_u = U·S·V^T the singular value decomposition of the Jacobian there, sigma its
   smallest singular value, phi = V[:, -1] and psi = U[:, -1] its right and left singular vectors
   (psi^T·F_u·phi = sigma), the Lyapunov–Schmidt reduction of F(u, lambda) = 0 onto phi gives the
   scalar bifurcation equation, to second order in the amplitude xi of u − u_k along phi,

       g(xi, lambda) = sigma·xi + c·(lambda − lambda_k) + ½·b·xi² = 0,
       c = psi^T·F_lambda,   b = psi^T·F_uu[phi, phi],

   so along the branch lambda(xi) = lambda_k − (sigma·xi + ½·b·xi²)/c, which has its extremum at
   xi* = −sigma/b,

       lambda* = lambda_k + sigma²/(2·b·c),   a maximum where b·c > 0 (d²lambda/dxi² = −b/c).

   At an exact fold (sigma = 0) c ≠ 0 and b ≠ 0 are the two conditions of a simple quadratic turning
   point (Keller 1977, Seydel 2010 §5.5); here they are evaluated at the last root before it and the
   model's own error is measured: `quadratic_model_error` is |psi^T·F(u_k + xi*·phi, lambda_k) −
   (sigma·xi* + ½·b·xi*²)| / |½·b·xi*²|, the share of psi^T·F at the predicted turning point that
   the quadratic model misses (< 1/2: the quadratic term dominates the higher ones there, and the
   turning point is certified by the model; above it, not).

   What it proves: no root of this branch lies beyond lambda* near (u_k, lambda_k) — the held-cage
   state followed from the symmetric thrust state does not exist at the full load. What it does NOT
   prove: that no held-cage state exists at lambda = 1 on another branch (the continuation also tries
   the full load from every earlier root of the path, `_held_cage_continuation`), nor that the
   bearing has no steady running state (the cage may whirl or rattle instead of being held).

2. **The traction–drag bound** (the proof that a steady state cannot exist because the traction
   cannot carry the drag). In any steady state the angular momentum of the balls and the cage about
   the bearing axis is constant (each ball's orbit and spin are constant in the orbiting frame, whose
   turning adds nothing about e_x: `flexbearing.multibody.dynamics` docstring, the Euler equation
   about e_x is I_b·w_x' = M_x), so the moments about the axis of everything outside that system
   balance:

       sum_j (T_i,j + T_o,j) = D(omega_c) + G,

   T the traction moments of the inner and outer races on ball j, D the drag moment (churning on
   balls and cage, the guide land's Petroff torque, the EHL rolling resistance, the pocket films),
   G the weight's moment (zero for a symmetric ball set). The EHL film-shear law bounds every
   traction coefficient by mu <= gamma_L·s (its limiting shear, `flexbearing.multibody.traction`),
   so |T_i,j + T_o,j| <= gamma_L·s·(Q_i,j + Q_o,j)·r_o. A state is excluded over a range of cage
   speeds where D's lower bound there exceeds that capacity. Over the whole admissible range
   0 <= omega_c <= omega_epicyclic it never can: the land's Petroff torque is proportional to
   omega_c and the churning drag to omega_c² (flexbearing.multibody.guide_land, drag), so D(0) is
   only the rolling and pocket-film resistances, while the traction at the gross slip of a cage at
   rest is gamma_L·s·Q. The bound therefore proves non-existence only where the drag at rest
   already exceeds the traction's capacity (`traction_drag_bound`), which a lubricated bearing under
   load does not reach; where it does not fire the run is "not converged", never "no steady state".
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# the quadratic model certifies the turning point where its error there is below this share of the
# quadratic term (the cubic and higher terms of the bifurcation equation smaller than the one kept)
QUADRATIC_MODEL_ERROR_MAX = 0.5


@dataclass(frozen=True)
class TurningPoint:
    """The second-order turning-point test at a root (module docstring, item 1)."""
    lam: float                     # the root's load parameter lambda_k
    sigma_min: float               # smallest singular value of F_u (scaled unknowns and equations)
    condition: float               # sigma_max / sigma_min
    c: float                       # psi^T·F_lambda
    b: float                       # psi^T·F_uu[phi, phi]
    f_lambda_share: float          # |c| / |F_lambda|: how much of F_lambda lies outside F_u's range
    lam_star: float                # lambda_k + sigma²/(2·b·c): the extremum of lambda on the branch
    is_maximum: bool               # b·c > 0: lambda has a local maximum there
    quadratic_model_error: float   # module docstring; nan where b = 0
    certified: bool                # a maximum, below lambda = 1, with the quadratic model holding

    def describe(self) -> str:
        """One sentence: what the test found, with its numbers."""
        nums = (f"second-order test at the last root lambda = {self.lam:.4f}: smallest singular value "
                f"{self.sigma_min:.2e} (condition {self.condition:.2e}), psi^T F_lambda = {self.c:.3e} "
                f"({100 * self.f_lambda_share:.0f} % of |F_lambda|), psi^T F_uu[phi,phi] = {self.b:.3e}, "
                f"quadratic model error {self.quadratic_model_error:.2f}")
        if self.certified:
            return (f"a certified turning point: lambda reaches a maximum of {self.lam_star:.4f} < 1 on "
                    f"this branch ({nums}), so no held-cage state of this branch reaches the full load; "
                    "a state on another branch, or a cage that is not held, is not excluded")
        return f"no turning point certified ({nums})"


def turning_point(residual, lam: float, n: int, h: float = 1e-3, h_curvature: float = 1e-2,
                  h_lambda: float = 1e-3) -> TurningPoint:
    """The second-order turning-point test (module docstring, item 1) at a root v = 0 of
    residual(v, lambda) (n scaled unknowns v, n scaled equations) at lambda = lam.

    F_u by central differences of step h (the unknowns scaled so that 1 is a meaningful change, as
    `flexbearing.multibody.steady`'s Newton), F_lambda by central differences of step h_lambda (exact
    for a residual affine in lambda, as the held-cage equations are: the radial load and the weight
    enter linearly), F_uu[phi, phi] = (F(h_c·phi) + F(−h_c·phi) − 2·F(0))/h_c² (error O(h_c²))."""
    f0 = np.asarray(residual(np.zeros(n), lam), dtype=float)
    jac = np.empty((n, n))
    e = np.zeros(n)
    for k in range(n):
        e[k] = h
        jac[:, k] = (residual(e, lam) - residual(-e, lam)) / (2.0 * h)
        e[k] = 0.0
    u, s, vt = np.linalg.svd(jac)
    sigma, phi, psi = float(s[-1]), vt[-1], u[:, -1]
    f_lam = (np.asarray(residual(np.zeros(n), lam + h_lambda)) - np.asarray(residual(np.zeros(n), lam - h_lambda))) \
        / (2.0 * h_lambda)
    c = float(psi @ f_lam)
    f_uu = (np.asarray(residual(h_curvature * phi, lam)) + np.asarray(residual(-h_curvature * phi, lam)) - 2.0 * f0) \
        / h_curvature ** 2
    b = float(psi @ f_uu)
    share = abs(c) / float(np.linalg.norm(f_lam)) if np.linalg.norm(f_lam) > 0.0 else 0.0
    if b == 0.0 or c == 0.0:
        return TurningPoint(lam, sigma, float(s[0] / sigma) if sigma > 0 else math.inf, c, b, share, math.nan, False,
                            math.nan, False)
    lam_star = lam + sigma ** 2 / (2.0 * b * c)
    is_max = b * c > 0.0
    xi = -sigma / b
    g_model = sigma * xi + 0.5 * b * xi ** 2
    g_true = float(psi @ (np.asarray(residual(xi * phi, lam)) - f0))
    err = abs(g_true - g_model) / abs(0.5 * b * xi ** 2)
    certified = bool(is_max and lam_star < 1.0 and err < QUADRATIC_MODEL_ERROR_MAX)
    return TurningPoint(lam, sigma, float(s[0] / sigma) if sigma > 0 else math.inf, c, b, share, float(lam_star),
                        bool(is_max), float(err), certified)


@dataclass(frozen=True)
class TractionDragBound:
    """The traction–drag bound (module docstring, item 2) evaluated at a state."""
    traction_capacity: float       # gamma_L·s·sum_j (Q_i,j + Q_o,j)·r_o, N·m: the most the races can drive
    drag_at_state: float           # the drag moment about the axis at the evaluated state, N·m
    drag_lower_bound: float        # a lower bound of the drag over 0 <= omega_c <= omega_epicyclic, N·m
    proves_no_steady_state: bool   # drag_lower_bound > traction_capacity

    def describe(self) -> str:
        if self.proves_no_steady_state:
            return (f"no steady state: the drag moment about the axis is at least {self.drag_lower_bound:.3g} N·m "
                    f"at every cage speed, above the {self.traction_capacity:.3g} N·m the races' traction can "
                    "carry (mu <= gamma_L·s)")
        ratio = self.traction_capacity / self.drag_at_state if self.drag_at_state > 0.0 else math.inf
        return (f"the traction–drag bound does not exclude a state: the races' traction can carry up to "
                f"{self.traction_capacity:.3g} N·m about the axis (mu <= gamma_L·s), {ratio:.3g} times the drag "
                f"moment at the solver's end state ({self.drag_at_state:.3g} N·m), and the drag falls towards "
                f"{self.drag_lower_bound:.3g} N·m as the cage slows (Petroff ∝ omega_c, churning ∝ omega_c²)")


def traction_drag_bound(traction_coefficient_max: float, inner_loads, outer_loads, outer_radius: float,
                        drag_at_state: float, drag_at_rest: float = 0.0) -> TractionDragBound:
    """The bound of the module docstring, item 2: capacity = mu_max·sum_j (Q_i,j + Q_o,j)·r_o (N·m; the
    inner loads of both half-grooves summed per ball), against the drag moment about the axis at
    the state (drag_at_state) and its lower bound over the cage-speed range, the drag at rest
    (drag_at_rest: 0 unless the caller bounds the rolling and pocket-film resistances from below)."""
    q = float(np.sum(np.abs(inner_loads)) + np.sum(np.abs(outer_loads)))
    cap = float(traction_coefficient_max) * q * float(outer_radius)
    lower = max(0.0, float(drag_at_rest))
    return TractionDragBound(cap, float(abs(drag_at_state)), lower, bool(lower > cap))
