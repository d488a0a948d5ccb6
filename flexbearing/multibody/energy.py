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

from flexbearing.multibody.cage_body import cage_body_angular_velocity, cage_rotation, pocket_pose
from flexbearing.multibody.dynamics import _hertz_lookup
from flexbearing.multibody.floating_frame import deformed_moments, mass_matrix
from flexbearing.multibody.geometry import race_contact, ring_point_in_plane
from flexbearing.multibody.model import (F_GUIDANCE, F_HERTZ_FIXED, F_INNER_HALVES, F_POCKET_SHAPE, P_ALPHA0, P_CG, P_CP, P_DW, P_FE, P_FI, P_GRAV, P_IB, P_IID,
                             P_KC, P_KN, P_KRIM, P_MB, P_MI, P_RIL, P_RIR, P_RO, P_XIL, P_XIR, P_XO, P_Z)
from flexbearing.multibody.profiles import load_at


@njit(cache=True)
def mechanical_energy(t, y, p, flags, htab, load_table, impacts, cage):
    """Kinetic energy of balls, ring and cage + elastic energy of the contacts − work potential
    of the (constant) external load, J. Conserved when traction, drag and damping are off and the
    Hertz constants are fixed (model option hertz_fixed_angle; otherwise K(alpha) makes the Hertz
    force field very slightly non-conservative). The ring spin is prescribed (constant speed in a
    free run), its kinetic energy is constant and left out.

    Hertz: V = (2/5)·K·delta^2.5. Pocket: V = Kc·Z²/2 (Z <= Cp), Kc·Cp²/2 + Kc·Cp·(Z − Cp) +
    (2/5)·Kn·(Z − Cp)^2.5 beyond. Rim: K_rim·(e − Cg)²/2. Load: −F·x_ring. Gravity (along −Z):
    g·(m_b·Σ z_ball + m_i·z_ring + m_cage·z_cage). Cage: ½·vᵀM(q)v of the floating-frame body,
    v = (R', w_body, q'), plus the modal strain energy ½·Σ omega_k²·q_k².
    """
    z = int(p[P_Z])
    r0 = 9 * z
    c0 = r0 + 11
    m0 = c0 + 12
    A = cage.A
    scr = cage.scratch
    cage_rotation(y[c0 + 3], y[c0 + 4], y[c0 + 5], A)
    cage_body_angular_velocity(A, y, c0, scr[1])
    mb = p[P_MB]
    ib = p[P_IB]
    dw = p[P_DW]
    ek = 0.0
    ev = 0.0
    xi = y[r0]
    yi = y[r0 + 1]
    zi = y[r0 + 2]
    ty = y[r0 + 3]
    tz = y[r0 + 4]
    for j in range(z):
        o = 9 * j
        xb = y[o]
        rb = y[o + 1]
        psi = y[o + 2]
        ek += 0.5 * mb * (y[o + 3] ** 2 + y[o + 4] ** 2 + (rb * y[o + 5]) ** 2)
        ev += mb * p[P_GRAV] * rb * math.sin(psi)
        ek += 0.5 * ib * (y[o + 6] ** 2 + y[o + 7] ** 2 + y[o + 8] ** 2)
        for c in range(1 + flags[F_INNER_HALVES]):      # one-piece ring: no second inner half
            if c == 0:
                xc_g = p[P_XO]
                rc_g = p[P_RO]
                f = p[P_FE]
                kind = 0
            else:
                x0 = p[P_XIL] if c == 1 else p[P_XIR]
                rr0 = p[P_RIL] if c == 1 else p[P_RIR]
                xc_g, rc_g = ring_point_in_plane(psi, x0, rr0, xi, yi, zi, ty, tz)
                f = p[P_FI]
                kind = 1
            delta, ca, sa = race_contact(xb, rb, xc_g, rc_g, f, dw)
            if delta > 0.0:
                if flags[F_HERTZ_FIXED]:
                    K = _hertz_lookup(htab, kind, math.cos(p[P_ALPHA0]))[0]
                else:
                    K = _hertz_lookup(htab, kind, ca)[0]
                ev += 0.4 * K * delta ** 2.5
        # pocket (exact pose of its interface node, as in rhs)
        pocket_pose(j, y, c0, m0, cage, scr[1], scr[3], scr[4], scr[5], scr[6])
        ax = scr[5, 0]
        ay = scr[5, 1]
        az = scr[5, 2]
        dx = xb - scr[3, 0]
        dy = rb * math.cos(psi) - scr[3, 1]
        dz = rb * math.sin(psi) - scr[3, 2]
        # cylindrical pocket: offset from its axis; spherical: from its centre (as rhs)
        da = dx * ax + dy * ay + dz * az if flags[F_POCKET_SHAPE] == 0 else 0.0
        ux = dx - da * ax
        uy = dy - da * ay
        uz = dz - da * az
        zz = math.sqrt(ux * ux + uy * uy + uz * uz)
        cp = p[P_CP]
        kc = p[P_KC]
        if zz <= cp:
            ev += 0.5 * kc * zz * zz
        else:
            ev += 0.5 * kc * cp * cp + kc * cp * (zz - cp) + 0.4 * p[P_KN] * (zz - cp) ** 2.5
    # ring (translation + tilt) and cage
    ek += 0.5 * p[P_MI] * (y[r0 + 5] ** 2 + y[r0 + 6] ** 2 + y[r0 + 7] ** 2)
    ev += p[P_GRAV] * (p[P_MI] * zi + cage.mass[0] * y[c0 + 2])
    ek += 0.5 * p[P_IID] * (y[r0 + 8] ** 2 + y[r0 + 9] ** 2)
    stiff = cage.stiffness
    n = stiff.shape[0]
    q = y[m0:m0 + n]
    v = cage.rhs                 # work array: the velocity (R', w_body, q')
    v[0] = y[c0 + 6]
    v[1] = y[c0 + 7]
    v[2] = y[c0 + 8]
    v[3] = scr[1, 0]
    v[4] = scr[1, 1]
    v[5] = scr[1, 2]
    for k in range(n):
        v[6 + k] = y[m0 + n + k]
        ev += 0.5 * stiff[k] * q[k] * q[k]
    Mmat = cage.Mmat
    deformed_moments(q, cage.second, cage.Sx, cage.SS, cage.U, cage.Wab)
    mass_matrix(A, q, cage.mass[0], cage.first, cage.S1, cage.Mff, cage.U, cage.Wab, Mmat)
    for i in range(6 + n):
        for k in range(6 + n):
            ek += 0.5 * v[i] * Mmat[i, k] * v[k]
    # the rim's potential: offset from the outer land's centre (the origin) or the inner ring's;
    # a ball-riding cage has no rim (dynamics._cage_guidance)
    guidance = flags[F_GUIDANCE]
    if guidance == 1:
        e = math.sqrt((y[c0 + 1] - yi) ** 2 + (y[c0 + 2] - zi) ** 2)
    else:
        e = math.sqrt(y[c0 + 1] ** 2 + y[c0 + 2] ** 2)
    if guidance != 2 and e > p[P_CG]:
        ev += 0.5 * p[P_KRIM] * (e - p[P_CG]) ** 2
    f3 = np.empty(3)
    load_at(t, load_table, impacts, f3)
    ev -= f3[0] * xi + f3[1] * yi + f3[2] * zi
    return ek, ev
