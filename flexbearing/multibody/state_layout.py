"""Layout of the bearing's state vector y: block sizes, slot names and block offsets, written once.

The fields and their units are described in the `flexbearing.multibody.model` docstring ("State
vector y"). In order: Z balls of BALL_STATE slots each (ball j at ball_offset(j)), the inner ring
(RING_STATE slots at ring_offset(Z)), the cage's floating frame (CAGE_STATE slots at
cage_offset(Z)), and the modal coordinates of a flexible cage (q then q', 2·n_modes slots at
modal_offset(Z); empty for a rigid cage). The constants are module-level ints, so the compiled
right-hand side sees them as compile-time constants (the same machine code as literal offsets).
"""
from __future__ import annotations

from numba import njit

# ---- ball j, in the frame orbiting with it (e_x, e_r, e_t)
BALL_STATE = 9
BALL_X = 0            # axial position of the ball centre, m
BALL_R = 1            # radial position (distance from the bearing axis), m
BALL_PSI = 2          # azimuth (orbital angle), rad
BALL_X_DOT = 3        # m/s
BALL_R_DOT = 4        # m/s
BALL_PSI_DOT = 5      # orbital speed, rad/s
BALL_W_X = 6          # absolute angular velocity on e_x, e_r, e_t, rad/s
BALL_W_R = 7
BALL_W_T = 8

# ---- inner ring: 5 positions, their 5 rates, the spin angle (prescribed speed)
RING_STATE = 11
RING_X = 0            # m
RING_Y = 1
RING_Z = 2
RING_TILT_Y = 3       # rad, small rotations about Y and Z
RING_TILT_Z = 4
RING_POSITIONS = 5    # slots 0..4 are positions, 5..9 their rates in the same order
RING_VX = 5           # m/s
RING_VY = 6
RING_VZ = 7
RING_TILT_Y_DOT = 8   # rad/s
RING_TILT_Z_DOT = 9
RING_PHI = 10         # spin angle phi_i, rad (phi_i' = omega_i(t))

# ---- cage floating frame: 6 positions, their 6 rates
CAGE_STATE = 12
CAGE_X = 0            # m
CAGE_Y = 1
CAGE_Z = 2
CAGE_PHI = 3          # cage spin angle about X, rad
CAGE_TILT_Y = 4       # rad
CAGE_TILT_Z = 5
CAGE_POSITIONS = 6    # slots 0..5 are positions, 6..11 their rates in the same order
CAGE_VX = 6           # m/s
CAGE_VY = 7
CAGE_VZ = 8
CAGE_OMEGA = 9        # cage spin speed omega_c, rad/s
CAGE_TILT_Y_DOT = 10  # rad/s
CAGE_TILT_Z_DOT = 11


@njit(cache=True)
def ball_offset(j):
    """Index of ball j's first slot (BALL_X)."""
    return BALL_STATE * j


@njit(cache=True)
def ring_offset(z):
    """Index of the inner ring's first slot, after the z balls."""
    return BALL_STATE * z


@njit(cache=True)
def cage_offset(z):
    """Index of the cage's first slot, after the inner ring."""
    return BALL_STATE * z + RING_STATE


@njit(cache=True)
def modal_offset(z):
    """Index of the first modal coordinate q_0 (q' follows the n_modes q's)."""
    return BALL_STATE * z + RING_STATE + CAGE_STATE


@njit(cache=True)
def state_size(z, n_modes):
    """Length of the state vector of z balls and a cage of n_modes modes."""
    return BALL_STATE * z + RING_STATE + CAGE_STATE + 2 * n_modes
