"""The bearing's mechanical energy: kinetic energy plus the potentials of its conservative forces.

Used by the power balance (flexbearing.multibody.power_loss: dE/dt against the drive power and the losses) and
by the recorded output mechanical_energy (flexbearing.multibody.outputs), and conserved by a run without
traction, drag and damping (tests/test_energy.py). The equations of motion whose energy this is:
flexbearing.multibody.dynamics.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from flexbearing.mesh.cage_geometry import GUIDANCE_BALLS, POCKET_ELLIPTICAL
from flexbearing.multibody.cage_body import (cage_body_angular_velocity, cage_rotation, pocket_axial_direction,
                                              pocket_pose)
from flexbearing.multibody.dynamics import _hertz_lookup
from flexbearing.multibody.floating_frame import deformed_moments, mass_matrix
from flexbearing.multibody.geometry import race_contact, ring_point_in_plane
from flexbearing.multibody.guide_land import rim_offset, rim_potential
from flexbearing.multibody.hertz import hertz_potential
from flexbearing.multibody.model import (CONTACT_INNER_LEFT, CONTACT_OUTER, RACE_INNER, RACE_OUTER, F_GUIDANCE, F_HERTZ_FIXED, F_INNER_HALVES, F_POCKET_SHAPE, P_ALPHA0, P_CG, P_CP, P_DW, P_FE, P_FI, P_GRAV, P_IB, P_IID,
                             P_KC, P_KN, P_KRIM, P_MB, P_MI, P_POCKET_B, P_POCKET_CONE, P_RIL, P_RIR, P_RO, P_RPOCKET, P_XIL,
                             P_XIR, P_XO, P_Z)
from flexbearing.multibody.pocket import pocket_contact_offset, pocket_potential
from flexbearing.multibody.profiles import load_at
from flexbearing.multibody.state_layout import (
    BALL_PSI, BALL_PSI_DOT, BALL_R, BALL_R_DOT, BALL_W_R, BALL_W_T, BALL_W_X, BALL_X, BALL_X_DOT, CAGE_PHI,
    CAGE_TILT_Y, CAGE_TILT_Z, CAGE_VX, CAGE_VY, CAGE_VZ, CAGE_X, CAGE_Y, CAGE_Z, RING_TILT_Y, RING_TILT_Y_DOT,
    RING_TILT_Z, RING_TILT_Z_DOT, RING_VX, RING_VY, RING_VZ, RING_X, RING_Y, RING_Z, ball_offset, cage_offset,
    modal_offset, ring_offset,
)


@njit(cache=True)
def _add_cage_energy(y, c0, m0, cage, A, w_body, ek, ev):
    """The cage's kinetic energy ½·vᵀM(q)v of the floating-frame body, v = (R', w_body, q')
    (flexbearing.multibody.floating_frame.mass_matrix at the cage's attitude A and modal coordinates
    q), added to ek, and its modal strain energy ½·Σ omega_k²·q_k² added to ev: returns (ek, ev)."""
    stiff = cage.stiffness
    n = stiff.shape[0]
    q = y[m0:m0 + n]
    v = cage.rhs                 # work array: the velocity (R', w_body, q')
    v[0] = y[c0 + CAGE_VX]
    v[1] = y[c0 + CAGE_VY]
    v[2] = y[c0 + CAGE_VZ]
    v[3] = w_body[0]
    v[4] = w_body[1]
    v[5] = w_body[2]
    for k in range(n):
        v[6 + k] = y[m0 + n + k]
        ev += 0.5 * stiff[k] * q[k] * q[k]
    Mmat = cage.Mmat
    deformed_moments(q, cage.second, cage.Sx, cage.SS, cage.U, cage.Wab)
    mass_matrix(A, q, cage.mass[0], cage.first, cage.S1, cage.Mff, cage.U, cage.Wab, Mmat)
    for i in range(6 + n):
        for k in range(6 + n):
            ek += 0.5 * v[i] * Mmat[i, k] * v[k]
    return ek, ev


@njit(cache=True)
def mechanical_energy(t, y, p, flags, htab, load_table, impacts, cage):
    """Kinetic energy of balls, ring and cage + elastic energy of the contacts − work potential
    of the (constant) external load, J. Conserved when traction, drag and damping are off and the
    Hertz constants are fixed (model option hertz_fixed_angle; otherwise K(alpha) makes the Hertz
    force field very slightly non-conservative). The ring spin is prescribed (constant speed in a
    free run), its kinetic energy is constant and left out.

    Each contact's potential is its law's own (the functions whose forces rhs applies):
    Hertz: V = (2/5)·K·delta^2.5 (hertz.hertz_potential). Pocket: V = Kc·Z²/2 (Z <= Cp),
    Kc·Cp²/2 + Kc·Cp·(Z − Cp) + (2/5)·Kn·(Z − Cp)^2.5 beyond (pocket.pocket_potential) of the
    approach Z of the pocket's shape (pocket.pocket_contact_offset, as rhs; an ellipse's axes turn with
    the cage). Rim: K_rim·(e − Cg)²/2
    (guide_land.rim_potential) of the offset from the land's axis (guide_land.rim_offset: an inner
    land's axis moves with the ring's centre and tilt). Load: −F·x_ring. Gravity (along −Z):
    g·(m_b·Σ z_ball + m_i·z_ring + m_cage·z_cage). Cage: ½·vᵀM(q)v of the floating-frame body,
    v = (R', w_body, q'), plus the modal strain energy ½·Σ omega_k²·q_k².
    """
    z = int(p[P_Z])
    r0 = ring_offset(z)
    c0 = cage_offset(z)
    m0 = modal_offset(z)
    A = cage.A
    scr = cage.scratch
    cage_rotation(y[c0 + CAGE_PHI], y[c0 + CAGE_TILT_Y], y[c0 + CAGE_TILT_Z], A)
    cage_body_angular_velocity(A, y, c0, scr[1])
    mb = p[P_MB]
    ib = p[P_IB]
    dw = p[P_DW]
    ek = 0.0
    ev = 0.0
    xi = y[r0 + RING_X]
    yi = y[r0 + RING_Y]
    zi = y[r0 + RING_Z]
    ty = y[r0 + RING_TILT_Y]
    tz = y[r0 + RING_TILT_Z]
    for j in range(z):
        o = ball_offset(j)
        xb = y[o + BALL_X]
        rb = y[o + BALL_R]
        psi = y[o + BALL_PSI]
        ek += 0.5 * mb * (y[o + BALL_X_DOT] ** 2 + y[o + BALL_R_DOT] ** 2 + (rb * y[o + BALL_PSI_DOT]) ** 2)
        ev += mb * p[P_GRAV] * rb * math.sin(psi)
        ek += 0.5 * ib * (y[o + BALL_W_X] ** 2 + y[o + BALL_W_R] ** 2 + y[o + BALL_W_T] ** 2)
        for c in range(1 + flags[F_INNER_HALVES]):      # one-piece ring: no second inner half
            if c == CONTACT_OUTER:
                xc_g = p[P_XO]
                rc_g = p[P_RO]
                f = p[P_FE]
                kind = RACE_OUTER
            else:
                x0 = p[P_XIL] if c == CONTACT_INNER_LEFT else p[P_XIR]
                rr0 = p[P_RIL] if c == CONTACT_INNER_LEFT else p[P_RIR]
                xc_g, rc_g = ring_point_in_plane(psi, x0, rr0, xi, yi, zi, ty, tz)
                f = p[P_FI]
                kind = RACE_INNER
            delta, ca, sa = race_contact(xb, rb, xc_g, rc_g, f, dw)
            if delta > 0.0:
                if flags[F_HERTZ_FIXED]:
                    K = _hertz_lookup(htab, kind, math.cos(p[P_ALPHA0]))[0]
                else:
                    K = _hertz_lookup(htab, kind, ca)[0]
                ev += hertz_potential(K, delta)
        # pocket (exact pose of its interface node, as in rhs)
        pocket_pose(j, y, c0, m0, cage, scr[1], scr[3], scr[4], scr[5], scr[6])
        ax = scr[5, 0]
        ay = scr[5, 1]
        az = scr[5, 2]
        dx = xb - scr[3, 0]
        dy = rb * math.cos(psi) - scr[3, 1]
        dz = rb * math.sin(psi) - scr[3, 2]
        # the approach the pocket law of rhs acts on (cylinder: from the axis; sphere: from the
        # centre; cone: from the wall's generator; ellipse: from the bore), and its potential
        kx = ky = kz = 0.0
        if flags[F_POCKET_SHAPE] == POCKET_ELLIPTICAL:
            kx, ky, kz = pocket_axial_direction(j, y, m0, A, cage.node_modes)
        zz = pocket_contact_offset(dx, dy, dz, ax, ay, az, flags[F_POCKET_SHAPE], p[P_POCKET_CONE],
                                   p[P_RPOCKET], p[P_POCKET_B], kx, ky, kz)[6]
        ev += pocket_potential(zz, p[P_CP], p[P_KC], p[P_KN])
    # ring (translation + tilt) and cage
    ek += 0.5 * p[P_MI] * (y[r0 + RING_VX] ** 2 + y[r0 + RING_VY] ** 2 + y[r0 + RING_VZ] ** 2)
    ev += p[P_GRAV] * (p[P_MI] * zi + cage.mass[0] * y[c0 + CAGE_Z])
    ek += 0.5 * p[P_IID] * (y[r0 + RING_TILT_Y_DOT] ** 2 + y[r0 + RING_TILT_Z_DOT] ** 2)
    ek, ev = _add_cage_energy(y, c0, m0, cage, A, scr[1], ek, ev)
    # the rim's potential: offset from the outer land's axis (the bearing axis) or the inner ring's
    # land axis in the cage's plane (it moves with the ring's centre and tilt);
    # a ball-riding cage has no rim (guidance_kernels._cage_guidance)
    if flags[F_GUIDANCE] != GUIDANCE_BALLS:
        e = rim_offset(flags[F_GUIDANCE], y[c0 + CAGE_X], y[c0 + CAGE_Y], y[c0 + CAGE_Z], xi, yi, zi, ty, tz)
        ev += rim_potential(e, p[P_CG], p[P_KRIM])
    f3 = np.empty(3)
    load_at(t, load_table, impacts, f3)
    ev -= f3[0] * xi + f3[1] * yi + f3[2] * zi
    return ek, ev
