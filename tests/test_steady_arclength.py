"""Pseudo-arclength continuation (flexbearing.multibody.steady_arclength) against analytic S-curves,
and on an uncertainty-study run whose natural continuation stops at a fold (slow)."""
import math

import numpy as np
import pytest

from flexbearing.multibody.steady_arclength import pseudo_arclength

K = 1.0   # F(u, lambda) = u³ − u + K·(lambda − ½): lambda(u) = ½ − (u³ − u)/K


def s_curve(v, lam):
    return np.array([v[0] ** 3 - v[0] + K * (lam - 0.5)])


def natural_continuation(residual, v, lam, step=0.05, min_step=1.0 / 1024):
    """lambda stepped up, Newton at each lambda from the last root: where it stops."""
    while lam < 1.0:
        trial, u = min(1.0, lam + step), v.copy()
        for _ in range(30):
            f = residual(u, trial)
            j = (residual(u + 1e-6, trial) - residual(u - 1e-6, trial)) / 2e-6
            u = u - f / j
        if abs(residual(u, trial)[0]) < 1e-12 and abs(u[0] - v[0]) < 0.5:
            lam, v, step = trial, u, step * 1.5
        else:
            step *= 0.5
            if step < min_step:
                return lam
    return lam


def test_arclength_passes_both_folds_of_an_s_curve_and_reaches_the_far_part():
    # the folds of lambda(u): dlambda/du = −(3u² − 1)/K = 0 at u = ±1/sqrt(3), lambda = ½ ± 2/(3·sqrt(3)·K)
    u_fold = 1.0 / math.sqrt(3.0)
    lam_max, lam_min = 0.5 + 2.0 / (3.0 * math.sqrt(3.0) * K), 0.5 - 2.0 / (3.0 * math.sqrt(3.0) * K)
    # the root at lambda = 0: u³ − u = K/2, the only real one (u > 1/sqrt(3))
    u0 = max(r.real for r in np.roots([1.0, 0.0, -1.0, -0.5 * K]) if abs(r.imag) < 1e-12)
    lam_stop = natural_continuation(s_curve, np.array([u0]), 0.0)
    assert lam_max - 1.0 / 512 < lam_stop <= lam_max          # the natural continuation stops at the fold
    res = pseudo_arclength(s_curve, np.array([u0]), 0.0, direction=np.array([-1.0, 1.0]), ds=0.05, ds_min=1e-6,
                           tol=1e-12, h=1e-6, h_lambda=1e-6)
    assert res.reached and res.lam == 1.0
    u1 = res.v[0]
    assert abs(s_curve(res.v, 1.0)[0]) <= 1e-12
    # the far part of the S: below the lower fold u < −1/sqrt(3); the root of u³ − u + K/2 = 0 there
    exact = min(r.real for r in np.roots([1.0, 0.0, -1.0, 0.5 * K]) if abs(r.imag) < 1e-12)
    assert u1 < -u_fold
    assert abs(u1 - exact) <= 1e-10 * abs(exact)
    assert len(res.turning_points) == 2
    # the turning points are recorded at accepted points next to the folds: within one step of them
    assert abs(res.turning_points[0] - lam_max) < 0.05 and abs(res.turning_points[1] - lam_min) < 0.05
    assert min(res.lam_path) < lam_min + 0.05


def test_arclength_reports_a_branch_that_turns_back_without_reaching_the_target():
    # a closed branch u² + (lambda − 0.4)² = 0.25·... : a circle of radius 0.3 about (0, 0.4): lambda ≤ 0.7
    def circle(v, lam):
        return np.array([v[0] ** 2 + (lam - 0.4) ** 2 - 0.09])
    res = pseudo_arclength(circle, np.array([-0.3]), 0.4, direction=np.array([1.0, 1.0]), ds=0.02, ds_min=1e-6,
                           tol=1e-12, h=1e-6, h_lambda=1e-6, lam_min=0.2)
    assert not res.reached
    assert "below lambda" in res.stop
    assert res.turning_points and abs(res.turning_points[0] - 0.7) < 0.02
    assert max(res.lam_path) <= 0.7 + 1e-9
    assert abs(circle(res.v, res.lam)[0]) <= 1e-12


def test_two_unknown_s_curve():
    # u = (a, b): a³ − a + (lambda − ½) = 0, b − a² = 0 (a second unknown slaved to the first)
    def f(v, lam):
        return np.array([v[0] ** 3 - v[0] + (lam - 0.5), v[1] - v[0] ** 2])
    a0 = max(r.real for r in np.roots([1.0, 0.0, -1.0, -0.5]) if abs(r.imag) < 1e-12)
    res = pseudo_arclength(f, np.array([a0, a0 ** 2]), 0.0, direction=np.array([-1.0, -2 * a0, 1.0]), ds=0.05,
                           ds_min=1e-6, tol=1e-12, h=1e-6, h_lambda=1e-6)
    assert res.reached
    assert np.max(np.abs(f(res.v, 1.0))) <= 1e-12
    assert res.v[0] < -1.0 / math.sqrt(3.0)


@pytest.mark.slow
def test_uncertainty_run_whose_branch_folds_below_the_full_load_is_followed_round_its_s_bend():
    """Point 35 of the uncertainty study, slip-rate case 3: the natural continuation in lambda stops at a
    certified fold at lambda* = 0.9986, just below the full load. The branch is S-shaped: followed by
    pseudo-arclength continuation it turns back at the fold, turns again at a lower fold and then
    passes lambda = 1, where the held-cage solve converges. 60–110 CPU-s: slow."""
    from flexbearing.multibody.steady import steady_held_cage_state
    from flexbearing.studies.uncertainty import case_problem, load_unknowns, sample_points
    from flexbearing.studies.validation import slip_rate as V
    point = sample_points(load_unknowns("scenes/slip_rate_unknowns.toml"))[35]
    _, info = steady_held_cage_state(*case_problem(point, V.slip_rate_cases()[2]), strict=False)
    assert info["converged"], info["reason"]
    assert info["residual"] <= 1e-9
    arc = info["arclength"]
    assert arc.reached and arc.lam == 1.0
    # an S: a maximum of lambda below 1, then a minimum below it, then lambda rises through 1
    assert len(arc.turning_points) == 2
    assert arc.turning_points[1] < arc.turning_points[0] < 1.0
    assert min(arc.lam_path) < arc.turning_points[0]
    assert info["continuation"][-1] == 1.0
    assert -0.5 < info["outputs"]["slip_rate"] < 0.5


def test_reduced_slope_is_the_derivative_along_the_slaved_manifold():
    # F(x, y) = (x − y², y − 2x): with y slaved by F_2 = 0 (y = 2x), F_1(x) = x − 4x², dF_1/dx = 1 − 8x;
    # at (x, y) = (0.5, 1): 1 − 4 = −3, and det J / det J_ff = (1·1 − (−2y)(−2))/1 = 1 − 4y = −3
    from flexbearing.multibody.steady_arclength import reduced_slope
    x, y = 0.5, 1.0
    jac = np.array([[1.0, -2.0 * y], [-2.0, 1.0]])
    # exact: J_ff = 1, the solve −2/1 and the product (−2)(−2) are small integers, no rounding anywhere
    assert reduced_slope(jac, 0) == 1.0 - 8.0 * x
    # a 3×3 check against det J / det J_ff
    rng = np.random.default_rng(3)
    a = rng.normal(size=(3, 3)) + 3.0 * np.eye(3)
    ff = np.delete(np.delete(a, 1, 0), 1, 1)
    assert abs(reduced_slope(a, 1) - np.linalg.det(a) / np.linalg.det(ff)) <= 1e-12 * abs(np.linalg.det(a))


def test_whirl_ratio_of_a_held_centre_and_of_a_half_frequency_whirl():
    # W = [phi(t1) − phi(t0)] / ∫ omega_c dt: a centre orbiting at half the cage speed gives 0.5 exactly
    # (phi linear in t, omega_c constant: the trapezoidal rule is exact); a centre at rest gives 0
    from flexbearing.multibody.steady_hold import whirl_ratio
    t = np.linspace(0.0, 0.03, 151)
    omega_c = 300.0
    e = 60e-6
    circle = np.column_stack([e * np.cos(0.5 * omega_c * t + 0.3), e * np.sin(0.5 * omega_c * t + 0.3)])
    assert abs(whirl_ratio(t, circle, np.full_like(t, omega_c)) - 0.5) <= 1e-12
    still = np.tile([40e-6, -20e-6], (t.size, 1))
    assert whirl_ratio(t, still, np.full_like(t, omega_c)) == 0.0
    # backward whirl is negative; a cage speed that ramps linearly is integrated exactly
    ramp = np.linspace(200.0, 400.0, t.size)
    theta = 200.0 * t + 0.5 * (200.0 / 0.03) * t ** 2
    back = np.column_stack([e * np.cos(-0.5 * theta), e * np.sin(-0.5 * theta)])
    assert abs(whirl_ratio(t, back, ramp) + 0.5) <= 1e-12


@pytest.mark.slow
def test_uncertainty_run_with_two_roots_reports_the_held_one():
    """Point 45, slip-rate case 6: the held-cage equations have two roots at the full load (slip −5.1 %
    on an earlier path, +52 % on today's), both with residual < 1e-10. From the −5.1 % root the cage
    whirls at half its speed (whirl ratio 0.52, eccentricity 0.20 -> 0.74 in 30 ms); from the +52 %
    root it stays held. The solver's root must carry the dynamic check, and be the held one."""
    from flexbearing.multibody.steady import steady_held_cage_state
    from flexbearing.studies.uncertainty import case_problem, load_unknowns, sample_points
    from flexbearing.studies.validation import slip_rate as V
    point = sample_points(load_unknowns("scenes/slip_rate_unknowns.toml"))[45]
    _, info = steady_held_cage_state(*case_problem(point, V.slip_rate_cases()[5]), strict=False)
    assert info["converged"] and info["residual"] <= 1e-9
    assert info["held"] and info["cage_hold"].held, info["cage_hold"].describe()


def test_arclength_stops_where_the_branch_closes_on_itself():
    # the circle u² + (lambda − 0.4)² = 0.09 with no lower bound in reach: round once, two turns
    # (lambda = 0.7 and 0.1), back at the first point
    def circle(v, lam):
        return np.array([v[0] ** 2 + (lam - 0.4) ** 2 - 0.09])
    res = pseudo_arclength(circle, np.array([-0.3]), 0.4, direction=np.array([1.0, 1.0]), ds=0.02, ds_min=1e-6,
                           tol=1e-12, h=1e-6, h_lambda=1e-6, lam_min=-1.0)
    assert res.closed and not res.reached
    assert abs(res.turning_points[0] - 0.7) < 0.02 and abs(res.turning_points[1] - 0.1) < 0.02
    assert abs(res.lam - 0.4) < 0.05 and max(res.lam_path) <= 0.7 + 1e-9
