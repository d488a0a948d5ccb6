"""The starts of a search for other held-cage roots (`flexbearing.multibody.steady_root_search`, and the
solver's last attempt in `flexbearing.multibody.steady`): a grid over the physical range of the cage
speed with each ball's spin from a pure-rolling law and its pocket offset against either wall, and a
start read off a state of the dynamics.

Pure rolling of a ball on a race (no slip at the contact; Harris & Kotzalas, *Rolling Bearing
Analysis*, 5th ed., CRC 2007, ch. 8 "Bearing kinematics"): the contact point's velocity is the race's.
On the outer race, at rest, v_centre + omega_b × rho_o = 0 with v_centre = omega_c × r_centre, so the
ball's angular velocity omega_b is proportional to the cage speed omega_c for a fixed contact
geometry. On the inner race, turning at omega_i about e_x, the same holds in the race's frame:
omega_b − omega_i·e_x is proportional to omega_c − omega_i. A start at cage speed omega_c scales a
reference state's spins (u_ref, at cage speed omega_ref) by either law:

    outer:  omega_b = omega_b,ref · omega_c / omega_ref
    inner:  omega_b = omega_i·e_x + (omega_b,ref − omega_i·e_x) · (omega_i − omega_c) / (omega_i − omega_ref)
"""
from __future__ import annotations

import math

import numpy as np

from flexbearing.multibody import model as M

# the starts' cage speeds, as fractions of the inner-ring speed: the epicyclic (pure-rolling) cage
# speed is 0.40-0.46 of it for the study's bearing (Dw·cos(alpha)/dm 0.08-0.2), and the study's slips
# (-8 % to +70 %) put omega_c between 0.13 and 0.50 of it; the grid covers 0.05-0.8
START_FRACTIONS = (0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5, 0.6, 0.7, 0.8)
# a ball's pocket offset against either wall, as a share of the pocket clearance's angle cp/R_pocket
WALL_SHARE = 0.6


def model_at(model, lam: float):
    """The model with its weight scaled by lambda (the held-cage continuation's parameter)."""
    p = model.p.copy()
    p[M.P_GRAV] = lam * model.p[M.P_GRAV]
    return model._replace(p=p)


def load_at(load, lam: float) -> np.ndarray:
    """(Fx, lambda·Fy, lambda·Fz): the radial load scaled by lambda."""
    load = np.asarray(load, dtype=float)
    return np.array([load[0], lam * load[1], lam * load[2]])


def physical_starts(model, speed_rad_s: float, u_ref: np.ndarray, fractions=START_FRACTIONS) -> list:
    """The starts of the module docstring, item 1, built on the reference unknowns u_ref (the held-cage
    solve's layout: 6 per ball (x, r, pocket offset, w_x, w_r, w_t), then omega_c, ring, cage): for every
    fraction f of the inner-ring speed, omega_c = f·omega_i, the spins by the outer- and the inner-race
    rolling law scaled from u_ref's, the pocket offsets +-WALL_SHARE·cp/R_pocket."""
    z = model.n_balls
    nb = 6 * z
    p = model.p
    w_ref = u_ref[:nb].reshape(z, 6)[:, 3:].copy()
    omega_ref = float(u_ref[nb])
    axis = np.array([1.0, 0.0, 0.0])
    starts = []
    for f in fractions:
        omega_c = f * speed_rad_s
        outer = w_ref * (omega_c / omega_ref)
        inner = speed_rad_s * axis + (w_ref - speed_rad_s * axis) * ((speed_rad_s - omega_c) / (speed_rad_s - omega_ref))
        for w in (outer, inner):
            for side in (1.0, -1.0):
                u = u_ref.copy()
                balls = u[:nb].reshape(z, 6)
                balls[:, 2] = side * WALL_SHARE * p[M.P_CP] / p[M.P_RCAGE_POCKET]
                balls[:, 3:] = w
                u[nb] = omega_c
                starts.append(u)
    return starts


def unknowns_of_state(model, y: np.ndarray, phase: float = 0.0) -> np.ndarray:
    """The held-cage unknowns read off a state vector y of the dynamics (a start from the settled
    dynamics): each ball's x, r, spin and its azimuth relative to its pocket's (the cage angle added,
    wrapped to (-pi, pi]), the ring's positions, the cage's positions and speed."""
    from flexbearing.multibody import state_layout as SL
    z = model.n_balls
    nb = 6 * z
    lay = M.state_layout(model)
    r0, c0 = lay["ring"], lay["cage"]
    u = np.zeros(nb + 11)
    for j in range(z):
        b = y[SL.ball_offset(j):SL.ball_offset(j) + SL.BALL_STATE]
        off = b[SL.BALL_PSI] - (y[c0 + SL.CAGE_PHI] + phase + 2.0 * math.pi * j / z)
        off = (off + math.pi) % (2.0 * math.pi) - math.pi
        u[6 * j:6 * j + 6] = (b[SL.BALL_X], b[SL.BALL_R], off, b[SL.BALL_W_X], b[SL.BALL_W_R], b[SL.BALL_W_T])
    u[nb] = y[c0 + SL.CAGE_OMEGA]
    u[nb + 1:nb + 6] = y[r0:r0 + SL.RING_POSITIONS]
    u[nb + 6:nb + 9] = y[c0 + SL.CAGE_X:c0 + SL.CAGE_Z + 1]
    u[nb + 9:nb + 11] = y[c0 + SL.CAGE_TILT_Y:c0 + SL.CAGE_TILT_Z + 1]
    return u
