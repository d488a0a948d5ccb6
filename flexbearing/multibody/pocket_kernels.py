"""The ball–pocket contact of `rhs`: the pocket law (linear Kc·Z up to the pocket clearance, Hertz
beyond; paper §2.3.1) with the lubricated pocket's Poiseuille rolling and Couette sliding
resistances (flexbearing.multibody.pocket), the pocket's pose from the cage (rigid or flexible), and the
reaction on the cage (`ball_pocket`). Equations and references in each docstring.
"""
from __future__ import annotations

import math
from collections import namedtuple

from numba import njit

from flexbearing.multibody import numba_cache  # noqa: F401  (drops stale compiled kernels first)
from flexbearing.multibody.model import (
    P_DW, P_Z, P_MB, P_CP, P_KC, P_KN, P_RPOCKET, P_ETA0, P_ZETA, P_MUPOCKET, F_DRAG, F_DAMPING,
    F_POCKET_SHAPE, P_POCKET_CONE, P_POCKET_B, W_P_POCKET, W_POCKET_Q, W_POCKET_Z, W_POCKET_T, W_PK_FX,
    W_PK_FY, W_PK_FZ, W_PK_LY, W_PK_LZ,
)
from flexbearing.multibody.geometry import cross
from flexbearing.multibody.pocket import (
    pocket_film_radii, pocket_resistance_coefficients, pocket_contact_offset, pocket_axis_point,
    pocket_elastic_force, pocket_rolling_force, pocket_sliding_force,
)
from flexbearing.mesh.cage_geometry import POCKET_ELLIPTICAL
from flexbearing.multibody.cage_body import pocket_axial_direction, pocket_pose_arrays
from flexbearing.multibody.floating_frame import add_node_load
from flexbearing.multibody.contact_status import STATUS_DEEP_POCKET, DELTA_MAX_FRAC, _flag
from flexbearing.multibody.kernel_state import BallLoad


POCKET_H_MIN = 1e-7        # m: floor of the ball–pocket gap in the sliding resistance (assumed)
PocketContact = namedtuple("PocketContact", "fx fy fz mx my mz x_action y_action z_action q offset power")
PocketContact.__doc__ = "One ball–pocket contact (`_pocket_force` docstring), inertial components, SI."


@njit(cache=True)
def pocket_film_coefficients(p, flags):
    """(c_R, c_S, r) of the lubricated pocket's rolling and sliding resistances
    (flexbearing.multibody.pocket.pocket_resistance_coefficients) for the model's ball, pocket and oil,
    at the pocket's nominal contact (pocket.pocket_film_radii: entrainment radius Rb and the
    conforming transverse radius R_xi in a cylindrical, conical or elliptical pocket; both radii
    conforming in a spherical one). Constant for a model; `rhs` evaluates them once per call and
    hands them to `_pocket_force`."""
    rxi, reta = pocket_film_radii(flags[F_POCKET_SHAPE], 0.5 * p[P_DW], p[P_RPOCKET], p[P_POCKET_B])
    return pocket_resistance_coefficients(reta, rxi, p[P_ETA0])


@njit(cache=True)
def _pocket_interface(bx, by, bz, vbx, vby, vbz, wbx, wby, wbz,
                      px, py, pz, ax, ay, az, vpx, vpy, vpz, wcx, wcy, wcz, kx, ky, kz, p, flags):
    """`_pocket_force` with the film coefficients of `pocket_film_coefficients` (one pocket on its
    own, as the tests and benchmarks call it)."""
    c_roll, c_slide, c_root = pocket_film_coefficients(p, flags)
    return _pocket_force(bx, by, bz, vbx, vby, vbz, wbx, wby, wbz, px, py, pz, ax, ay, az, vpx, vpy, vpz,
                         wcx, wcy, wcz, kx, ky, kz, p, flags, c_roll, c_slide, c_root)


@njit(cache=True, inline="always")
def _pocket_film_forces(fx, fy, fz, Q, zz, ux, uy, uz, ex, ey, ez, px, py, pz, vbx, vby, vbz, wbx, wby, wbz,
                        vpx, vpy, vpz, wcx, wcy, wcz, p, c_roll, c_slide, c_root):
    """The lubricated pocket's resistances (flexbearing.multibody.pocket; paper §2.3.2) added to the
    force (fx, fy, fz) on the ball: returns (fx, fy, fz, mx, my, mz), M about the ball centre.

    On each side s = ±1 of the ball (points b + s·Rb·u and p + e + s·Rp·u, u the unit approach
    direction) the ball surface slides on the pocket wall at g = (v_ball − v_wall) tangential;
    the film there gives the Poiseuille rolling resistance F_R (entrainment g/2 relative to the
    wall, independent of the gap; pocket.pocket_rolling_force) and the Couette sliding resistance
    F_S (gap h0 = Cp − s·Z, floored at POCKET_H_MIN, wetted edge at the gap Cp;
    pocket.pocket_sliding_force), both along −g on the ball, with c_R, c_S, r of
    `pocket_film_coefficients`; and the Coulomb part mu_p·Q (option pocket_friction, default 0)
    on the loaded side only.
    """
    mx = 0.0
    my = 0.0
    mz = 0.0
    rb = 0.5 * p[P_DW]
    rp = p[P_RPOCKET]
    cp_gap = p[P_CP]
    for side in (1.0, -1.0):
        sx, sy, sz = cross(wbx, wby, wbz, side * rb * ux, side * rb * uy, side * rb * uz)
        wx_ = px + ex + side * rp * ux
        wy_ = py + ey + side * rp * uy
        wz_ = pz + ez + side * rp * uz
        ox, oy, oz = cross(wcx, wcy, wcz, wx_ - px, wy_ - py, wz_ - pz)
        gx = vbx + sx - (vpx + ox)
        gy = vby + sy - (vpy + oy)
        gz = vbz + sz - (vpz + oz)
        gn = gx * ux + gy * uy + gz * uz
        gx -= gn * ux
        gy -= gn * uy
        gz -= gn * uz
        g = math.sqrt(gx * gx + gy * gy + gz * gz)
        if g <= 1e-12:
            continue
        h0 = cp_gap - side * zz
        if h0 < POCKET_H_MIN:
            h0 = POCKET_H_MIN
        f_r = pocket_rolling_force(c_roll, c_root, 0.5 * g)
        f_s = pocket_sliding_force(c_slide, c_root, g, h0, cp_gap)
        f_c = p[P_MUPOCKET] * Q if side > 0.0 else 0.0
        tf = (f_r + f_s + f_c) / g
        fx -= tf * gx
        fy -= tf * gy
        fz -= tf * gz
        m1, m2, m3 = cross(side * rb * ux, side * rb * uy, side * rb * uz, -tf * gx, -tf * gy, -tf * gz)
        mx += m1
        my += m2
        mz += m3
    return fx, fy, fz, mx, my, mz


@njit(cache=True)
def _pocket_force(bx, by, bz, vbx, vby, vbz, wbx, wby, wbz,
                  px, py, pz, ax, ay, az, vpx, vpy, vpz, wcx, wcy, wcz, kx, ky, kz, p, flags, c_roll, c_slide,
                  c_root):
    """Ball–pocket force of one pocket (paper §2.3.1), inertial components.

    b ball centre, (px, py, pz) pocket centre, a pocket axis (radial, unit), v_p the velocity of
    the pocket centre, w_c the cage angular velocity, k the cage's axial direction at the pocket
    (unit, cage_body.pocket_axial_direction; used by the elliptical pocket only, whose section
    axes turn with the cage). Offset of the ball from
    the pocket axis Z = |d − (d·a)a|, d = b − p; normal force on the ball −Q(Z)·u, u the unit
    offset, Q = Kc·Z (Z <= Cp), Kc·Cp + Kn·(Z − Cp)^1.5 (+ damping) beyond; with the drag switch
    the hydrodynamic pocket resistances (comment below) and optional Coulomb friction mu_p·Q.
    Returns PocketContact(fx, fy, fz: F on the ball; mx, my, mz: M on the ball about its centre;
    x_action, y_action, z_action: point of action on the cage; q: Q; offset: Z; power: P) with P the power the pocket dissipates (flexbearing.multibody.power_loss): with the non-conservative
    part F_nc = F + Q_el·u of the force (Q_el the spring/Hertz part of Q) and the cage receiving
    −F and −M − (b − p)×F at its node,

        P = −[F_nc·(v_b − v_p − w_c × (b − p)) + M·(w_b − w_c)].

    The cage receives −F at the point of action.
    """
    dx = bx - px
    dy = by - py
    dz = bz - pz
    # the approach zz along u: from the cylinder's axis, the sphere's centre, the cone's wall (e: the
    # offset's part the wall's nearest point follows; pocket.pocket_contact_offset)
    ex, ey, ez, ux, uy, uz, zz = pocket_contact_offset(dx, dy, dz, ax, ay, az, flags[F_POCKET_SHAPE],
                                                       p[P_POCKET_CONE], p[P_RPOCKET], p[P_POCKET_B], kx, ky, kz)
    if zz < 1e-15:
        return PocketContact(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, px, py, pz, 0.0, zz, 0.0)
    ux /= zz
    uy /= zz
    uz /= zz
    cp = p[P_CP]
    kc = p[P_KC]
    q_el = pocket_elastic_force(zz, cp, kc, p[P_KN])
    Q = q_el
    if zz > cp and flags[F_DAMPING]:
        # Hertz branch: contact damping on the approach rate along u, (v_b − v_pocket point)·u
        rate = (vbx - vpx) * ux + (vby - vpy) * uy + (vbz - vpz) * uz
        c = 2.0 * p[P_ZETA] * math.sqrt(1.5 * p[P_KN] * math.sqrt(zz - cp) * p[P_MB])
        Q += c * rate
        if Q < kc * cp:
            Q = kc * cp
    fx = -Q * ux
    fy = -Q * uy
    fz = -Q * uz
    mx = 0.0
    my = 0.0
    mz = 0.0
    # contact point on the pocket wall
    rp = p[P_RPOCKET]
    qx = px + ex + rp * ux
    qy = py + ey + rp * uy
    qz = pz + ez + rp * uz
    if flags[F_DRAG]:
        fx, fy, fz, mx, my, mz = _pocket_film_forces(fx, fy, fz, Q, zz, ux, uy, uz, ex, ey, ez, px, py, pz,
                                                     vbx, vby, vbz, wbx, wby, wbz, vpx, vpy, vpz, wcx, wcy,
                                                     wcz, p, c_roll, c_slide, c_root)
    # dissipated power (docstring): relative velocity of the ball centre to the cage point there
    r1, r2, r3 = cross(wcx, wcy, wcz, dx, dy, dz)
    pw = ((fx + q_el * ux) * (vbx - vpx - r1) + (fy + q_el * uy) * (vby - vpy - r2)
          + (fz + q_el * uz) * (vbz - vpz - r3)
          + mx * (wbx - wcx) + my * (wby - wcy) + mz * (wbz - wcz))
    return PocketContact(fx, fy, fz, mx, my, mz, qx, qy, qz, Q, zz, -pw)


@njit(cache=True, _nrt=False, inline="always")
def ball_pocket(j, b, y, c0, m0, A, w_body, pos, vel, axv, wn, Fc, Tn, q_modes, nl, node_position, node_modes, q_ext,
                xc, yc, zc, p, flags, c_roll, c_slide, c_root, work, load):
    """Ball j in its pocket (`_pocket_force`, paper §2.3.1): the force on the ball added to its load,
    the opposite load on the cage's interface node (floating frame + modes), recorded into work.

    On the cage: −F_b and the reaction moment, applied at the point w of the pocket axis level with
    the ball (the normal force's line of action passes through it), carried to the interface node:
    node force −F_b, node moment (w − p)×(−F_b) − M_b − (b − w)×F_b. This is the virtual work of the
    pocket force for the node's motion, so the normal force stays the exact gradient of its
    potential (conservative runs conserve energy). A spherical pocket has no axis: w = p.
    """
    zb = int(p[P_Z])
    dw = p[P_DW]
    cs = b.cos_psi
    sn = b.sin_psi
    # pose of the pocket's interface node
    pocket_pose_arrays(j, y, c0, m0, A, node_position, node_modes, w_body, pos, vel, axv, wn)
    ppx = pos[0]
    ppy = pos[1]
    ppz = pos[2]
    ax = axv[0]
    ay = axv[1]
    az = axv[2]
    # the cage's axial direction at the pocket: an elliptical section's axes turn with the cage
    kx = ky = kz = 0.0
    if flags[F_POCKET_SHAPE] == POCKET_ELLIPTICAL:
        kx, ky, kz = pocket_axial_direction(j, y, m0, A, node_modes)
    # ball in inertial components
    bx = b.x
    byy = b.r * cs
    bzz = b.r * sn
    pk = _pocket_force(bx, byy, bzz, b.x_dot, b.r_dot * cs - b.v_t * sn, b.r_dot * sn + b.v_t * cs, b.w_x,
                       b.w_r * cs - b.w_t * sn, b.w_r * sn + b.w_t * cs,
                       ppx, ppy, ppz, ax, ay, az, vel[0], vel[1], vel[2], wn[0], wn[1], wn[2],
                       kx, ky, kz, p, flags, c_roll, c_slide, c_root)
    pfx, pfy, pfz = pk.fx, pk.fy, pk.fz
    work[j, W_POCKET_Q] = pk.q
    work[j, W_POCKET_Z] = pk.offset
    work[j, W_P_POCKET] = pk.power
    if pk.offset > p[P_CP] + DELTA_MAX_FRAC * dw:
        _flag(work, zb, STATUS_DEEP_POCKET, j, 3, pk.offset - p[P_CP])
    # on the ball, to the orbiting frame
    pft = -pfy * sn + pfz * cs
    work[j, W_POCKET_T] = pft
    load = BallLoad(load.fx + pfx, load.fr + (pfy * cs + pfz * sn), load.ft + pft, load.mx + pk.mx,
                    load.mr + (pk.my * cs + pk.mz * sn), load.mt + (-pk.my * sn + pk.mz * cs))
    # on the cage (docstring)
    da_ = pocket_axis_point(bx - ppx, byy - ppy, bzz - ppz, ax, ay, az, flags[F_POCKET_SHAPE], p[P_POCKET_CONE])
    wpx = ppx + da_ * ax
    wpy = ppy + da_ * ay
    wpz = ppz + da_ * az
    Fc[0] = -pfx
    Fc[1] = -pfy
    Fc[2] = -pfz
    l1, l2, l3 = cross(da_ * ax, da_ * ay, da_ * az, -pfx, -pfy, -pfz)
    b1, b2, b3 = cross(bx - wpx, byy - wpy, bzz - wpz, pfx, pfy, pfz)
    Tn[0] = l1 - pk.mx - b1
    Tn[1] = l2 - pk.my - b2
    Tn[2] = l3 - pk.mz - b3
    add_node_load(A, q_modes, node_position, node_modes, j, Fc, Tn, q_ext)
    for i in range(3):
        nl[j, i] = A[0, i] * Fc[0] + A[1, i] * Fc[1] + A[2, i] * Fc[2]
        nl[j, 3 + i] = A[0, i] * Tn[0] + A[1, i] * Tn[1] + A[2, i] * Tn[2]
    work[j, W_PK_FX] = -pfx
    work[j, W_PK_FY] = -pfy
    work[j, W_PK_FZ] = -pfz
    work[j, W_PK_LY] = wpy - yc
    work[j, W_PK_LZ] = wpz - zc
    return load
