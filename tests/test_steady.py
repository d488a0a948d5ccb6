"""Steady running state of a thrust-loaded bearing (multibody/steady.py).

Reference: the dynamics itself, integrated from a different start. The paper bearing under 55 kN
axial load at 14,000 rpm (no radial load, no gravity) settles within 0.1 s; the time-averaged
cage speed and ball angular velocity of that run (measured: cage 656.84–657.26 rad/s over
0.05–0.1 s, oscillating with the cage's axial motion; ball 0 w = (−4852, 1363, −195) rad/s) must
equal the fixed point (656.92 rad/s; (−4849, 1369, −195) rad/s) within the run's own oscillation,
5e-4 on the cage speed and 1 % on the ball's spin components. Integrating from the fixed point
must stay there (cage speed within 1e-4 over 20 ms): it is an equilibrium of the integrated
equations, not only a root of the residual.
"""
import math

import numpy as np
import pytest

from mesh.validation import InputError
from multibody import dynamics as D
from multibody import integrator as I
from multibody import model as M
from multibody.bearing import PAPER_BEARING, PAPER_OIL
from multibody.initial import initial_state
from multibody.model import build_model
from multibody.steady import steady_thrust_state

W = 14000 * math.pi / 30
FA = 55e3
SP = np.array([[0.0, W]])
LD = np.array([[0.0, FA, 0.0, 0.0]])
IMP = np.zeros((0, 6))


@pytest.fixture(scope="module")
def paper():
    model = build_model(PAPER_BEARING, PAPER_OIL, {})
    y, info = steady_thrust_state(model, W, FA)
    return model, y, info


def _run(model, y, t_end, t_avg):
    c0 = M.state_layout(model)["cage"]
    ws = I.Workspace(model)
    t, h = 0.0, 1e-7
    cage, ball = [], []
    for k in range(1, int(round(t_end / 1e-3)) + 1):
        y, t, h, _, _ = I.advance(model, y, t, k * 1e-3, SP, LD, IMP, I.DEFAULT_TOL, h, ws)
        if t >= t_avg - 1e-12:
            cage.append(y[c0 + 9])
            ball.append(y[6:9].copy())
    return np.array(cage), np.array(ball)


def test_fixed_point_is_found_and_is_an_equilibrium_of_the_dynamics(paper):
    model, y, info = paper
    assert info["converged"] and info["residual"] < 1e-10
    # the balls drive the cage against its drag: each ball sits ahead of its pocket centre
    assert info["pocket_offset"] > 0.0
    cage, _ = _run(model, y.copy(), 0.02, 0.0)
    assert np.max(np.abs(cage / info["cage_speed"] - 1.0)) < 1e-4


def test_fixed_point_equals_the_settled_dynamics_from_the_quasi_static_start(paper):
    model, y, info = paper
    cage, ball = _run(model, initial_state(model, W, FA, 0.0), 0.1, 0.05)
    assert abs(np.mean(cage) / info["cage_speed"] - 1.0) < 5e-4
    w_fixed = np.array([info["ball_w_x"], info["ball_w_r"], info["ball_w_t"]])
    np.testing.assert_allclose(ball.mean(axis=0), w_fixed, rtol=0, atol=1e-2 * abs(w_fixed[0]))
    # the free ball's spin axis is pitched (w_r) and yawed (w_t): no race-control hypothesis was made
    assert abs(w_fixed[1]) > 0.1 * abs(w_fixed[0]) and w_fixed[2] != 0.0


def test_weight_is_refused():
    model = build_model(PAPER_BEARING, PAPER_OIL, {"gravity": 9.81})
    with pytest.raises(InputError, match="gravity"):
        steady_thrust_state(model, W, FA)
