"""The ball-pass periodic orbit by shooting (flexbearing.multibody.steady_periodic) on analytic systems."""
import math

import numpy as np
import pytest

from flexbearing.multibody import state_layout as SL
from flexbearing.multibody.steady_periodic import (Shooting, ball_pass_shift, fixed_step_flow, floquet_multipliers,
                                                    shoot, slot_name)

# Hopf normal form z' = (mu + i omega) z − (1 − i b)|z|² z: in polar form r' = r(mu − r²), theta' = omega + b r²,
# the circle r = sqrt(mu) is an orbit of angular speed omega + b mu; with the rotation by 2 pi/Z as the symmetry S
# it returns after T = (2 pi/Z)/(omega + b mu), and its nontrivial Floquet multiplier (P^-1 M over T) is
# exp(-2 mu T) (the radial variation d(dr)/dt = (mu − 3 r²) dr = −2 mu dr), the trivial one 1 (Seydel 2010, §7.2).
MU, OMEGA, B, Z = 0.5, 2.0, 1.0, 3


def _hopf(y):
    x, v = y
    r2 = x * x + v * v
    return np.array([MU * x - OMEGA * v - r2 * (x + B * v), MU * v + OMEGA * x - r2 * (v - B * x)])


def _rotation(y):
    c, s = math.cos(2 * math.pi / Z), math.sin(2 * math.pi / Z)
    return np.array([c * y[0] - s * y[1], s * y[0] + c * y[1]])


def _solve(n_steps):
    problem = Shooting(flow=fixed_step_flow(_hopf, n_steps), shift=_rotation, scale=np.ones(2),
                       fixed=np.array([1]), ignored=np.array([], dtype=int))     # phase condition: y(0) = 0
    sol = shoot(problem, np.array([1.1, 0.0]), 0.8 * 2 * math.pi / Z / (OMEGA + B * MU), tol=1e-12)
    _, yT = problem.residual(sol["y"], sol["period"])
    mon, pm, _ = problem.linearisation(sol["y"], sol["period"], yT)
    return sol, floquet_multipliers(mon, pm)


def test_shooting_finds_the_hopf_orbit_its_period_and_floquet_multipliers():
    period = 2 * math.pi / Z / (OMEGA + B * MU)
    errors = []
    for n in (8, 16):
        sol, (mu, k) = _solve(n)
        assert sol["converged"] and sol["residual"] <= 1e-12
        errors.append((abs(sol["period"] - period) / period, abs(sol["y"][0] - math.sqrt(MU))))
    # the discretisation's error of a 5th-order method falls 2^5 = 32 times per halving of the step; the
    # fine one lies below (h·|lambda|)^5 with h|lambda| = T/16·(omega + b mu + 2 mu) ~ 0.13 (local error bound)
    h_lam = period / 16 * (OMEGA + B * MU + 2 * MU)
    for e_coarse, e_fine in zip(*errors):
        assert e_fine <= h_lam ** 5 and (e_fine == 0.0 or e_coarse / e_fine > 16.0)
    # multipliers: the trivial one is 1 and the radial one exp(-2 mu T), to the forward differences' error
    # O(FD_STEP · |second derivative|) ~ 1e-6 plus the RK error above
    assert abs(mu[k] - 1.0) < 1e-5
    assert abs(np.delete(mu, k)[0] - math.exp(-2 * MU * period)) < 1e-5


def test_the_ball_pass_shift_moves_each_ball_into_its_neighbours_place():
    z, c0 = 4, SL.cage_offset(4)
    n = SL.state_size(z, 0)
    y = np.arange(n, dtype=float) * 0.01
    pitch = 2 * math.pi / z
    for j in range(z):           # azimuths of a cage already turned three times, pocket j at 0.1 + j·pitch
        y[SL.ball_offset(j) + SL.BALL_PSI] = 0.1 + j * pitch + 6 * math.pi + 0.003 * j
    y[c0 + SL.CAGE_PHI] = 0.1 + 6 * math.pi
    for d in (1, -1):
        s = ball_pass_shift(y, z, d, c0)
        for j in range(z):
            src, o = SL.ball_offset((j + d) % z), SL.ball_offset(j)
            mask = np.arange(SL.BALL_STATE) != SL.BALL_PSI
            assert np.array_equal(s[o:o + SL.BALL_STATE][mask], y[src:src + SL.BALL_STATE][mask])
            # the neighbour's azimuth, wrapped to lie one pitch ahead (d = 1) or behind (d = -1) of ball j
            want = y[src + SL.BALL_PSI] + (2 * math.pi if j + d >= z else -2 * math.pi if j + d < 0 else 0.0)
            assert s[o + SL.BALL_PSI] == pytest.approx(want, abs=1e-12)
            assert abs(s[o + SL.BALL_PSI] - y[o + SL.BALL_PSI] - d * pitch) < 0.01
        assert s[c0 + SL.CAGE_PHI] == pytest.approx(y[c0 + SL.CAGE_PHI] + d * pitch, abs=1e-12)
        assert np.array_equal(s[SL.ring_offset(z):c0], y[SL.ring_offset(z):c0])


@pytest.mark.slow
def test_the_fixed_step_flow_of_the_bearing_agrees_with_the_adaptive_integrator():
    """bearing_flow (N fixed Dormand–Prince steps over one ball-pass period) against the project's adaptive
    integrator at tol 1e-10 from the held-cage state of the clearance-free paper bearing (Fr 4 kN): they
    differ by the fixed-step discretisation error, which the step doubling estimates (|Phi_N − Phi_2N| is
    that error to within a factor 1 + 2^-p); the FSAL-pair arithmetic itself is checked on the Hopf orbit."""
    from flexbearing.multibody import integrator as I
    from flexbearing.multibody.bearing import PAPER_BEARING, PAPER_OIL
    from flexbearing.multibody.model import build_model
    from flexbearing.multibody.steady import steady_held_cage_state
    from flexbearing.multibody.steady_periodic import _first_guess, _normalised, _orbit_scale, bearing_flow
    w, load = 14000 * math.pi / 30, np.array([55e3, 0.0, -4e3])
    model = build_model(PAPER_BEARING.with_(radial_clearance=0.0), PAPER_OIL, {})
    y, _ = steady_held_cage_state(model, w, load)
    y = _normalised(model, y)
    period, n_steps, _ = _first_guess(model, w, load, y)
    scale = _orbit_scale(model, y)
    fixed = bearing_flow(model, w, load, n_steps)(y, period)
    fine = bearing_flow(model, w, load, 2 * n_steps)(y, period)
    adaptive, *_ = I.advance(model, y.copy(), 0.0, period, np.array([[0.0, w]]), np.array([[0.0, *load]]),
                             np.zeros((0, 6)), tol=1e-10)
    err_estimate = np.max(np.abs(fixed - fine) / scale)
    assert np.max(np.abs(fixed - adaptive) / scale) <= 2.0 * err_estimate + 1e-4   # 1e-4: the tol-1e-10 run's own error


def test_slot_names_follow_the_state_layout():
    z = 3
    assert slot_name(z, SL.ball_offset(2) + SL.BALL_PSI) == "ball 2 azimuth"
    assert slot_name(z, SL.ring_offset(z) + SL.RING_TILT_Y_DOT) == "inner ring tilt y'"
    assert slot_name(z, SL.cage_offset(z) + SL.CAGE_OMEGA) == "cage speed"
    assert slot_name(z, SL.cage_offset(z) + SL.CAGE_TILT_Z_DOT) == "cage tilt z'"
