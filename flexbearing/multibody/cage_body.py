"""The cage in the bearing: its orientation, angular velocity and equations in the floating frame.

The cage's state (flexbearing.multibody.model, block CAGE, then its modal block MODES): the frame origin
(x, y, z), the angles theta = (phi, by, bz) of A = R_z(bz)·R_y(by)·R_x(phi) (spin phi about the
cage axis, then the tilts about Y and Z), their rates, and the modal coordinates q, q' of a flexible
cage (none for a rigid one). `cage_equations` turns the loads `flexbearing.multibody.dynamics.rhs` applies
(pocket forces at the interface nodes, the guide-land force and torque, gravity) into the state
derivative through the floating-frame equations of flexbearing.multibody.floating_frame, mapping the body's
angular acceleration to the angle accelerations exactly (w = G(theta)·theta'); `pocket_pose` gives
the pose and velocity of a pocket's interface node, the flexible cage's elastic motion included.
All compiled with numba, allocation-free, on the arrays of flexbearing.multibody.floating_frame.CageArrays.
"""
from __future__ import annotations

import math

from numba import njit

from flexbearing.multibody.floating_frame import accelerations as ffrf_accelerations
from flexbearing.multibody.geometry import cross
from flexbearing.multibody.state_layout import (
    CAGE_OMEGA, CAGE_PHI, CAGE_POSITIONS, CAGE_TILT_Y, CAGE_TILT_Y_DOT, CAGE_TILT_Z, CAGE_TILT_Z_DOT, CAGE_VX,
    CAGE_VY, CAGE_VZ,
)


@njit(cache=True)
def cage_rotation(phi, by, bz, A):
    """A = R_z(bz)·R_y(by)·R_x(phi): cage body -> inertial (spin phi about the cage axis, then the
    tilts about Y and Z; for small tilts A ≈ (I + [beta]x)·R_x(phi), beta = (0, by, bz))."""
    cf = math.cos(phi)
    sf = math.sin(phi)
    cy = math.cos(by)
    sy = math.sin(by)
    cz = math.cos(bz)
    sz = math.sin(bz)
    # R_z R_y
    a00 = cz * cy
    a01 = -sz
    a02 = cz * sy
    a10 = sz * cy
    a11 = cz
    a12 = sz * sy
    a20 = -sy
    a21 = 0.0
    a22 = cy
    # · R_x(phi) = [[1,0,0],[0,cf,-sf],[0,sf,cf]]
    A[0, 0] = a00
    A[0, 1] = a01 * cf + a02 * sf
    A[0, 2] = -a01 * sf + a02 * cf
    A[1, 0] = a10
    A[1, 1] = a11 * cf + a12 * sf
    A[1, 2] = -a11 * sf + a12 * cf
    A[2, 0] = a20
    A[2, 1] = a21 * cf + a22 * sf
    A[2, 2] = -a21 * sf + a22 * cf


@njit(cache=True)
def cage_angular_velocity(by, bz, dphi, dby, dbz):
    """Inertial angular velocity w = G(theta)·theta' of A = R_z(bz)R_y(by)R_x(phi):
    w = e_z·bz' + R_z e_y·by' + R_z R_y e_x·phi'."""
    cy = math.cos(by)
    sy = math.sin(by)
    cz = math.cos(bz)
    sz = math.sin(bz)
    wx = cz * cy * dphi - sz * dby
    wy = sz * cy * dphi + cz * dby
    wz = -sy * dphi + dbz
    return wx, wy, wz


@njit(cache=True)
def cage_body_angular_velocity(A, y, c0, w):
    """w[:] = Aᵀ·G(theta)·theta': the cage's angular velocity in its body frame (A current)."""
    wx, wy, wz = cage_angular_velocity(y[c0 + CAGE_TILT_Y], y[c0 + CAGE_TILT_Z], y[c0 + CAGE_OMEGA],
                                       y[c0 + CAGE_TILT_Y_DOT], y[c0 + CAGE_TILT_Z_DOT])
    w[0] = A[0, 0] * wx + A[1, 0] * wy + A[2, 0] * wz
    w[1] = A[0, 1] * wx + A[1, 1] * wy + A[2, 1] * wz
    w[2] = A[0, 2] * wx + A[1, 2] * wy + A[2, 2] * wz


@njit(cache=True)
def cage_angle_accelerations(by, bz, dphi, dby, dbz, ax, ay, az):
    """theta'' = G⁻¹·(w' − G'·theta') for the inertial angular acceleration w' = (ax, ay, az).

    G = [g1, g2, e_z], g1 = R_z R_y e_x = (cz·cy, sz·cy, −sy), g2 = R_z e_y = (−sz, cz, 0);
    G'·theta' = phi'·(w_zy × g1) + by'·(bz'·e_z × g2), w_zy = e_z·bz' + g2·by' (the frame R_z R_y).
    """
    cy = math.cos(by)
    sy = math.sin(by)
    cz = math.cos(bz)
    sz = math.sin(bz)
    g1x, g1y, g1z = cz * cy, sz * cy, -sy
    g2x, g2y = -sz, cz
    wzx = g2x * dby
    wzy = g2y * dby
    wzz = dbz
    c1x, c1y, c1z = cross(wzx, wzy, wzz, g1x, g1y, g1z)
    # e_z × g2 = (−g2y, g2x, 0)
    rx = ax - dphi * c1x - dby * dbz * (-g2y)
    ry = ay - dphi * c1y - dby * dbz * g2x
    rz = az - dphi * c1z
    # solve [g1 g2 e_z] (u, v, w) = r: the first two rows involve u, v only
    det = g1x * g2y - g2x * g1y            # = cy
    u = (rx * g2y - g2x * ry) / det
    v = (g1x * ry - g1y * rx) / det
    w = rz - g1z * u
    return u, v, w


@njit(cache=True)
def cage_equations(y, dydt, c0, m0, cage, land_fy, land_fz, land_mx, grav):
    """Cage equations: the floating-frame equations of flexbearing.multibody.floating_frame with the applied
    generalised forces cage.Qext (pocket loads, added by `rhs`), the guide-land force and torque
    at the frame origin and gravity; rigid cage = zero modes (flexbearing.multibody.dynamics docstring).

    State: (x, y, z) frame origin, theta = (phi, by, bz) with A = R_z(bz)R_y(by)R_x(phi), their
    rates, then q and q' (block MODES)."""
    A = cage.A
    Qext = cage.Qext
    acc = cage.acc
    node_load = cage.node_load
    land_modes = cage.land_modes
    n = cage.stiffness.shape[0]
    phi = y[c0 + CAGE_PHI]
    by = y[c0 + CAGE_TILT_Y]
    bz = y[c0 + CAGE_TILT_Z]
    dphi = y[c0 + CAGE_OMEGA]
    dby = y[c0 + CAGE_TILT_Y_DOT]
    dbz = y[c0 + CAGE_TILT_Z_DOT]
    cage_rotation(phi, by, bz, A)
    w = cage.scratch[0]
    cage_body_angular_velocity(A, y, c0, w)
    # guide land: resultant force (0, fy, fz) and torque about X on the frame; gravity along −Z
    Qext[1] += land_fy
    Qext[2] += land_fz - cage.mass[0] * grav
    Qext[3] += A[0, 0] * land_mx
    Qext[4] += A[0, 1] * land_mx
    Qext[5] += A[0, 2] * land_mx
    # ... and distributed over the guide surface for the elastic coordinates: the file's
    # statically equivalent land loads (cosine pressure for the force, uniform shear for the
    # torque; flexbearing.fem_cage.reduction) per unit body-frame force y, z and torque x, Q_q += Gᵀ·L_b.
    # Kept in row Z of node_load for the stress recovery's residual modes.
    zl = node_load.shape[0] - 1
    lby = A[1, 1] * land_fy + A[2, 1] * land_fz
    lbz = A[1, 2] * land_fy + A[2, 2] * land_fz
    lbx = A[0, 0] * land_mx
    node_load[zl, 0] = lby
    node_load[zl, 1] = lbz
    node_load[zl, 2] = lbx
    for k in range(n):
        Qext[6 + k] += land_modes[0, k] * lby + land_modes[1, k] * lbz + land_modes[2, k] * lbx
    q = y[m0:m0 + n]
    qd = y[m0 + n:m0 + 2 * n]
    ffrf_accelerations(A, w, q, qd, Qext, cage.mass[0], cage.first, cage.second, cage.S1, cage.Sx, cage.SS,
                       cage.Mff, cage.stiffness, cage.damping, cage.Mmat, cage.rhs, cage.U, cage.Wab, acc)
    for k in range(CAGE_POSITIONS):
        dydt[c0 + k] = y[c0 + CAGE_POSITIONS + k]
    dydt[c0 + CAGE_VX] = acc[0]
    dydt[c0 + CAGE_VY] = acc[1]
    dydt[c0 + CAGE_VZ] = acc[2]
    # w' (inertial) = A·w'_body
    ax = A[0, 0] * acc[3] + A[0, 1] * acc[4] + A[0, 2] * acc[5]
    ay = A[1, 0] * acc[3] + A[1, 1] * acc[4] + A[1, 2] * acc[5]
    az = A[2, 0] * acc[3] + A[2, 1] * acc[4] + A[2, 2] * acc[5]
    u, v, ww = cage_angle_accelerations(by, bz, dphi, dby, dbz, ax, ay, az)
    dydt[c0 + CAGE_OMEGA] = u
    dydt[c0 + CAGE_TILT_Y_DOT] = v
    dydt[c0 + CAGE_TILT_Z_DOT] = ww
    for k in range(n):
        dydt[m0 + k] = qd[k]
        dydt[m0 + n + k] = acc[6 + k]


@njit(cache=True)
def pocket_pose(j, y, c0, m0, cage, w, pos, vel, axis, wnode):
    """Pocket j of the (flexible) cage: centre pos, its velocity vel, axis (unit, radial in the
    undeformed cage, turned by the interface node's small elastic rotation) and the node's
    angular velocity wnode, all inertial. The cage rotation must be in cage.A and its
    body-frame angular velocity in w (`cage_body_angular_velocity`).

    The interface node's kinematics in the floating frame (pos = R + A u_p,
    vel = R' + A (w × u_p + Phi_p q'), rot = Psi_p q, u_p = x_p + Phi_p q; Shabana, Dynamics of
    Multibody Systems, 4th ed. 2013, ch. 5) and its angular velocity
    A (w + Psi_p q'), read from the state vector by index: no array views are made (each view
    costs an atomic reference-count increment and decrement, ~20 % of a rigid cage's rhs when
    this ran once per pocket through slices of y)."""
    pocket_pose_arrays(j, y, c0, m0, cage.A, cage.node_position, cage.node_modes, w, pos, vel, axis, wnode)


@njit(cache=True)
def pocket_axial_direction(j, y, m0, A, nmodes):
    """The cage's axial direction at pocket j's interface node, unit, inertial: (k_x, k_y, k_z).

    The body frame's e_x turned by the node's small elastic rotation rot = Psi_j q as the pocket
    axis is in `pocket_pose_arrays` (e + rot × e, normalised; e_x + rot × e_x = (1, rot_z, −rot_y)),
    then by the cage's rotation A: the pocket's own frame, which an elliptical pocket's section
    axes follow (flexbearing.multibody.pocket.pocket_contact_offset). A rigid cage: A's first column."""
    n = nmodes.shape[2]
    r1 = 0.0
    r2 = 0.0
    for k in range(n):
        qk = y[m0 + k]
        r1 += nmodes[j, 4, k] * qk
        r2 += nmodes[j, 5, k] * qk
    bn = math.sqrt(1.0 + r2 * r2 + r1 * r1)
    b0 = 1.0 / bn
    b1 = r2 / bn
    b2 = -r1 / bn
    return (A[0, 0] * b0 + A[0, 1] * b1 + A[0, 2] * b2, A[1, 0] * b0 + A[1, 1] * b1 + A[1, 2] * b2,
            A[2, 0] * b0 + A[2, 1] * b1 + A[2, 2] * b2)


@njit(cache=True)
def pocket_pose_arrays(j, y, c0, m0, A, npos, nmodes, w, pos, vel, axis, wnode):
    """`pocket_pose` with the cage's rotation A, node positions and node mode rows passed as
    arrays (flexbearing.multibody.dynamics.rhs takes them out of the cage once per call: reading them from
    the cage tuple per pocket cost reference-count operations too)."""
    n = nmodes.shape[2]
    u0 = npos[j, 0]
    u1 = npos[j, 1]
    u2 = npos[j, 2]
    d0 = 0.0
    d1 = 0.0
    d2 = 0.0
    r0 = 0.0
    r1 = 0.0
    r2 = 0.0
    o0 = w[0]
    o1 = w[1]
    o2 = w[2]
    for k in range(n):
        qk = y[m0 + k]
        qdk = y[m0 + n + k]
        u0 += nmodes[j, 0, k] * qk
        u1 += nmodes[j, 1, k] * qk
        u2 += nmodes[j, 2, k] * qk
        d0 += nmodes[j, 0, k] * qdk
        d1 += nmodes[j, 1, k] * qdk
        d2 += nmodes[j, 2, k] * qdk
        r0 += nmodes[j, 3, k] * qk
        r1 += nmodes[j, 4, k] * qk
        r2 += nmodes[j, 5, k] * qk
        o0 += nmodes[j, 3, k] * qdk
        o1 += nmodes[j, 4, k] * qdk
        o2 += nmodes[j, 5, k] * qdk
    b0 = w[1] * u2 - w[2] * u1 + d0
    b1 = w[2] * u0 - w[0] * u2 + d1
    b2 = w[0] * u1 - w[1] * u0 + d2
    for i in range(3):
        pos[i] = y[c0 + i] + A[i, 0] * u0 + A[i, 1] * u1 + A[i, 2] * u2
        vel[i] = y[c0 + CAGE_VX + i] + A[i, 0] * b0 + A[i, 1] * b1 + A[i, 2] * b2
    # undeformed radial axis through the node, turned by the node rotation: e + rot × e
    ny = npos[j, 1]
    nz = npos[j, 2]
    nr = math.sqrt(ny * ny + nz * nz)
    ey = ny / nr
    ez = nz / nr
    bx = r1 * ez - r2 * ey
    by_ = ey - r0 * ez
    bz_ = ez + r0 * ey
    bn = math.sqrt(bx * bx + by_ * by_ + bz_ * bz_)
    bx /= bn
    by_ /= bn
    bz_ /= bn
    for i in range(3):
        axis[i] = A[i, 0] * bx + A[i, 1] * by_ + A[i, 2] * bz_
    # node angular velocity: A (w + Psi_j q')
    for i in range(3):
        wnode[i] = A[i, 0] * o0 + A[i, 1] * o1 + A[i, 2] * o2
