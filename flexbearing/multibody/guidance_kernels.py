"""What guides the cage in `rhs`: the land film of the outer or inner ring, or nothing but the balls
(`_cage_guidance`, flexbearing.multibody.guide_land), its reaction on the inner ring, and the land's and
the cage's structural damping power. Equations and references in each docstring.
"""
from __future__ import annotations

import math
from collections import namedtuple

from numba import njit

from flexbearing.multibody import numba_cache  # noqa: F401  (drops stale compiled kernels first)
from flexbearing.multibody.model import (
    P_R1, P_CG, P_L3, P_KRIM, P_MURIM, P_ETA0, P_EPSMAX, P_LAND_L, F_DRAG, F_LAND, F_GUIDANCE, WR_P_LAND,
    WR_P_STRUCTURAL,
)
from flexbearing.mesh.cage_geometry import GUIDANCE_BALLS, GUIDANCE_INNER, GUIDANCE_OUTER
from flexbearing.multibody.geometry import cross
from flexbearing.multibody.guide_land import guide_land_force, inner_land_offset, land_count, rim_force
from flexbearing.multibody.kernel_state import RingLoad


GuidanceLoad = namedtuple("GuidanceLoad", "fy fz mx eps rim_force fx")
GuidanceLoad.__doc__ = ("What guides the cage (`_cage_guidance`): force (y, z) (N) and torque about X (N·m) on the "
                        "cage, eccentricity ratio e/Cg, the rim's normal force (N) and the axial force on the "
                        "cage (N; an inner land tilted with its ring: guide_land.inner_land_offset).")


@njit(cache=True)
def _guide_land(yc, zc, vy, vz, omega_c, p, flags):
    """Guide-land force (y, z) and torque about X on the cage, plus eps and the rim force: GuidanceLoad.

    flexbearing.multibody.guide_land.guide_land_force (Ocvirk short bearing with the whirl and squeeze terms,
    Childs' pi-film; the paper's form is the special case without them; Petroff-type torque;
    rim penalty contact k_rim·(e − Cg) with friction), outer ring fixed (omega_land = 0). The
    whirl/squeeze terms give the film its damping: without them it is a pure cross-coupled
    stiffness and the cage whirls out to the rim. With the drag switch off (conservative runs)
    only the rim's normal force remains.
    """
    e = math.sqrt(yc * yc + zc * zc)
    cg = p[P_CG]
    eta = p[P_ETA0] if flags[F_LAND] else 0.0
    mu = p[P_MURIM] if flags[F_DRAG] else 0.0
    n_lands = land_count(p[P_LAND_L], p[P_L3])
    fy, fz, mx = guide_land_force(yc, zc, vy, vz, omega_c, 0.0, p[P_R1], p[P_LAND_L] / n_lands, cg,
                                  eta, p[P_EPSMAX], True, p[P_KRIM], mu, n_lands)
    frim = rim_force(e, cg, p[P_KRIM])
    return GuidanceLoad(fy, fz, mx, e / cg, frim, 0.0)


@njit(cache=True)
def _cage_guidance(xc, yc, zc, vxc, vyc, vzc, omega_c, ring, omega_i, p, flags):
    """Force (y, z) and torque about X on the cage from what guides it (flags[F_GUIDANCE]), plus
    eps, the rim force and the axial force: GuidanceLoad(fy, fz, mx, eps, rim_force, fx). ring: the
    inner ring's RingState.

    "outer" (0): `_guide_land`, the outer ring's land, fixed. "inner" (1): the same short-bearing
    film and rim between the cage bore and the inner ring's land, with the cage offset and
    velocity taken relative to the land's axis in the cage's plane, which moves with the ring's
    centre and tilt (guide_land.inner_land_offset: e = (yc − yi − tilt_z·l, zc − zi + tilt_y·l),
    l = xc − xi), the force normal to that tilted axis (axial part fx = −tilt_z·fy + tilt_y·fz,
    so the rim force is the gradient of its potential), and the land turning
    with the ring, omega_land = omega_i (guide_land_force: U = R1·(omega_c + omega_i) in the
    Couette term, Petroff torque ∝ omega_i − omega_c). The short-bearing gap between a bush of
    centre c and a journal of centre j is h = Cg − (j − c)·n = Cg + e·n, the rotation by pi of the
    outer land's h = Cg − e·n: the pressure field turns with it, so the force on the cage (the
    bush now) is again −W_r·e_hat + W_t·(x_hat × e_hat), the form guide_land_force writes
    (tests/test_guidance.py integrates the short-bearing pressure of the bush for it). The inner
    ring takes the opposite force and torque (`rhs`). "balls" (2): no land, the pockets centre
    the cage; zero force, eps = 0.
    """
    g = flags[F_GUIDANCE]
    if g == GUIDANCE_OUTER:
        return _guide_land(yc, zc, vyc, vzc, omega_c, p, flags)
    if g == GUIDANCE_BALLS:
        return GuidanceLoad(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    ey, ez, vey, vez, _ = inner_land_offset(xc, yc, zc, vxc, vyc, vzc, ring.x, ring.y, ring.z, ring.tilt_y,
                                            ring.tilt_z, ring.vx, ring.vy, ring.vz, ring.tilt_y_dot,
                                            ring.tilt_z_dot)
    e = math.sqrt(ey * ey + ez * ez)
    cg = p[P_CG]
    eta = p[P_ETA0] if flags[F_LAND] else 0.0
    mu = p[P_MURIM] if flags[F_DRAG] else 0.0
    n_lands = land_count(p[P_LAND_L], p[P_L3])
    fy, fz, mx = guide_land_force(ey, ez, vey, vez, omega_c, omega_i, p[P_R1],
                                  p[P_LAND_L] / n_lands, cg, eta, p[P_EPSMAX], True, p[P_KRIM], mu,
                                  n_lands)
    frim = rim_force(e, cg, p[P_KRIM])
    return GuidanceLoad(fy, fz, mx, e / cg, frim, ring.tilt_y * fz - ring.tilt_z * fy)


@njit(cache=True, _nrt=False, inline="always")
def guidance_reaction_on_ring(g, xc, yc, zc, ring, flags, rl):
    """An inner-ring land (`_cage_guidance`) puts the opposite of its force F = (fx, fy, fz) and
    torque M_x on the ring.

    With l = xc − x_ring the lever of the land's axis point in the cage's plane
    (guide_land.inner_land_offset), the moments about Y and Z are the rim potential's generalised
    forces on the ring's tilts, M_y = −dV/dtilt_y = l·F_z and M_z = −dV/dtilt_z = −l·F_y: the
    moment about the ring centre of −(0, F_y, F_z) applied on the land's axis in the cage's plane
    (or at the cage centre, on the same line of action). The axial part −F_x (tilt × F, second
    order) stays out of these moments, as the linearised ring kinematics require (the Hertz
    reactions are built the same way: race_kernels.inner_race_reaction). About X (the prescribed
    spin: the drive torque) the moment of −F at the cage centre and −M_x."""
    if flags[F_GUIDANCE] != GUIDANCE_INNER:
        return rl
    m1, m2, m3 = cross(xc - ring.x, yc - ring.y, zc - ring.z, 0.0, -g.fy, -g.fz)
    return RingLoad(rl.fx - g.fx, rl.fy - g.fy, rl.fz - g.fz, rl.mx + (m1 - g.mx), rl.my + m2, rl.mz + m3)


@njit(cache=True, _nrt=False)
def land_and_structural_power(y, m0, g, xc, yc, zc, vxc, vyc, vzc, ring, omega_i, A, w_b, cage, flags, work, zb):
    """Dissipated power of the guide land and of the cage's modal damping (flexbearing.multibody.power_loss):
    the land's force, torque and distributed modal loads on the cage, less the rim's normal force,
    which is conservative (potential k_rim·(e − Cg)²/2); an inner land works on the cage's motion
    relative to the land: the power of F on the cage and of its reaction on the ring (force and tilt
    moments, `guidance_reaction_on_ring`) is F_y·de_y/dt + F_z·de_z/dt, e the offset from the land's
    axis in the cage's plane (guide_land.inner_land_offset; the axial part F_x cancels against the
    tilt terms). P_structural = sum_k d_k·q_k'²."""
    lfy, lfz, lmx, frim = g.fy, g.fz, g.mx, g.rim_force
    wx_inertial = A[0, 0] * w_b[0] + A[0, 1] * w_b[1] + A[0, 2] * w_b[2]
    if flags[F_GUIDANCE] == GUIDANCE_INNER:
        ey_, ez_, vey, vez, _ = inner_land_offset(xc, yc, zc, vxc, vyc, vzc, ring.x, ring.y, ring.z, ring.tilt_y,
                                                  ring.tilt_z, ring.vx, ring.vy, ring.vz, ring.tilt_y_dot,
                                                  ring.tilt_z_dot)
        p_land = lfy * vey + lfz * vez + lmx * (wx_inertial - omega_i)
        if frim > 0.0:
            p_land += frim * (ey_ * vey + ez_ * vez) / math.sqrt(ey_ * ey_ + ez_ * ez_)
    else:
        p_land = lfy * vyc + lfz * vzc + lmx * wx_inertial
        if frim > 0.0:
            e_c = math.sqrt(yc * yc + zc * zc)
            p_land += frim * (yc * vyc + zc * vzc) / e_c
    land_modes = cage.land_modes
    damp = cage.damping
    n_m = damp.shape[0]
    node_load = cage.node_load
    zl = node_load.shape[0] - 1
    p_struct = 0.0
    for k in range(n_m):
        qd_k = y[m0 + n_m + k]
        p_land += qd_k * (land_modes[0, k] * node_load[zl, 0] + land_modes[1, k] * node_load[zl, 1]
                          + land_modes[2, k] * node_load[zl, 2])
        p_struct += damp[k] * qd_k * qd_k
    work[zb, WR_P_LAND] = -p_land
    work[zb, WR_P_STRUCTURAL] = p_struct
