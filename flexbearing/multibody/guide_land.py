"""Cage–guide-land interaction: short journal bearing film (Ocvirk) plus a hard rim contact.

The cage's guiding cylinder (radius R1, width L) runs inside the outer ring's guide land with the
radial clearance Cg. The cage centre sits at the offset e = (ey, ez) from the land centre in the
plane normal to the bearing axis x; eps = |e|/Cg; e_hat = e/|e| points to the thinnest film.

Film forces on the cage, short-bearing (Ocvirk & DuBois) theory with the half-Sommerfeld (pi-film)
boundary condition (paper eqs for F_cy, F_cz, M_cx, its refs. 28–29; Hamrock, Fundamentals of
Fluid Film Lubrication, 1994, ch. 13):

    W_r = eta·U·L³·eps² / (Cg²·(1 − eps²)²)            along −e_hat (restoring),
    W_t = pi·eta·U·L³·eps / (4·Cg²·(1 − eps²)^1.5)     along x_hat × e_hat,
    U   = R1·(omega_cage + omega_land)                  (sum of the surface speeds, paper),
    M_x = 2·pi·eta·(omega_land − omega_cage)·R1³·L / (Cg·sqrt(1 − eps²))   on the cage,

M_x is Petroff's torque at eps = 0 (the paper's form: the pressure part e·W_t/2 is not included).

Option `dynamic` (an improvement over the paper, off by default): the short-bearing forces with the
whirl and squeeze terms of the moving cage centre (Childs, Turbomachinery Rotordynamics, 1993,
§3.5, pi-film with limits fixed on the line of centres):

    F_r = −(eta·R1·L³/(2·Cg²))·[2·eps²·(w_s − 2·phidot)/(1 − eps²)² + pi·(1 + 2·eps²)·epsdot/(1 − eps²)^2.5]
    F_t =  (eta·R1·L³/(2·Cg²))·[pi·eps·(w_s − 2·phidot)/(2·(1 − eps²)^1.5) + 4·eps·epsdot/(1 − eps²)²]

with w_s = omega_cage + omega_land, phidot the whirl rate of e_hat and epsdot = (de/dt)/Cg; with
phidot = epsdot = 0 these are W_r and W_t above. Childs' forms hold for w = w_s − 2·phidot > 0.
For w < 0 (the other sense of rotation, or a cage whirling faster than half its spin, e.g. the
synchronous whirl of a cage riding its land) the pi-film lies on the other half of the
circumference, (pi, 2pi) instead of (0, pi): the pressure's rotation part w·eps·sin(theta) and its
squeeze part eps_dot·cos(theta) are then integrated over the mirrored half, which keeps the
radial terms' restoring sign (|w| in the first) and flips the sign of the tangential squeeze term
(cos·sin is odd about the line of centres), while the tangential rotation term is linear in w
over either half:

    F_r = −(eta·R1·L³/(2·Cg²))·[2·eps²·|w|/(1 − eps²)² + pi·(1 + 2·eps²)·epsdot/(1 − eps²)^2.5]
    F_t =  (eta·R1·L³/(2·Cg²))·[pi·eps·w/(2·(1 − eps²)^1.5) + sgn(w)·4·eps·epsdot/(1 − eps²)²]

(tests/test_guide_land.py integrates the short-bearing pressure over the half for both signs of w;
tests/test_symmetry.py checks the whole model for the mirror that reverses the rotation). sgn(w)
is smoothed as tanh(w/(1 rad/s)), as the rim friction below, so the force stays continuous where
the whirl passes half the spin. (The squeeze term must change sign with w: a version that kept it for w < 0 broke the mirror.)

The film terms are evaluated at min(eps, eps_max) (default 0.95) so they stay finite; from
|e| >= Cg a rim contact takes over: a radial penalty F_rim = k_rim·(|e| − Cg) along −e_hat with
Coulomb friction mu_rim·F_rim on the rim (torque −mu_rim·F_rim·R1·sign(omega_cage − omega_land),
smoothed by tanh over 1 rad/s). k_rim is a penalty stiffness, not a Hertz law; `rim_stiffness`
gives the default (pi/4)·E'·L, the order of the Hertz line-contact stiffness of two steel
cylinders of width L. All forces and the torque act on the cage; the ring gets the opposite.

The same forms hold for a cage guided by the inner ring's land (the cage's bore is then the bush
around a turning journal): with e the cage centre's offset from the land's axis in the cage's plane
(which moves with the ring's centre and tilt: `inner_land_offset`), its rate and omega_land =
omega_i (flexbearing.multibody.guidance_kernels._cage_guidance gives the reason;
tests/test_guidance.py integrates the bush's short-bearing pressure for it). The force is normal
to the land's axis, which tilts with the ring: it has the axial part `inner_land_offset` gives.
"""
from __future__ import annotations

import math

from numba import njit

from flexbearing.common.validation import require_range
from flexbearing.mesh.cage_geometry import GUIDANCE_INNER
from flexbearing.multibody.model_layout import P_CG, P_KRIM, P_L3, P_LAND_L, P_MURIM, P_R1


@njit(cache=True)
def rim_stiffness(E_eff, width):
    """Default rim-contact penalty stiffness k_rim = (pi/4)·E'·L, N/m (see module docstring)."""
    return 0.25 * math.pi * E_eff * width


@njit(cache=True, inline="always")
def land_count(lands_width, lands_width_cubed):
    """n of n identical lands of width w from the model's n·w and n·w³ (P_LAND_L, P_L3;
    `fill_guide_land_parameters`): n = sqrt((n·w)³/(n·w³))."""
    return int(round(math.sqrt(lands_width ** 3 / lands_width_cubed)))


@njit(cache=True, inline="always")
def rim_force(e, Cg, k_rim):
    """Normal force of the rim penalty contact, N: k_rim·(e − Cg) for e > Cg, else 0 (module docstring)."""
    return k_rim * (e - Cg) if e > Cg else 0.0


@njit(cache=True)
def rim_potential(e, Cg, k_rim):
    """Potential of `rim_force`, J: k_rim·(e − Cg)²/2 for e > Cg, else 0."""
    return 0.5 * k_rim * (e - Cg) ** 2 if e > Cg else 0.0


@njit(cache=True, inline="always")
def inner_land_offset(xc, yc, zc, vxc, vyc, vzc, xi, yi, zi, tilt_y, tilt_z, vxi, vyi, vzi, tilt_y_dot, tilt_z_dot):
    """Offset e = (e_y, e_z) of the cage centre from the inner ring's land axis in the cage's plane
    x = xc, its rate de/dt, and the axial lever l = xc − xi of that axis point from the ring centre:
    (e_y, e_z, de_y/dt, de_z/dt, l), m, m/s, m.

    The land turns with the ring. Under the ring's small-angle rigid motion u = t + theta × p,
    theta = (0, tilt_y, tilt_z) (flexbearing.multibody.geometry.ring_point_in_plane, the kinematics
    of the ring's Hertz contacts), the land axis point nominally at (l, 0, 0) from the ring centre
    is at (xi + l, yi + tilt_z·l, zi − tilt_y·l), so in the cage's plane (l = xc − xi)

        e_y = yc − yi − tilt_z·l,   e_z = zc − zi + tilt_y·l.

    The rim potential V(|e|) (`rim_potential`) then depends on the ring's tilt, and its gradient is
    the force the dynamics apply (flexbearing.multibody.guidance_kernels): on the cage (F_y, F_z) =
    −dV/de and, the force being normal to the tilted land axis (1, tilt_z, −tilt_y),
    F_x = −dV/dxc = −tilt_z·F_y + tilt_y·F_z; on the ring the opposite force and the moments
    M_y = −dV/dtilt_y = l·F_z, M_z = −dV/dtilt_z = −l·F_y (Lagrange's generalised forces of the
    linearised ring kinematics, as for the Hertz contacts: race_kernels.inner_race_reaction).
    With the land axis fixed to the ring centre instead (e = (yc − yi, zc − zi)) the reaction's
    moments l·F did work on the ring's tilt that no potential stored: a conservative run's energy
    error then did not fall with the integrator's tolerance (tests/test_energy.py)."""
    lever = xc - xi
    ey = yc - yi - tilt_z * lever
    ez = zc - zi + tilt_y * lever
    vx_rel = vxc - vxi
    vey = vyc - vyi - tilt_z_dot * lever - tilt_z * vx_rel
    vez = vzc - vzi + tilt_y_dot * lever + tilt_y * vx_rel
    return ey, ez, vey, vez, lever


@njit(cache=True)
def rim_offset(guidance, xc, yc, zc, xi, yi, zi, tilt_y, tilt_z):
    """|e| of the cage centre (xc, yc, zc) from the axis of the land that guides it, m: the outer
    ring's (the bearing axis) or, for guidance code GUIDANCE_INNER, the inner ring's land axis in
    the cage's plane, which moves with the ring's centre (xi, yi, zi) and tilt (`inner_land_offset`)
    (flexbearing.mesh.cage_geometry.GUIDANCES; a ball-riding cage's offset from the origin only scales
    its recorded eccentricity)."""
    if guidance == GUIDANCE_INNER:
        ey, ez, _, _, _ = inner_land_offset(xc, yc, zc, 0.0, 0.0, 0.0, xi, yi, zi, tilt_y, tilt_z,
                                            0.0, 0.0, 0.0, 0.0, 0.0)
        return math.sqrt(ey * ey + ez * ez)
    return math.sqrt(yc * yc + zc * zc)


@njit(cache=True)
def ocvirk_forces(eps, U, eta, L, Cg):
    """(W_r, W_t) of the static short bearing, N: W_r = eta·U·L³·eps²/(Cg²(1 − eps²)²),
    W_t = pi·eta·U·L³·eps/(4·Cg²·(1 − eps²)^1.5) (Ocvirk; module docstring)."""
    q = 1.0 - eps * eps
    c = eta * U * L ** 3 / (Cg * Cg)
    return c * eps * eps / (q * q), 0.25 * math.pi * c * eps / q ** 1.5


@njit(cache=True)
def guide_land_force(ey, ez, vy, vz, omega_cage, omega_land, R1, L, Cg, eta, eps_max, dynamic,
                     k_rim, mu_rim, n_lands=1):
    """Film + rim force on the cage from the guide land: returns (F_y, F_z, M_x) in N, N, N·m.

    ey, ez: cage centre offset from the land centre (m); vy, vz its velocity (m/s, used only if
    dynamic); omega_cage, omega_land: spin speeds about +x (rad/s); R1 guiding radius (m); L width
    of one land (m), n_lands identical lands side by side (each a short bearing: forces add as
    n·L³, the Petroff torque as n·L); Cg radial clearance (m); eta viscosity (Pa·s); eps_max film cap (< 1); dynamic:
    include whirl and squeeze; k_rim (N/m), mu_rim: rim contact. Equations: module docstring.
    """
    e = math.sqrt(ey * ey + ez * ez)
    eps_true = e / Cg
    eps = min(eps_true, eps_max)
    q = 1.0 - eps * eps
    torque = 2.0 * math.pi * eta * (omega_land - omega_cage) * R1 ** 3 * n_lands * L / (Cg * math.sqrt(q))
    if e <= 0.0:
        return 0.0, 0.0, torque
    cy = ey / e
    cz = ez / e
    ws = omega_cage + omega_land
    if dynamic:
        edot = (ey * vy + ez * vz) / e                 # radial speed
        phidot = (ey * vz - ez * vy) / (e * e)         # whirl rate of e_hat about +x
        epsdot = edot / Cg
        if eps_true >= eps_max and epsdot > 0.0:
            epsdot = 0.0                               # capped film: no further squeeze growth
        c = n_lands * eta * R1 * L ** 3 / (2.0 * Cg * Cg)
        w = ws - 2.0 * phidot
        film_side = math.tanh(w)                       # which half carries the pi-film (docstring)
        wr = c * (2.0 * eps * eps * abs(w) / (q * q)
                  + math.pi * (1.0 + 2.0 * eps * eps) * epsdot / q ** 2.5)
        wt = c * (math.pi * eps * w / (2.0 * q ** 1.5) + film_side * 4.0 * eps * epsdot / (q * q))
    else:
        wr, wt = ocvirk_forces(eps, R1 * ws, eta, L, Cg)
        wr = n_lands * abs(wr)
        wt = n_lands * wt                                   # restoring for either sense of rotation
    # radial (−e_hat) and tangential (x_hat × e_hat = (−cz, cy)) components
    fy = -wr * cy - wt * cz
    fz = -wr * cz + wt * cy
    if e > Cg:
        frim = rim_force(e, Cg, k_rim)
        fy -= frim * cy
        fz -= frim * cz
        torque -= mu_rim * frim * R1 * math.tanh(omega_cage - omega_land)
    return fy, fz, torque


def fill_guide_land_parameters(p, bearing, E_eff, k_rim, mu_rim):
    """The guide land's slots of the model's parameter vector p (flexbearing.multibody.model_layout;
    flexbearing.multibody.model.build_model): R1 the cage's guiding radius (its outside on the outer
    ring's land, its bore on the inner ring's), Cg the radial clearance (Bearing.guide_clearance),
    the lands' n·L³ and n·L (the inner land runs under the whole bore; the relief and the two
    lands are on the outside), the rim's k_rim (model option rim_stiffness, N/m in [1e5, 1e13];
    None: `rim_stiffness` of E_eff, the ball–cage E', and n·L) and its friction mu_rim ([0, 1])."""
    cage = bearing.cage
    p[P_R1] = cage.inner_radius if cage.guidance == "inner" else cage.outer_radius
    p[P_CG] = bearing.guide_clearance
    if cage.guidance == "inner":
        p[P_L3] = cage.width ** 3
        p[P_LAND_L] = cage.width
    elif cage.relief_depth > 0.0:
        p[P_L3] = 2.0 * cage.land_width ** 3
        p[P_LAND_L] = 2.0 * cage.land_width
    else:
        p[P_L3] = cage.width ** 3
        p[P_LAND_L] = cage.width
    if k_rim is None:
        k_rim = rim_stiffness(E_eff, p[P_LAND_L])
    p[P_KRIM] = require_range("model.rim_stiffness", k_rim, 1e5, 1e13, unit="N/m")
    p[P_MURIM] = require_range("model.rim_friction", mu_rim, 0.0, 1.0)
