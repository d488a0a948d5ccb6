"""The state slots the kernels of `rhs` read, as named values (flexbearing.multibody.state_layout), and the
loads they add up.

Named results: namedtuples are value types in nopython mode (no allocation); fields read by name.
The kernels are inlined into `rhs` and compiled without NRT reference counting (flexbearing.multibody.dynamics,
"the kernels of rhs").
"""
from __future__ import annotations

import math
from collections import namedtuple

from numba import njit

from flexbearing.multibody import numba_cache  # noqa: F401  (drops stale compiled kernels first)
from flexbearing.multibody.state_layout import (
    BALL_PSI, BALL_PSI_DOT, BALL_R, BALL_R_DOT, BALL_W_R, BALL_W_T, BALL_W_X, BALL_X, BALL_X_DOT,
    RING_TILT_Y, RING_TILT_Y_DOT, RING_TILT_Z, RING_TILT_Z_DOT, RING_VX, RING_VY, RING_VZ, RING_X, RING_Y,
    RING_Z, ball_offset,
)


# Named results: namedtuples are value types in nopython mode (no allocation); fields read by name.
# Compilation: `rhs` and the kernels are compiled without NRT reference counting (_nrt=False; they
# allocate nothing): with it every array a kernel takes costs an atomic increment and decrement per
# ball (measured: 20 us per rhs instead of 14 us at the paper's rigid-cage state). The small kernels
# and the pocket (many array arguments) are inlined by numba (inline="always"), the large ones are
# calls: inlining all of them saved another 0.5 us per rhs but tripled the first compilation on a
# new machine (19 s -> 61 s for a first run; 29 s as now), measured with an empty NUMBA_CACHE_DIR.
# Both options change the machine code only, never the arithmetic: dy/dt is bit-identical to the
# single-function rhs (benchmarks/rhs_ab.py).
BallState = namedtuple("BallState", "x r psi x_dot r_dot psi_dot w_x w_r w_t cos_psi sin_psi v_t")
BallState.__doc__ = "Ball j's state slots (state_layout.BALL_*), cos/sin of its azimuth and its orbital speed r·psi'."
RingState = namedtuple("RingState", "x y z tilt_y tilt_z vx vy vz tilt_y_dot tilt_z_dot")
RingState.__doc__ = "The inner ring's positions and rates (state_layout.RING_*), inertial, m, rad, m/s, rad/s."
BallLoad = namedtuple("BallLoad", "fx fr ft mx mr mt")
BallLoad.__doc__ = "Force (N) and moment about the centre (N·m) on a ball, on its orbiting triad (e_x, e_r, e_t)."
RingLoad = namedtuple("RingLoad", "fx fy fz mx my mz")
RingLoad.__doc__ = "Force (N) and moment about its centre (N·m) on the inner ring from the balls and the cage, inertial."


@njit(cache=True, _nrt=False, inline="always")
def ball_state(y, j):
    """Ball j's slots of y (state_layout) with cos psi, sin psi and v_t = r·psi'."""
    o = ball_offset(j)
    r = y[o + BALL_R]
    psi = y[o + BALL_PSI]
    psid = y[o + BALL_PSI_DOT]
    return BallState(y[o + BALL_X], r, psi, y[o + BALL_X_DOT], y[o + BALL_R_DOT], psid, y[o + BALL_W_X],
                     y[o + BALL_W_R], y[o + BALL_W_T], math.cos(psi), math.sin(psi), r * psid)


@njit(cache=True, _nrt=False, inline="always")
def ring_state(y, r0):
    """The inner ring's positions and rates (state_layout.RING_*) from its block at r0."""
    return RingState(y[r0 + RING_X], y[r0 + RING_Y], y[r0 + RING_Z], y[r0 + RING_TILT_Y], y[r0 + RING_TILT_Z],
                     y[r0 + RING_VX], y[r0 + RING_VY], y[r0 + RING_VZ], y[r0 + RING_TILT_Y_DOT],
                     y[r0 + RING_TILT_Z_DOT])
