"""Steady running state of a thrust-loaded bearing: the fixed point of the dynamics' own equations.

Under a pure axial load, without gravity and with the cage centred, every ball meets the same
loads at every azimuth, so the steady state is the same for all balls and constant in the frame
that turns with the cage. It is found directly instead of by integrating until the transients
have died (which at light load and high speed takes the dynamics 5–15 s of simulated time:
benchmarks/results/slip_rate.md, "Long runs").

Unknowns (9): ball centre x, r in its plane; the ball's azimuth relative to its pocket centre
(the ball presses on the pocket wall to push the cage against its drag); the common orbital
speed = cage speed; the ball's absolute angular velocity (3 components in (e_x, e_r, e_t)); the
inner ring's axial position; the cage's axial position. Equations (9): the corresponding
accelerations of `multibody.dynamics.rhs` vanish (ball x, r, orbit and three angular
accelerations; ring axial; cage spin; cage axial), each scaled to a force per ball. Solved by
MINPACK's hybrid Powell method (scipy.optimize.root "hybr"), Levenberg–Marquardt as fallback,
from the quasi-static start (`multibody.initial.initial_state`) with the ball against the
driving side of its pocket.

This is Harris's skidding analysis of a thrust-loaded angular-contact ball bearing (T. A. Harris,
"An analytical method to predict skidding in thrust-loaded, angular-contact ball bearings",
J. Lubr. Technol. 93(1):17–24, 1971), made with the dynamics' own force models: the ball spin
follows from the traction at both contacts (no race-control hypothesis), with churning drag,
pocket and guide-land forces. The result is a state vector y of the dynamics: integrating from it
stays there (tests/test_steady.py), and a run started from it needs no settling.

Limits: a fixed point exists only where the traction can balance the drag at some skid; where the
traction law is flat over the slips involved (the 4106 fit's dead zone at light loads,
multibody.traction "Origin law") the equations are singular and no root is found — `converged`
is False and the dynamics must be integrated instead. Measured on the slip-rate cases (validation
oil state, Fr and gravity left out; benchmarks/bench_steady.py): roots for cases 4, 5, 6, 10, 11,
14, 15, none for 1–3, 7–9, 12, 13; 0.3–0.5 s each, most of it the quasi-static start (the root
search itself 20–40 ms). The fixed point has a centred cage. Whether the dynamics stay there is a
separate question: with the weight on (the slip validation) they settle within 0.3 points of it
(cases 5, 6); without it, at light load, the outer-ring-guided cage whirls out to its rim
(tests/test_cage_whirl.py) and the skid changes (case 4, 15 s: cage 198 against 267 rad/s).
"""
from __future__ import annotations

import math

import numpy as np

from mesh.validation import InputError, require_range
from multibody import dynamics as D
from multibody import model as M
from multibody.initial import initial_state

UNKNOWNS = ("ball_x", "ball_r", "pocket_offset", "orbit_speed", "ball_w_x", "ball_w_r", "ball_w_t",
            "ring_x", "cage_x")


def steady_thrust_state(model, speed_rad_s: float, axial_load: float, y_start: np.ndarray | None = None,
                        tol: float = 1e-10) -> tuple[np.ndarray, dict]:
    """(y, info): the steady state (module docstring) at inner-ring speed speed_rad_s (rad/s) and
    axial load axial_load (N, along +X), as a full state vector of `model` (multibody.model layout,
    ball j at azimuth 2·pi·j/Z + pocket_offset, cage angle 0). info: converged, residual (max scaled
    residual, N per ball), cage_speed (rad/s), slip_rate ((nm − nc)/nm, nm at the mean loaded
    contact angle, the paper's definition), the unknowns by name, nfev, and outputs (the
    multibody.dynamics.evaluate_outputs dict of y). tol: residual tolerance relative to the axial
    load per ball."""
    require_range("steady.speed_rad_s", speed_rad_s, 0.0, 1e5, lo_open=True, unit="rad/s")
    require_range("steady.axial_load", abs(axial_load), 0.0, 1e7, lo_open=True, unit="N")
    p = model.p
    if p[M.P_GRAV] != 0.0:
        raise InputError(f"model.gravity = {p[M.P_GRAV]} m/s^2: the steady thrust state needs 0 "
                         "(with weight the balls differ by azimuth and there is no common steady state)")
    from scipy.optimize import root

    z = model.n_balls
    lay = M.state_layout(model)
    r0, c0 = lay["ring"], lay["cage"]
    speed_table = np.array([[0.0, speed_rad_s]])
    load_table = np.array([[0.0, axial_load, 0.0, 0.0]])
    impacts = np.zeros((0, 6))
    work = D.new_work(model)
    y0 = initial_state(model, speed_rad_s, axial_load, 0.0) if y_start is None else np.asarray(y_start, float)
    dydt = np.zeros_like(y0)
    # start: quasi-static ball, displaced towards the pocket side that drives the cage (the pocket
    # force is the soft linear Kc·z inside the clearance, paper §2.3.1; starting at the centre, where
    # it vanishes, slows the search at light loads)
    u0 = np.array([y0[0], y0[1], 0.6 * p[M.P_CP] / p[M.P_RCAGE_POCKET], y0[5], y0[6], y0[7], y0[8],
                   y0[r0], y0[c0]])
    w_ball = abs(y0[6]) + abs(y0[7]) + 1.0
    scale_u = np.array([1e-6, 1e-6, 1e-4, 1e-3 * abs(y0[5]) + 1e-3, 1e-3 * w_ball, 1e-3 * w_ball,
                        1e-3 * w_ball, 1e-6, 1e-6])
    # accelerations -> forces per ball (N), relative to the axial load per ball
    half_dw, half_dm = 0.5 * p[M.P_DW], 0.5 * p[M.P_DM]
    scale_r = np.array([p[M.P_MB], p[M.P_MB], p[M.P_MB] * half_dm, p[M.P_IB] / half_dw, p[M.P_IB] / half_dw,
                        p[M.P_IB] / half_dw, p[M.P_MI] / z, p[M.P_ICP] / half_dm / z, p[M.P_MC] / z])
    scale_r /= abs(axial_load) / z

    def state(v):
        u = u0 + v * scale_u
        y = np.zeros_like(y0)
        for j in range(z):
            y[9 * j:9 * j + 9] = (u[0], u[1], 2.0 * math.pi * j / z + u[2], 0.0, 0.0, u[3], u[4], u[5], u[6])
        y[r0] = u[7]
        y[c0] = u[8]
        y[c0 + 9] = u[3]                # the cage turns with the balls
        return y

    def residual(v):
        y = state(v)
        D.rhs(0.0, y, dydt, p, model.flags, model.hertz_table, model.traction_table, speed_table, load_table,
              impacts, work, model.cage)
        return scale_r * np.array([dydt[3], dydt[4], dydt[5], dydt[6], dydt[7], dydt[8], dydt[r0 + 5],
                                   dydt[c0 + 9], dydt[c0 + 6]])

    sol = root(residual, np.zeros(9), method="hybr", options=dict(xtol=1e-12))
    nfev = sol.nfev
    if np.max(np.abs(sol.fun)) > tol:
        sol = root(residual, sol.x, method="lm", options=dict(xtol=1e-14, ftol=1e-14))
        nfev += sol.nfev
    y = state(sol.x)
    res = float(np.max(np.abs(sol.fun)))
    out = D.evaluate_outputs(model, 0.0, y, speed_table, load_table, impacts)
    info = dict(converged=bool(res <= tol), residual=res, cage_speed=float(y[c0 + 9]),
                slip_rate=float(out["slip_rate"]), nfev=int(nfev))
    info.update(zip(UNKNOWNS, (u0 + sol.x * scale_u).tolist()))
    info["outputs"] = out
    return y, info
