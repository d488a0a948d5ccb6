"""The steady solve started from the settled dynamics (flexbearing.multibody.steady_settle) and its
use as the thrust state's last fallback (flexbearing.multibody.steady._thrust_state_from_dynamics)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from flexbearing.multibody.steady_settle import settle_then_solve

# a damped oscillator x'' = −atan(x − 1) − C·x' with a stiff first-order lag w' = −K·(w − x): its only
# fixed point is x = w = 1, v = 0, stable (eigenvalues of the linearisation: −C/2 ± i·sqrt(1 − C²/4), −K)
C, K = 0.5, 1000.0
# Newton on atan(x − 1) = 0 converges only for |x − 1| < 1.3917452 (the root of 2x = (1 + x²)·atan x)
NEWTON_RADIUS = 1.3917452


def _flow(y, t0, t1):
    rhs = lambda t, u: [u[1], -math.atan(u[0] - 1.0) - C * u[1], -K * (u[2] - u[0])]
    return solve_ivp(rhs, (t0, t1), y, method="Radau", rtol=1e-8, atol=1e-10).y[:, -1]


def _newton(x, w, tol=1e-12, max_iter=50):
    """Newton on the fixed-point equations (accelerations at v = 0): atan(x − 1) = 0, K·(w − x) = 0.
    (x, w) or None where it does not converge."""
    for _ in range(max_iter):
        f = np.array([math.atan(x - 1.0), K * (w - x)])
        if max(abs(f)) <= tol:
            return x, w
        jac = np.array([[1.0 / (1.0 + (x - 1.0) ** 2), 0.0], [-K, K]])
        x, w = np.array([x, w]) - np.linalg.solve(jac, f)
        if not (math.isfinite(x) and abs(x) < 1e6):
            return None
    return None


def test_plain_newton_from_the_start_diverges_but_the_settled_start_converges():
    y0 = np.array([4.0, 0.0, 0.0])                  # x, v, w: outside Newton's basin (|x − 1| = 3)
    assert _newton(y0[0], y0[2]) is None
    found = settle_then_solve(_flow, lambda y: _newton(y[0], y[2]), y0, chunk=1.0, max_chunks=40)
    assert found.root is not None
    x, w = found.root
    # Newton's last step from residual <= 1e-12: |dx| <= |J^-1|·1e-12 with |d atan/dx| = 1 at the root,
    # and w − x = f_w/K
    assert abs(x - 1.0) <= 2e-12 and abs(w - 1.0) <= 2e-12
    # it converged only once the dynamics had brought x inside Newton's basin, which takes more than
    # the first chunk from x = 4 (the restoring force is bounded by pi/2)
    assert found.chunks > 1 and abs(found.state[0] - 1.0) < NEWTON_RADIUS


def test_without_a_fixed_point_no_root_after_the_last_chunk():
    drift = lambda y, t0, t1: y + (t1 - t0)         # y' = 1: no fixed point
    found = settle_then_solve(drift, lambda y: None, np.zeros(2), chunk=0.5, max_chunks=4)
    assert found.root is None and found.chunks == 4 and found.settled_time == pytest.approx(2.0, rel=1e-15)
    assert np.array_equal(found.state, np.full(2, 2.0))


def test_bad_chunk_is_refused():
    with pytest.raises(ValueError, match="chunk"):
        settle_then_solve(lambda y, a, b: y, lambda y: None, np.zeros(1), chunk=0.0, max_chunks=3)


@pytest.mark.slow
def test_cold_oil_study_run_without_a_thrust_root_in_reach_converges_from_the_settled_dynamics():
    """Point 5 of the uncertainty study, slip-rate case 11 (Fa 1500 N, Fr 500 N, 10,000 rpm, oil at
    62 °C): neither the thrust state from the quasi-static start nor its speed continuation nor the
    held-cage solve from the quasi-static balls converges; the thrust state from the thrust-only
    dynamics settled for a few hundredths of a second does, and the held-cage continuation goes on
    from it to the full load. The end state must be a root (the residual of the held-cage
    equations, re-evaluated at it) and the cage must lag its epicyclic speed (the traction drives
    it against its drag: 0 < cage speed < nominal). ~10–15 CPU-s: slow."""
    from flexbearing.multibody import model as M
    from flexbearing.multibody import steady as S
    from flexbearing.studies.uncertainty import case_problem, load_unknowns, sample_points
    from flexbearing.studies.validation import slip_rate as V
    point = sample_points(load_unknowns("scenes/slip_rate_unknowns.toml"))[5]
    model, omega, load = case_problem(point, V.slip_rate_cases()[10])
    load = np.array(load)
    p = model.p.copy()
    p[M.P_GRAV] = 0.0
    assert S._thrust_state_by_speed(model._replace(p=p), omega, load[0]) is None     # today's path fails
    s = S._thrust_state_from_dynamics(model._replace(p=p), omega, load[0])
    assert s is not None and s["converged"] and s["residual"] <= 1e-10
    assert 0.0 < s["settled_time"] <= S.SETTLE_CHUNK * S.SETTLE_CHUNKS
    _, info = S.steady_held_cage_state(model, omega, load, strict=False)
    assert info["converged"] and info["continuation"][-1] == 1.0
    residual = S._held_cage_equations(model, omega, load, 0.0, info["unknowns"])[0]
    assert np.max(np.abs(residual(np.zeros(6 * model.n_balls + 11)))) <= 1e-9
    assert 0.0 < info["cage_speed"] < float(info["outputs"]["nominal_cage_speed"])
