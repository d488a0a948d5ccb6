"""Equations of motion of the bearing (SPEC §4; paper §2.5) and the compiled right-hand side.

State layout: `flexbearing.multibody.model` docstring (balls in their orbiting frames, inner ring 5 DOF +
prescribed spin, rigid cage 6 DOF, empty modal block). Frames and contact conventions:
`flexbearing.multibody.geometry` (X shaft axis, azimuth psi from +Y towards +Z, (e_x, e_r, e_t) right-handed).

Ball j (mass m_b, moment of inertia I_b = m_b·Dw²/10), Newton in cylindrical coordinates, i.e.
in the frame orbiting with the ball (centrifugal and Coriolis terms explicit):

    m_b·x''                       = F_x
    m_b·(r'' − r·psi'²)           = F_r            (r·psi'² : centrifugal)
    m_b·(r·psi'' + 2·r'·psi')     = F_t            (2·r'·psi' : Coriolis)

Euler for the (isotropic) ball with its absolute angular velocity w resolved on the rotating
triad (e_x, e_r, e_t), whose angular velocity is psi'·e_x (de_r/dt = psi'·e_t, de_t/dt = −psi'·e_r):

    I_b·w_x'                      = M_x
    I_b·(w_r' − psi'·w_t)         = M_r            (psi'·w_t, psi'·w_r : gyroscopic terms of the
    I_b·(w_t' + psi'·w_r)         = M_t             orbiting frame, paper's G_y, G_z)

F and M collect, for each ball: the Hertz loads of the outer and the two inner half-grooves
(Q = K·delta^1.5, K from the exact Hertz solution at the current contact angle, tabulated in
cos(alpha)), optional viscous contact damping, the sliced EHL traction of every loaded contact
(flexbearing.multibody.traction: the paper's 4106 fit, or the EHL film-shear law when the model's flag
F_TRACTION_LAW says "ehl" (model option traction_law), with the Hamrock–Dowson central film at the contact's inlet
viscosity; transverse traction on by default, see below), the EHL rolling resistance F_R at each contact and the pressure rolling force F_H through
the ball centre (flexbearing.multibody.drag), the ball–pocket force (paper §2.3.1: linear Kc·Z up to the
pocket clearance, Hertz beyond) with the lubricated pocket's Poiseuille rolling and Couette
sliding resistances (flexbearing.multibody.pocket), the churning drag in the oil–air mixture
(flexbearing.multibody.drag: F_d = ½·rho_mix·C_d(Re)·(pi·Dw²/4)·v², mixture at rest), with the option
ball_drag_moment the mixture's viscous moment on the spinning ball (M = −pi·eta_mix·Dw³·w, drag.py),
and gravity (off).

Transverse traction (model option, default ON, unlike the paper's T_eta = 0): with traction only
along the rolling direction nothing restrains the ball's rotation about e_t, the gyroscopic
moment of the orbiting frame makes w_r and w_t drift without bound (observed: w_r ~ 1100 rad/s
after 0.5 s); the paper's statement that the preload prevents gyroscopic rotation and hence
transverse sliding is what the transverse traction enforces. With it the slip vector
(du, dv)/UR gets mu(|s|) along it (flexbearing.multibody.traction module docstring).

Ball attitude (model option `ball_attitude`, default "free" = the Euler equations above). The
options "outer", "inner" and "jones" impose race control instead (Jones, J. Basic Eng. 82(2):309,
1960, the hypothesis of flexbearing.multibody.quasi_static: the ball's spin axis lies in the ball plane,
gyroscopic pivoting is prevented, and the controlling race has no spin): with n the controlling
contact's normal (from the groove centre through the ball, in the (e_x, e_r) plane) and w_race
its race's angular velocity (0 outer, omega_i inner),

    (w − w_race·e_x)·n = 0,   w_t = 0,   I_b·(dw/dt)·u = M·u,   u = e_t × n = (−n_r, n_x, 0),

i.e. one rotational degree of freedom, the rolling about u, driven by the applied moments; the two
constraints are held by a first-order relaxation at rate k = `attitude_rate` (default 2e4 1/s,
time constant 50 us, far below the 1–10 ms of the ball and cage dynamics and far above the
integrator's 1–10 us steps). The moments that hold the constraints act on the ball as pure
couples from the races. About e_t it is the gyroscopic couple M_c = I_b·psi'·w_r − M_t of the
orbiting frame, realised as equal and opposite friction forces f·u_i at the inner and −f·u_i at
the outer contact point, f = M_c/((p_i − p_o) × u_i)_t, u_i = e_t × n_i (Jones's race-control
factors lambda_o = lambda_i = 1 when the contacts are collinear; flexbearing.multibody.quasi_static's
`friction_share` = (1, 1)); the inner ring receives −f·u_i at its contact point (option
`attitude_ring_reaction`, default on). That reaction matters: at the paper's 14,000 rpm it is
~130 N per ball along the axis, 5 % of the ring's 55 kN; without it the mean ball loads come out
5–8 % above the quasi-static ones. It also depends on the ring's position through the constraint
(a circulatory force): measured stable over 0.4 s at the paper case (55 kN, 14,000 rpm), but at
light load (2000 N axial, 4000 rpm, drag off, where it is ~35 N per ball, a third of the load)
the run leaves the race-control speed after ~0.5 s (cage 2–9 % slow at 0.8 s, gross sliding);
with the option off the same runs hold the race-control speed to 3e-4. Use it off for light-load
studies. About n the constraint moment is the spin-locking couple M_n = I_b·(dw/dt − dw/dt_free)·n:
the controlling race's spin friction. With inner-race control the inner ring takes −M_n·n (its share
of the friction torque; the outer ring is fixed); before that reaction was applied, 6 % of the
loss at the paper case went unaccounted in the power balance. Carrying the gyroscopic moment
instead as one friction force on the ball at the controlling contact (lambda = 2 there) makes
that force follow the contact normal through
the constraint, a follower force: measured, a growing axial oscillation of the balls (contact
angles ±1° to ±3.5° within 0.25 s at 2000 N, 4000 rpm) that ends in gross sliding, also at a
10 ms constraint time constant; so it is not offered. "jones" picks per ball and step the race
with the larger Q·a·cos(alpha_o − alpha_i) (outer) or Q·a (inner) (Jones's criterion with E(k)
ratio 1); an unloaded controlling race falls back to the free equations. On the balls and the
inner ring the constraint moments do the work M_n·sigma + M_t·w_t (sigma the spin on the
controlling race), zero once the constraints hold (tests/test_ball_attitude.py checks it against
the power balance). The initial state (flexbearing.multibody.initial) starts such balls on the race-control
kinematics.

"no_pivot" is the paper's own hypothesis (§2.2.2: the preload prevents the gyroscopic rotation of
the ball, so there is no sliding in the eta direction and T_eta = 0; use it with
transverse_traction off, as the paper): only the yaw is held,

    w_t → 0 at the rate k,   I_b·dw_x/dt = M_x,   I_b·dw_r/dt = M_r + I_b·psi'·w_t,

so the spin axis stays in the ball plane but its pitch beta = atan(w_r/w_x) is free and follows
the moments the contacts, pockets and drag apply about e_x and e_r; no race is assumed to roll
without spin. The gyroscopic couple M_c = I_b·psi'·w_r − M_t is carried by the same pair of
transverse friction forces as race control (and, with attitude_ring_reaction, reacted on the inner
ring). The couple acts about e_t, where w_t = 0, so it does no work on the ball: the power balance
of flexbearing.multibody.power_loss closes as for free balls (without the ring reaction). With a free ball the
gyroscopic couple instead turns the axis until beta = 0 at the test's light loads
(flexbearing.studies.validate docstring): the two hypotheses bracket what the EHL traction can hold.

Inner ring (mass m_i, diametral/polar inertia I_d, I_p, spin omega_i(t) prescribed):

    m_i·(x'', y'', z'') = F_ext(t) + sum of the race reactions
    I_d·theta_y'' = M_y − I_p·omega_i·theta_z'
    I_d·theta_z'' = M_z + I_p·omega_i·theta_y'          (gyroscopic coupling of the spinning ring)

Cage (rigid; `flexbearing.multibody.cage_body.cage_equations`): the same six equations with the cage's own spin as a degree of
freedom, I_p·omega_c' = M_x, forces from the pockets (computed in `_pocket_interface`) and from
the guide land (`_guide_land`). Hook for the flexible cage (floating frame + modal coordinates,
state block MODES of flexbearing.multibody.model): `rhs` stores per pocket j the interface force on the cage
(work[j, W_PK_FX:W_PK_FZ+1], inertial) and its cage-fixed lever (W_PK_LY, W_PK_LZ), and
`cage_equations` is the only function that turns the resultants into accelerations; a flexible
cage replaces it by M(zeta)·zeta'' + ... = Q_flex with the modal forces Phi^T·F built from those
columns (and adds the elastic pocket displacements to the pocket centres). With zero modes the
equations are these rigid ones exactly.

Guide land (formulas.md, Ocvirk short bearing; paper §2.4): with eps = e/Cg and U = R1·omega_c
(outer ring fixed, no whirl term, as the paper):
    W_r = eta0·|U|·L³·eps²/(Cg²·(1 − eps²)²)           (towards the ring centre)
    W_t = pi·eta0·U·L³·eps/(4·Cg²·(1 − eps²)^1.5)        (90° ahead of the eccentricity in the
                                                          sense of rotation)
    M_x = −2·pi·eta0·omega_c·R1³·L/(Cg·sqrt(1 − eps²))   (Petroff torque, drags the cage)
evaluated at min(eps, eps_max); at e > Cg a rim contact F = K_rim·(e − Cg)^1.5 with Coulomb
friction takes over.

Everything runs in `rhs`, compiled with numba, allocation-free: it writes dy/dt into `dydt` and
the recordable contact quantities into `work` (float64 (Z+1, N_WORK), model.W_* / WR_* columns),
among them the power every dissipative pair dissipates (flexbearing.multibody.power_loss: the work–energy
theorem of these equations closes to rounding, tests/test_power_loss.py). Every force pair acts on
both bodies: the inner ring receives the reaction to the traction's spin couple as well, and the
race velocity at a contact is the ring's rigid-body velocity there (spin of the offset centre and
tilt rates included).
"""
from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from flexbearing.multibody import model as M
from flexbearing.multibody.model import (
    F_INNER_HALVES, P_OIL_WREF,
    P_DW, P_Z, P_FE, P_FI, P_XO, P_RO, P_XIL, P_RIL, P_XIR, P_RIR, P_MB, P_IB, P_MI, P_IID,
    P_IIP, P_EBR, P_CP, P_KC, P_KN, P_RPOCKET, P_R1, P_CG,
    P_L3, P_KRIM, P_MURIM, P_ETA0, P_T0K, P_K0, P_RHO_OIL, P_OILFRAC, P_SLIN, P_UMIN,
    P_ZETA, P_MUPOCKET, P_GRAV, P_EPSMAX, P_ALPHA0, P_UREG, P_LAND_L, P_ETA_TRACTION, P_ALPHA_P,
    F_TRACTION, F_DRAG, F_DAMPING, F_TRANSVERSE, F_NSLICES, F_HERTZ_FIXED, F_LAND, F_ROLLRES, F_ATTITUDE, F_ATT_RING, P_ATT_RATE,
    F_TRACTION_LAW, F_GUIDANCE, F_POCKET_SHAPE, F_BALL_DRAG_MOMENT, P_SPIN_SCALE_INNER, P_POCKET_CONE, P_POCKET_B,
    H_K, H_ELL, H_EK, H_R, H_RX, H_RY, N_HGRID, N_WC, WC_Q, WC_COS, WC_SIN, WC_P0, WC_UR, WC_RX,
    WC_RY, WC_A, WC_SLIP, WC_DELTA, WC_FT, WC_P_TRACTION, WC_P_ROLLING, WC_P_DAMPING, W_P_POCKET,
    W_P_CHURNING, WR_P_LAND, WR_P_STRUCTURAL, W_POCKET_Q, W_POCKET_Z, W_POCKET_T, W_DRAG, W_PK_FX, W_PK_FY, W_PK_FZ, W_PK_LY, W_PK_LZ,
    WR_FX, WR_LAND_FY, WR_LAND_FZ, WR_LAND_M, WR_RIM_F, WR_RING_TORQUE, WR_EPS, WR_OMEGA_I,
    WR_STATUS, WR_BAD_BALL, WR_BAD_CONTACT, WR_BAD_VALUE,
)
from flexbearing.multibody.geometry import cross, race_contact, ring_point_in_plane, ring_velocity_at, ring_velocity_in_plane
from flexbearing.multibody.profiles import load_at, speed_at
from flexbearing.multibody.guide_land import guide_land_force
from flexbearing.multibody.pocket import (pocket_curvature_radii, pocket_resistance_coefficients,
                                          spherical_pocket_curvature_radii, pocket_contact_offset,
                                          pocket_axis_point)
from flexbearing.multibody.oil_supply import cavity_oil_fraction
from flexbearing.multibody.drag import (ball_drag_moment_coefficient, churning_drag, ehl_rolling_resistance,
                                       ehl_pressure_rolling_force, oil_air_mixture)
from flexbearing.multibody.traction import TRACTION_LAWS, sliced_traction, sliced_traction_ehl, traction_coefficients_table
from flexbearing.multibody.film import film_thickness as hamrock_dowson_film
from flexbearing.multibody.cage_body import cage_body_angular_velocity, cage_equations, cage_rotation, pocket_pose_arrays
from flexbearing.multibody.floating_frame import add_node_load
from flexbearing.multibody.state_layout import (
    BALL_PSI, BALL_PSI_DOT, BALL_R, BALL_R_DOT, BALL_W_R, BALL_W_T, BALL_W_X, BALL_X, BALL_X_DOT,
    CAGE_OMEGA, CAGE_PHI, CAGE_TILT_Y, CAGE_TILT_Z, CAGE_VY, CAGE_VZ, CAGE_X, CAGE_Y, CAGE_Z,
    RING_PHI, RING_POSITIONS, RING_TILT_Y, RING_TILT_Y_DOT, RING_TILT_Z, RING_TILT_Z_DOT, RING_VX, RING_VY,
    RING_VZ, RING_X, RING_Y, RING_Z, ball_offset, cage_offset, modal_offset, ring_offset,
)



def _invalidate_stale_numba_cache() -> None:
    """Drop the compiled kernels' numba cache when any source they link changed.

    numba's on-disk cache of a function is keyed on its own source file only, but `rhs` links in
    the compiled code of other modules (geometry, traction, profiles, hertz, the floating frame,
    ...), the integrator links `rhs` and the stress monitor (which links flexbearing.fem_cage.von_mises): an
    edit there would otherwise leave a stale kernel in the cache. A hash of every source of this
    package and of flexbearing/fem_cage/von_mises.py is kept next to the cache; on mismatch the cached entries
    of every module of the package are removed.
    """
    import hashlib
    import os
    import glob
    here = os.path.dirname(os.path.abspath(__file__))
    sources = sorted(glob.glob(os.path.join(here, "*.py")))
    sources.append(os.path.join(here, "..", "fem_cage", "von_mises.py"))
    h = hashlib.sha1()
    for path in sources:
        try:
            with open(path, "rb") as f:
                h.update(os.path.basename(path).encode())
                h.update(f.read())
        except OSError:
            pass
    cache = os.environ.get("NUMBA_CACHE_DIR") or os.path.join(here, "__pycache__")
    stamp = os.path.join(cache, "flexbearing_rhs_sources.sha1")
    try:
        with open(stamp) as f:
            if f.read().strip() == h.hexdigest():
                return
    except OSError:
        pass
    try:
        os.makedirs(cache, exist_ok=True)
        for path in sources[:-1]:
            stem = os.path.splitext(os.path.basename(path))[0]
            for fn in glob.glob(os.path.join(cache, "**", f"{stem}.*.nb[ic]"), recursive=True):
                os.remove(fn)
        with open(stamp, "w") as f:
            f.write(h.hexdigest())
    except OSError:
        pass


_invalidate_stale_numba_cache()

# status codes written into work[Z, WR_STATUS] (first offence wins)
TRACTION_EHL = TRACTION_LAWS.index("ehl")   # flags[F_TRACTION_LAW] of the EHL film-shear law
STATUS_OK = 0
STATUS_DEEP_RACE = 1        # race approach beyond DELTA_MAX_FRAC·Dw
STATUS_DEEP_POCKET = 2      # ball beyond the pocket clearance by more than DELTA_MAX_FRAC·Dw
STATUS_RIM = 3              # cage beyond the guide clearance by more than its clearance
STATUS_NONFINITE = 4
POCKET_H_MIN = 1e-7        # m: floor of the ball–pocket gap in the sliding resistance (assumed)
DELTA_MAX_FRAC = 0.01       # 220 um for Dw = 22 mm: ~4x the Hertz approach at the static capacity
CONTACT_NAMES = ("outer race", "inner-left race", "inner-right race", "pocket", "guide land rim")


# ---------------------------------------------------------------- named results of the contact laws
RaceContact = namedtuple("RaceContact", "q cos_a sin_a p0 ur rx ry a slip delta fx fr ft mx mr mt x_p r_p "
                                        "cx cr p_traction p_rolling p_damping f_h")
RaceContact.__doc__ = "One ball–race contact (`_race` docstring: fields, units SI)."
PocketContact = namedtuple("PocketContact", "fx fy fz mx my mz x_action y_action z_action q offset power")
PocketContact.__doc__ = "One ball–pocket contact (`_pocket_force` docstring), inertial components, SI."
GuidanceLoad = namedtuple("GuidanceLoad", "fy fz mx eps rim_force")
GuidanceLoad.__doc__ = ("What guides the cage (`_cage_guidance`): force (y, z) (N) and torque about X (N·m) on the "
                        "cage, eccentricity ratio e/Cg and the rim's normal force (N).")


@njit(cache=True)
def _hertz_lookup(htab, kind, cos_a):
    """Linear interpolation of the Hertz table (model._hertz_tables) at cos(alpha) in [0, 1]."""
    x = cos_a * (N_HGRID - 1)
    if x < 0.0:
        x = 0.0
    i = int(x)
    if i >= N_HGRID - 1:
        i = N_HGRID - 2
    w = x - i
    K = htab[kind, i, H_K] * (1.0 - w) + htab[kind, i + 1, H_K] * w
    ell = htab[kind, i, H_ELL] * (1.0 - w) + htab[kind, i + 1, H_ELL] * w
    ek = htab[kind, i, H_EK] * (1.0 - w) + htab[kind, i + 1, H_EK] * w
    R = htab[kind, i, H_R] * (1.0 - w) + htab[kind, i + 1, H_R] * w
    rx = htab[kind, i, H_RX] * (1.0 - w) + htab[kind, i + 1, H_RX] * w
    ry = htab[kind, i, H_RY] * (1.0 - w) + htab[kind, i + 1, H_RY] * w
    return K, ell, ek, R, rx, ry


@njit(cache=True)
def control_race(attitude, q_o, a_o, nxo, nro, q_i, a_i, nxi, nri):
    """Race that controls a ball's attitude (module docstring, "Ball attitude"): 0 outer, 1 inner,
    −1 free (attitude 0, or the controlling race unloaded), −2 no pivoting (attitude 4: no race
    controls, only the yaw w_t is held). attitude 1 outer, 2 inner, 3 Jones:
    the race with the larger spin-friction capacity Q·a·E(k) controls, the outer one entering with
    cos(alpha_o − alpha_i) = −n_o·n_i (E(k) ratio taken as 1). q, a load and semi-major axis, n the
    contact normal (n_x, n_r) of the outer and of the more loaded inner contact."""
    if attitude == 4:
        return -2
    if attitude == 1:
        return 0 if q_o > 0.0 else -1
    if attitude == 2:
        return 1 if q_i > 0.0 else -1
    if attitude == 3:
        if q_o > 0.0 and q_i > 0.0:
            cos_oi = -(nxo * nxi + nro * nri)
            return 0 if q_o * a_o * cos_oi >= q_i * a_i else 1
        if q_o > 0.0:
            return 0
        if q_i > 0.0:
            return 1
    return -1


@njit(cache=True)
def _race(kind, xb, rb, xc, rc, f, vb_x, vb_r, vb_t, w_x, w_r, w_t, psid,
          rv_x, rv_r, rv_t0, ring_speed, ring_rc, g1, g2, cd_x, cd_r, p, flags, htab, ttab):
    """One ball–race contact: load, geometry and the forces/moments on the ball.

    kind 0 outer, 1 inner. (xc, rc) groove centre in the ball plane; (rv_x, rv_r, rv_t0, g1, g2,
    ring_rc) and ring_speed give the race's rigid-body velocity at any point of the ball plane
    (geometry.ring_velocity_in_plane: translation, spin of the offset centre, tilt rates; all zero
    for the fixed outer ring). (cd_x, cd_r) = d(xc, rc)/dt, the rate of the
    groove centre seen in the ball's plane (it follows the ball around an offset or tilted ring),
    gives the approach rate d(delta)/dt = (v_b − c')·n of the contact damping: the spin of a
    groove about its own axis does not move it. Returns RaceContact(q, cos_a, sin_a, p0, ur, rx,
    ry, a, slip, delta, fx, fr, ft, mx, mr, mt, x_p, r_p, cx, cr, p_traction, p_rolling, p_damping,
    f_h): load Q, contact angle, Hertz pressure, rolling speed UR, curvature radii, semi-major axis,
    slide-to-roll ratio, approach, with F, M the force and the moment about the ball centre acting on the ball; the race receives
    −F at the contact point (x_p, r_p), the couple −(Cx, Cr, 0), the traction's spin moment about
    the contact normal, and the couple (b − p) × (−F_H·e_t) that puts its share −F_H of the pressure
    rolling force on the ball's line of action, through the ball centre (every pair then has zero
    net force and zero net moment, so its power does not depend on the observer's rotation). P_* is the power the contact dissipates (flexbearing.multibody.power_loss; P_traction
    and P_damping are never negative):

        P_traction = T_t·du0 − M_n·du1 + T_tau·dv     (Σ over the slices of tau·du, exact for the
                                                        linear du(y) = du0 + du1·y of the slices)
        P_rolling  = F_R·du0 − F_H·(v_b,t − v_ring,t(b))   (F_R at the contact, F_H through the
                                                        ball centre b on both bodies)
        P_damping  = (Q − Q_el)·d(delta)/dt
    """
    dw = p[P_DW]
    delta, ca, sa = race_contact(xb, rb, xc, rc, f, dw)
    if delta <= 0.0:
        return RaceContact(0.0, ca, sa, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, delta,
                           0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    dx = xb - xc
    dr = rb - rc
    dist = math.sqrt(dx * dx + dr * dr)
    nx = dx / dist
    nr = dr / dist
    if flags[F_HERTZ_FIXED]:
        K, ell, ek, R, rx, ry = _hertz_lookup(htab, kind, math.cos(p[P_ALPHA0]))
    else:
        K, ell, ek, R, rx, ry = _hertz_lookup(htab, kind, ca)
    sqd = math.sqrt(delta)
    q_el = K * delta * sqd
    rho = 0.5 * dw - 0.5 * delta
    x_p = xb + rho * nx
    r_p = rb + rho * nr
    # race surface velocity at the contact point (docstring)
    vrace_x, vrace_r, vrace_t = ring_velocity_at(rv_x, rv_r, rv_t0, g1, g2, ring_rc, ring_speed, x_p, r_p)
    # approach rate d(delta)/dt = (v_b − c')·n (docstring)
    approach = (vb_x - cd_x) * nx + (vb_r - cd_r) * nr
    Q = q_el
    if flags[F_DAMPING]:
        c = 2.0 * p[P_ZETA] * math.sqrt(1.5 * K * sqd * p[P_MB])
        Q = q_el + c * approach
        if Q < 0.0:
            Q = 0.0
    p_damp = (Q - q_el) * approach
    p_trac = 0.0
    p_roll = 0.0
    cx = 0.0
    cr = 0.0
    Fx = -Q * nx
    Fr = -Q * nr
    Ft = 0.0
    Mx = 0.0
    Mr = 0.0
    Mt = 0.0
    # contact ellipse (Hertz, elastic part of the load)
    b_ax = (6.0 * ek * q_el * R / (math.pi * ell * p[P_EBR])) ** (1.0 / 3.0)
    a_ax = ell * b_ax
    p0 = 1.5 * q_el / (math.pi * a_ax * b_ax)
    # surface speeds in the rolling direction at the contact centre (geometry.contact_kinematics)
    vball_t = vb_t + rho * (w_x * nr - w_r * nx)
    vc = r_p * psid
    ur = 0.5 * ((vball_t - vc) + (vrace_t - vc))
    du0 = vrace_t - vball_t
    slip = du0 / abs(ur) if ur != 0.0 else 0.0
    if flags[F_TRACTION] and Q > 0.0:
        # transverse direction tau = (cos a, −sin a) = (−n_r, n_x)·sign ; use tau = (nr, −nx)
        # for the outer (n_r > 0) and (−nr, nx) for the inner, i.e. tau = s·(nr, −nx), s = sign(n_r)
        sg = 1.0 if nr >= 0.0 else -1.0
        tx_ = sg * nr
        tr_ = -sg * nx
        # du(y) = race − ball along e_t at p + y·tau: ball adds (w × y·tau)_t = y(w_x·tau_r − w_r·tau_x),
        # race adds y·(ring_speed·tau_r − g2·tau_x) (g2: the ring's tilt rate about e_r)
        du1 = ring_speed * tr_ - g2 * tx_ - (w_x * tr_ - w_r * tx_)
        # transverse sliding race − ball at the centre (ball: v_b + w × rho·n, ring: rigid-body velocity)
        vball_x = vb_x - rho * w_t * nr
        vball_r = vb_r + rho * w_t * nx
        dv = (vrace_x - vball_x) * tx_ + (vrace_r - vball_r) * tr_
        urr = abs(ur)
        if urr < p[P_UMIN]:
            urr = p[P_UMIN]
        if flags[F_TRACTION_LAW] == TRACTION_EHL:
            # EHL film-shear law (flexbearing.multibody.traction): the film at the contact's inlet viscosity
            eta_in = p[P_ETA0] * math.exp(-ttab[7, 3] * ttab[7, 0])
            h_c = hamrock_dowson_film(rx, ry, p[P_EBR], q_el, urr, eta_in, p[P_ALPHA_P])[1]
            Tt, Ttau, Mn = sliced_traction_ehl(Q, a_ax, b_ax, p0, h_c, urr, du0, du1, 0.0, dv,
                                               flags[F_NSLICES], flags[F_TRANSVERSE] != 0, p[P_SLIN],
                                               p[P_ETA0], p[P_ALPHA_P], p[P_K0], ttab)
        else:
            # the fit at UR_eff = max(|UR|, u_reg): coefficients and slide-to-roll ratio
            # (flexbearing.multibody.traction, "Low rolling speed")
            u_s = urr if urr > p[P_UREG] else p[P_UREG]
            A, B, C, D = traction_coefficients_table(Q, u_s, rx, p[P_EBR], p[P_ETA_TRACTION], p[P_T0K], p[P_K0], ttab)
            Tt, Ttau, Mn = sliced_traction(Q, a_ax, u_s, du0, du1, 0.0, dv, A, B, C, D,
                                           flags[F_NSLICES], flags[F_TRANSVERSE] != 0, p[P_SLIN])
        if kind == 1:
            # diagnostic of the race-control screening (model option spin_moment_scale_inner, 1 = the law)
            Mn *= p[P_SPIN_SCALE_INNER]
        # force on the ball at p: Tt·e_t + Ttau·tau
        Fx += Ttau * tx_
        Fr += Ttau * tr_
        Ft += Tt
        # moment about the ball centre of the force at rho·n: (rho n) × F ; n = (nx, nr, 0)
        Mx += rho * (nr * Tt)
        Mr += -rho * (nx * Tt)
        Mt += rho * (nx * Ttau * tr_ - nr * Ttau * tx_)
        # spin moment about e_t × tau = (−tau_r, tau_x, 0)·(−1)... e_t × tau = (-(tau_r)*(-1)...)
        # e_t × tau with e_t = (0,0,1): (0·0 − 1·tau_r, 1·tau_x − 0·0, 0) = (−tau_r, tau_x, 0)
        cx = -Mn * tr_
        cr = Mn * tx_
        Mx += cx
        Mr += cr
        p_trac = Tt * du0 - Mn * du1 + Ttau * dv
    if flags[F_ROLLRES] and flags[F_DRAG]:
        # EHL rolling resistance (flexbearing.multibody.drag): F_R at the contact, opposite to the entrainment
        # speed, and the pressure rolling force F_H = −2(Rx/r_b)·F_R through the ball centre
        f_r = ehl_rolling_resistance(q_el, ur, rx, ell, p[P_EBR], p[P_ETA0], p[P_ALPHA_P])
        f_h = ehl_pressure_rolling_force(f_r, rx, 0.5 * dw)
        Ft += f_r + f_h
        Mx += rho * nr * f_r
        Mr += -rho * nx * f_r
        # the race takes −F_H on the same line, through the ball centre (a balanced pair): its
        # velocity there is the ring's rigid-body velocity at (xb, rb)
        vring_bt = ring_velocity_at(rv_x, rv_r, rv_t0, g1, g2, ring_rc, ring_speed, xb, rb)[2]
        p_roll = f_r * du0 - f_h * (vb_t - vring_bt)
    return RaceContact(Q, ca, sa, p0, ur, rx, ry, a_ax, slip, delta, Fx, Fr, Ft, Mx, Mr, Mt, x_p, r_p,
                       cx, cr, p_trac, p_roll, p_damp, f_h)


@njit(cache=True)
def pocket_film_coefficients(p, flags):
    """(c_R, c_S, r) of the lubricated pocket's rolling and sliding resistances
    (flexbearing.multibody.pocket.pocket_resistance_coefficients) for the model's ball, pocket and oil:
    entrainment radius Rb, transverse radius R_xi (pocket.pocket_curvature_radii) in a cylindrical
    pocket; both radii conforming in a spherical one (pocket.spherical_pocket_curvature_radii).
    Constant for a model; `rhs` evaluates them once per call and hands them to `_pocket_force`."""
    if flags[F_POCKET_SHAPE] != 1:          # cylinder; cone, ellipse at their nominal contact (pocket docstring)
        rxi, reta = pocket_curvature_radii(0.5 * p[P_DW], p[P_RPOCKET] if flags[F_POCKET_SHAPE] != 3
                                           else p[P_RPOCKET] ** 2 / p[P_POCKET_B])
    else:
        rxi, reta = spherical_pocket_curvature_radii(0.5 * p[P_DW], p[P_RPOCKET])
    return pocket_resistance_coefficients(reta, rxi, p[P_ETA0])


@njit(cache=True)
def _pocket_interface(bx, by, bz, vbx, vby, vbz, wbx, wby, wbz,
                      px, py, pz, ax, ay, az, vpx, vpy, vpz, wcx, wcy, wcz, cx, cy, cz, p, flags):
    """`_pocket_force` with the film coefficients of `pocket_film_coefficients` (one pocket on its
    own, as the tests and benchmarks call it)."""
    c_roll, c_slide, c_root = pocket_film_coefficients(p, flags)
    return _pocket_force(bx, by, bz, vbx, vby, vbz, wbx, wby, wbz, px, py, pz, ax, ay, az, vpx, vpy, vpz,
                         wcx, wcy, wcz, cx, cy, cz, p, flags, c_roll, c_slide, c_root)


@njit(cache=True)
def _pocket_force(bx, by, bz, vbx, vby, vbz, wbx, wby, wbz,
                  px, py, pz, ax, ay, az, vpx, vpy, vpz, wcx, wcy, wcz, cx, cy, cz, p, flags, c_roll, c_slide,
                  c_root):
    """Ball–pocket force of one pocket (paper §2.3.1), inertial components.

    b ball centre, (px, py, pz) pocket centre, a pocket axis (radial, unit), v_p the velocity of
    the pocket centre, w_c the cage angular velocity, c the cage centre. Offset of the ball from
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
                                                       p[P_POCKET_CONE], p[P_RPOCKET], p[P_POCKET_B])
    if zz < 1e-15:
        return PocketContact(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, px, py, pz, 0.0, zz, 0.0)
    ux /= zz
    uy /= zz
    uz /= zz
    cp = p[P_CP]
    kc = p[P_KC]
    if zz <= cp:
        Q = kc * zz
        q_el = Q
    else:
        pen = zz - cp
        sq = math.sqrt(pen)
        Q = kc * cp + p[P_KN] * pen * sq
        q_el = Q
        if flags[F_DAMPING]:
            # approach rate along u: (v_b − v_pocket point)·u
            rate = (vbx - vpx) * ux + (vby - vpy) * uy + (vbz - vpz) * uz
            c = 2.0 * p[P_ZETA] * math.sqrt(1.5 * p[P_KN] * sq * p[P_MB])
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
        # Lubricated pocket (flexbearing.multibody.pocket; paper §2.3.2): on each side s = ±1 of the ball
        # (points b + s·Rb·u and p + (d·a)a + s·Rp·u) the ball surface slides on the pocket wall at
        # g = (v_ball − v_wall) tangential; the film there gives the Poiseuille rolling resistance
        # F_R (entrainment g/2 relative to the wall, independent of the gap) and the Couette
        # sliding resistance F_S (gap h0 = Cp − s·Z, floored at POCKET_H_MIN, wetted edge at the
        # gap Cp), both along −g on the ball. Entrainment radius Rb (the ball surface runs along
        # the radial pocket axis), transverse radius R_xi (conforming, pocket.pocket_curvature_radii).
        # With c_R, c_S, r of `pocket_film_coefficients`: F_R = (c_R·g/2)·r, F_S = ((c_S·g)·r)·ln(Cp/h0)
        # (zero for h0 >= Cp, i.e. on the unloaded side), evaluated as pocket_rolling_resistance and
        # pocket_sliding_resistance do (bit-identical).
        rb = 0.5 * p[P_DW]
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
            f_r = c_roll * (0.5 * g) * c_root
            f_s = c_slide * g * c_root * math.log(cp_gap / h0) if cp_gap > h0 else 0.0
            # Coulomb part (option pocket_friction, default 0) on the loaded side only
            f_c = p[P_MUPOCKET] * Q if side > 0.0 else 0.0
            tf = (f_r + f_s + f_c) / g
            fx -= tf * gx
            fy -= tf * gy
            fz -= tf * gz
            m1, m2, m3 = cross(side * rb * ux, side * rb * uy, side * rb * uz, -tf * gx, -tf * gy, -tf * gz)
            mx += m1
            my += m2
            mz += m3
    # dissipated power (docstring): relative velocity of the ball centre to the cage point there
    r1, r2, r3 = cross(wcx, wcy, wcz, dx, dy, dz)
    pw = ((fx + q_el * ux) * (vbx - vpx - r1) + (fy + q_el * uy) * (vby - vpy - r2)
          + (fz + q_el * uz) * (vbz - vpz - r3)
          + mx * (wbx - wcx) + my * (wby - wcy) + mz * (wbz - wcz))
    return PocketContact(fx, fy, fz, mx, my, mz, qx, qy, qz, Q, zz, -pw)


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
    # n lands of width w: P_LAND_L = n·w, P_L3 = n·w³  ->  n = sqrt(P_LAND_L³ / P_L3)
    n_lands = int(round(math.sqrt(p[P_LAND_L] ** 3 / p[P_L3])))
    fy, fz, mx = guide_land_force(yc, zc, vy, vz, omega_c, 0.0, p[P_R1], p[P_LAND_L] / n_lands, cg,
                                  eta, p[P_EPSMAX], True, p[P_KRIM], mu, n_lands)
    frim = p[P_KRIM] * (e - cg) if e > cg else 0.0
    return GuidanceLoad(fy, fz, mx, e / cg, frim)


@njit(cache=True)
def _cage_guidance(yc, zc, vyc, vzc, omega_c, yi, zi, vyi, vzi, omega_i, p, flags):
    """Force (y, z) and torque about X on the cage from what guides it (flags[F_GUIDANCE]), plus
    eps and the rim force: GuidanceLoad(fy, fz, mx, eps, rim_force).

    "outer" (0): `_guide_land`, the outer ring's land, fixed. "inner" (1): the same short-bearing
    film and rim between the cage bore and the inner ring's land, with the cage offset and
    velocity taken relative to the ring's centre, e = (yc − yi, zc − zi), and the land turning
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
    if g == 0:
        return _guide_land(yc, zc, vyc, vzc, omega_c, p, flags)
    if g == 2:
        return GuidanceLoad(0.0, 0.0, 0.0, 0.0, 0.0)
    ey = yc - yi
    ez = zc - zi
    e = math.sqrt(ey * ey + ez * ez)
    cg = p[P_CG]
    eta = p[P_ETA0] if flags[F_LAND] else 0.0
    mu = p[P_MURIM] if flags[F_DRAG] else 0.0
    n_lands = int(round(math.sqrt(p[P_LAND_L] ** 3 / p[P_L3])))
    fy, fz, mx = guide_land_force(ey, ez, vyc - vyi, vzc - vzi, omega_c, omega_i, p[P_R1],
                                  p[P_LAND_L] / n_lands, cg, eta, p[P_EPSMAX], True, p[P_KRIM], mu,
                                  n_lands)
    frim = p[P_KRIM] * (e - cg) if e > cg else 0.0
    return GuidanceLoad(fy, fz, mx, e / cg, frim)


@njit(cache=True)
def _flag(work, zb, status, ball, contact, value):
    if work[zb, WR_STATUS] == 0.0:
        work[zb, WR_STATUS] = status
        work[zb, WR_BAD_BALL] = ball
        work[zb, WR_BAD_CONTACT] = contact
        work[zb, WR_BAD_VALUE] = value


# ---------------------------------------------------------------- the kernels of `rhs`
# Named results: namedtuples are value types in nopython mode (no allocation); fields read by name.
# Compilation: the kernels are inlined into `rhs` by numba (inline="always"; as separate LLVM
# functions they are not inlined and the calls cost ~1 us per rhs), and `rhs` and the kernels are
# compiled without NRT reference counting (_nrt=False; they allocate nothing): with it every array a
# kernel takes costs an atomic increment and decrement per ball (measured: 20 us per rhs instead
# of 14 us at the paper's rigid-cage state). Both are numba options that change the machine code
# only, never the arithmetic: dy/dt is bit-identical to the single-function rhs (benchmarks/rhs_ab.py).
BallState = namedtuple("BallState", "x r psi x_dot r_dot psi_dot w_x w_r w_t cos_psi sin_psi v_t")
BallState.__doc__ = "Ball j's state slots (state_layout.BALL_*), cos/sin of its azimuth and its orbital speed r·psi'."
RingState = namedtuple("RingState", "x y z tilt_y tilt_z vx vy vz tilt_y_dot tilt_z_dot")
RingState.__doc__ = "The inner ring's positions and rates (state_layout.RING_*), inertial, m, rad, m/s, rad/s."
BallLoad = namedtuple("BallLoad", "fx fr ft mx mr mt")
BallLoad.__doc__ = "Force (N) and moment about the centre (N·m) on a ball, on its orbiting triad (e_x, e_r, e_t)."
RingLoad = namedtuple("RingLoad", "fx fy fz mx my mz")
RingLoad.__doc__ = "Force (N) and moment about its centre (N·m) on the inner ring from the balls and the cage, inertial."
RaceControl = namedtuple("RaceControl", "q_outer a_outer nx_outer nr_outer x_outer r_outer "
                                        "q_inner a_inner nx_inner nr_inner x_inner r_inner")
RaceControl.__doc__ = ("Load Q (N), semi-major axis a (m), contact normal (n_x, n_r) from the groove centre through "
                       "the ball and contact point (x, r) of the outer contact and of the more loaded inner half: "
                       "what `control_race` and the race-control couple need.")
BallRaceContacts = namedtuple("BallRaceContacts", "ball ring control")
Attitude = namedtuple("Attitude", "control n_x n_r w_race u_x u_r ring")
Attitude.__doc__ = ("The controlling race of a ball (`control_race` code), its contact normal (n_x, n_r), its "
                    "angular velocity w_race (rad/s), the free rolling axis u = e_t × n, and the inner ring's "
                    "load with the race-control couple's reaction added.")
CageFrame = namedtuple("CageFrame", "A w_body pos vel axis w_node force torque q_modes node_load "
                                    "node_position node_modes q_ext")
CageFrame.__doc__ = ("The cage's arrays the pockets use, taken once per rhs (every array view costs an atomic "
                     "reference count; made per ball they were ~20 % of a rigid cage's rhs): rotation A, scratch "
                     "rows, modal coordinates, node loads, node geometry and modes, modal force Q_ext.")


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


@njit(cache=True, _nrt=False, inline="always")
def _record_race_contact(work, j, c, res, ft):
    """Contact c of ball j into its work columns (model.WC_*), ft the tangential force with the lean term."""
    wc = c * N_WC
    work[j, wc + WC_Q] = res.q
    work[j, wc + WC_COS] = res.cos_a
    work[j, wc + WC_SIN] = res.sin_a
    work[j, wc + WC_P0] = res.p0
    work[j, wc + WC_UR] = res.ur
    work[j, wc + WC_RX] = res.rx
    work[j, wc + WC_RY] = res.ry
    work[j, wc + WC_A] = res.a
    work[j, wc + WC_SLIP] = res.slip
    work[j, wc + WC_DELTA] = res.delta
    work[j, wc + WC_FT] = ft
    work[j, wc + WC_P_TRACTION] = res.p_traction
    work[j, wc + WC_P_ROLLING] = res.p_rolling
    work[j, wc + WC_P_DAMPING] = res.p_damping


@njit(cache=True, _nrt=False, inline="always")
def inner_race_reaction(res, ft, ft_lean, b, ring, x0, rr0, rl):
    """The inner ring's share of one inner contact (`_race`), added to the ring load rl.

    Normal part (+Q·n through the groove centre): generalised forces of the linearised ring
    kinematics (geometry.ring_point_in_plane), i.e. −dV/du of the Hertz potential, so that the force
    field stays conservative: with g = Q·n in the ball plane, n = (−sin a, −cos a),
        F = (g_x, g_r cos psi, g_r sin psi),
        M_y = sin psi·(g_x r0 − g_r x0),  M_z = −cos psi·(g_x r0 − g_r x0).
    Traction part (all the rest of −F): force at the contact point with its lever from the ring
    centre (this also gives the drive torque about X). The lean force (`ball_race_contacts`) is the
    psi-gradient of the ball's Hertz potential; the ring's generalised forces above already are the
    exact ring gradient, so it has no reaction here (momentum is then off by Q·t_c/r_b ~ 1e-5·Q:
    second order). Then the reaction to the traction's spin couple (Cx, Cr) on the ball, and the
    couple (b − p) × (−F_H·e_t) that moves the ring's share of the pressure rolling force onto the
    line through the ball centre (`_race` docstring).
    """
    cs = b.cos_psi
    sn = b.sin_psi
    qn = res.q
    gxn = -qn * res.sin_a
    grn = -qn * res.cos_a
    rfx = rl.fx + gxn
    rfy = rl.fy + grn * cs
    rfz = rl.fz + grn * sn
    arm = gxn * rr0 - grn * x0
    rmy = rl.my + sn * arm
    rmz = rl.mz - cs * arm
    gx = -res.fx - gxn
    gr = -res.fr - grn
    gt = -(ft - ft_lean)
    gy = gr * cs - gt * sn
    gz = gr * sn + gt * cs
    rfx += gx
    rfy += gy
    rfz += gz
    lx = res.x_p - ring.x
    ly = res.r_p * cs - ring.y
    lz = res.r_p * sn - ring.z
    m1, m2, m3 = cross(lx, ly, lz, gx, gy, gz)
    h1, h2, h3 = cross(b.x - res.x_p, (b.r - res.r_p) * cs, (b.r - res.r_p) * sn,
                       0.0, res.f_h * sn, -res.f_h * cs)
    return RingLoad(rfx, rfy, rfz, rl.mx + (m1 - res.cx + h1), rmy + (m2 - res.cr * cs + h2),
                    rmz + (m3 - res.cr * sn + h3))


@njit(cache=True, _nrt=False, inline="always")
def ball_race_contacts(j, b, ring, omega_i, p, flags, htab, ttab, work, load, rl):
    """Ball j's race contacts (`_race`: Hertz Q = K·delta^1.5, EHL traction, rolling resistance,
    damping; outer, inner-left and on a split ring inner-right), added to the ball load and the
    ring load rl, recorded into work; returns BallRaceContacts(ball, ring, control).

    The groove-centre circle of a displaced (offset, tilted) ring is not centred on the bearing
    axis: seen from the ball the contact normal leans out of the ball plane,
        F_t = −(Q/r_b)·d(delta)/d(psi) = (Q/r_b)·(n_x·dx_c/dpsi + n_r·dr_c/dpsi),
    with (geometry.ring_point_in_plane) dx_c/dpsi = r0·th', dr_c/dpsi = t_c − x0·th',
    t_c = −y_i·sin psi + z_i·cos psi, th' = tilt_y·cos psi + tilt_z·sin psi, and n = (−sin a, −cos a)
    for an inner race. This keeps the Hertz force the exact gradient of its potential
    (tests/test_energy.py). The groove-centre rate (the ring's own motion and the ball's orbit
    around it) gives the contact damping's approach rate.
    """
    zb = int(p[P_Z])
    dw = p[P_DW]
    cs = b.cos_psi
    sn = b.sin_psi
    psid = b.psi_dot
    # race-control attitude (module docstring): outer contact and the more loaded inner half
    ctl = RaceControl(0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0)
    # inner-ring rigid-body velocity field over the ball plane: translation, the spin of the
    # offset centre, the tilt rates
    rv_x, rv_r, rv_t, g1, g2, ring_rc = ring_velocity_in_plane(b.psi, omega_i, ring.x, ring.y, ring.z, ring.vx,
                                                               ring.vy, ring.vz, ring.tilt_y_dot, ring.tilt_z_dot)
    rv_r_trans = ring.vy * cs + ring.vz * sn
    # contact 2 (the second inner half) exists on a split ring only (model.F_INNER_HALVES)
    for c in range(1 + flags[F_INNER_HALVES]):
        ft_lean = 0.0
        x0 = 0.0
        rr0 = 0.0
        if c == 0:
            res = _race(0, b.x, b.r, p[P_XO], p[P_RO], p[P_FE], b.x_dot, b.r_dot, b.v_t, b.w_x, b.w_r, b.w_t, psid,
                        0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, p, flags, htab, ttab)
            ft = res.ft
        else:
            if c == 1:
                x0 = p[P_XIL]
                rr0 = p[P_RIL]
            else:
                x0 = p[P_XIR]
                rr0 = p[P_RIR]
            xc_g, rc_g = ring_point_in_plane(b.psi, x0, rr0, ring.x, ring.y, ring.z, ring.tilt_y, ring.tilt_z)
            th_rate = (ring.tilt_y_dot * sn - ring.tilt_z_dot * cs) + (ring.tilt_y * cs + ring.tilt_z * sn) * psid
            cd_x = ring.vx + rr0 * th_rate
            cd_r = rv_r_trans + (-ring.y * sn + ring.z * cs) * psid - x0 * th_rate
            res = _race(1, b.x, b.r, xc_g, rc_g, p[P_FI], b.x_dot, b.r_dot, b.v_t, b.w_x, b.w_r, b.w_t, psid,
                        rv_x, rv_r, rv_t, omega_i, ring_rc, g1, g2, cd_x, cd_r, p, flags, htab, ttab)
            ft = res.ft
            if res.q > 0.0:
                thp = ring.tilt_y * cs + ring.tilt_z * sn
                dxc = rr0 * thp
                drc = (-ring.y * sn + ring.z * cs) - x0 * thp
                ft_lean = res.q * (-res.sin_a * dxc - res.cos_a * drc) / b.r
                ft = res.ft + ft_lean
        if c == 0:      # outer: n = (sin a, cos a)
            ctl = RaceControl(res.q, res.a, res.sin_a, res.cos_a, res.x_p, res.r_p, ctl.q_inner, ctl.a_inner,
                              ctl.nx_inner, ctl.nr_inner, ctl.x_inner, ctl.r_inner)
        elif res.q > ctl.q_inner:      # inner: n = (−sin a, −cos a)
            ctl = RaceControl(ctl.q_outer, ctl.a_outer, ctl.nx_outer, ctl.nr_outer, ctl.x_outer, ctl.r_outer,
                              res.q, res.a, -res.sin_a, -res.cos_a, res.x_p, res.r_p)
        _record_race_contact(work, j, c, res, ft)
        if res.delta > DELTA_MAX_FRAC * dw:
            _flag(work, zb, STATUS_DEEP_RACE, j, c, res.delta)
        if res.q > 0.0 or res.delta > 0.0:
            load = BallLoad(load.fx + res.fx, load.fr + res.fr, load.ft + ft, load.mx + res.mx, load.mr + res.mr,
                            load.mt + res.mt)
            if c > 0:
                rl = inner_race_reaction(res, ft, ft_lean, b, ring, x0, rr0, rl)
    return BallRaceContacts(load, rl, ctl)


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
    # ball in inertial components
    bx = b.x
    byy = b.r * cs
    bzz = b.r * sn
    pk = _pocket_force(bx, byy, bzz, b.x_dot, b.r_dot * cs - b.v_t * sn, b.r_dot * sn + b.v_t * cs, b.w_x,
                       b.w_r * cs - b.w_t * sn, b.w_r * sn + b.w_t * cs,
                       ppx, ppy, ppz, ax, ay, az, vel[0], vel[1], vel[2], wn[0], wn[1], wn[2],
                       xc, yc, zc, p, flags, c_roll, c_slide, c_root)
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


@njit(cache=True, _nrt=False, inline="always")
def ball_churning_drag(j, b, rho_mix, eta_mix, dw, flags, work, load):
    """Churning drag on the orbiting ball j in the oil–air mixture at rest (flexbearing.multibody.drag):
    F_d = ½·rho_mix·C_d(Re)·(pi·Dw²/4)·v², v = r·psi', along −e_t; with the option ball_drag_moment the
    mixture's viscous moment on the spinning ball, M = −c·w, c = pi·eta_mix·Dw³ (Stokes–Lamb), and
    the power they dissipate, −F_d·v + c·|w|². Added to the ball load, recorded into work."""
    if not flags[F_DRAG]:
        work[j, W_DRAG] = 0.0
        work[j, W_P_CHURNING] = 0.0
        return load
    vbt = b.v_t
    fd = churning_drag(dw, vbt, rho_mix, eta_mix)
    work[j, W_DRAG] = -fd
    work[j, W_P_CHURNING] = -fd * vbt
    if not flags[F_BALL_DRAG_MOMENT]:
        return BallLoad(load.fx, load.fr, load.ft + fd, load.mx, load.mr, load.mt)
    c_spin = ball_drag_moment_coefficient(dw, eta_mix)
    work[j, W_P_CHURNING] += c_spin * (b.w_x * b.w_x + b.w_r * b.w_r + b.w_t * b.w_t)
    return BallLoad(load.fx, load.fr, load.ft + fd, load.mx - c_spin * b.w_x, load.mr - c_spin * b.w_r,
                    load.mt - c_spin * b.w_t)


@njit(cache=True, _nrt=False, inline="always")
def race_control_couple(b, load, ctl, omega_i, ring, p, flags, rl):
    """Which race controls ball b's attitude (`control_race`) and, with race control or no pivoting
    and the option attitude_ring_reaction, the inner ring's reaction to the gyroscopic couple
    M_c = I_b·psi'·w_r − M_t the races supply: forces +f·u_i at the inner contact point and −f·u_i
    at the outer one, f = M_c/((p_i − p_o) × u_i)_t, u_i = e_t × n_i (module docstring, "Ball
    attitude"); the ring receives −f·u_i at its contact point. Returns Attitude."""
    cs = b.cos_psi
    sn = b.sin_psi
    c = control_race(flags[F_ATTITUDE], ctl.q_outer, ctl.a_outer, ctl.nx_outer, ctl.nr_outer, ctl.q_inner,
                     ctl.a_inner, ctl.nx_inner, ctl.nr_inner)
    cnx = cnr = w_ring = ux = ur = 0.0
    if c == -1:
        return Attitude(c, cnx, cnr, w_ring, ux, ur, rl)
    if c == 0:
        cnx, cnr, w_ring = ctl.nx_outer, ctl.nr_outer, 0.0
    elif c == 1:
        cnx, cnr, w_ring = ctl.nx_inner, ctl.nr_inner, omega_i
    ux = -cnr
    ur = cnx
    if flags[F_ATT_RING] and ctl.q_outer > 0.0 and ctl.q_inner > 0.0:
        dpx = ctl.x_inner - ctl.x_outer
        dpr = ctl.r_inner - ctl.r_outer
        uix = -ctl.nr_inner
        uir = ctl.nx_inner
        arm = dpx * uir - dpr * uix
        if arm != 0.0:
            f_g = (p[P_IB] * b.psi_dot * b.w_r - load.mt) / arm
            gx = -f_g * uix
            gr = -f_g * uir
            gy = gr * cs
            gz = gr * sn
            m1, m2, m3 = cross(ctl.x_inner - ring.x, ctl.r_inner * cs - ring.y, ctl.r_inner * sn - ring.z, gx, gy, gz)
            rl = RingLoad(rl.fx + gx, rl.fy + gy, rl.fz + gz, rl.mx + m1, rl.my + m2, rl.mz + m3)
    return Attitude(c, cnx, cnr, w_ring, ux, ur, rl)


@njit(cache=True, _nrt=False, inline="always")
def ball_equations(j, b, load, att, p, dydt):
    """dy/dt of ball j (module docstring): Newton in the orbiting frame,
        m_b·x'' = F_x,  m_b·(r'' − r·psi'²) = F_r,  m_b·(r·psi'' + 2·r'·psi') = F_t,
    Euler of the free ball, I_b·w_x' = M_x, I_b·(w_r' − psi'·w_t) = M_r, I_b·(w_t' + psi'·w_r) = M_t,
    or with race control the one rotation about u = e_t × n driven by M·u, the no-spin and no-yaw
    constraints relaxed at the rate k = attitude_rate (no pivoting: only the yaw). Returns the
    inner ring's load att.ring with, under inner-race control, the reaction −M_n·n to the
    spin-locking couple M_n = I_b·(dw/dt − dw/dt_free)·n (that race's spin friction; without it 6 %
    of the loss at the paper case went unaccounted)."""
    o = ball_offset(j)
    mb = p[P_MB]
    ib = p[P_IB]
    kr = p[P_ATT_RATE]
    rb = b.r
    vbr = b.r_dot
    psid = b.psi_dot
    w_r = b.w_r
    w_t = b.w_t
    mx, mr, mt = load.mx, load.mr, load.mt
    rl = att.ring
    dydt[o + BALL_X] = b.x_dot
    dydt[o + BALL_R] = vbr
    dydt[o + BALL_PSI] = psid
    dydt[o + BALL_X_DOT] = load.fx / mb
    dydt[o + BALL_R_DOT] = load.fr / mb + rb * psid * psid
    dydt[o + BALL_PSI_DOT] = (load.ft / mb - 2.0 * vbr * psid) / rb
    ctl = att.control
    if ctl < 0:
        dydt[o + BALL_W_X] = mx / ib
        dydt[o + BALL_W_R] = mr / ib + psid * w_t
        if ctl == -2:
            # no gyroscopic pivoting: the yaw is held at 0, the pitch is free
            dydt[o + BALL_W_T] = -kr * w_t
        else:
            dydt[o + BALL_W_T] = mt / ib - psid * w_r
        return rl
    # race control: no spin on the controlling race, no yaw; the one free rotation is about u
    cnx = att.n_x
    cnr = att.n_r
    ux = att.u_x
    ur = att.u_r
    a_u = (mx * ux + mr * ur) / ib + psid * w_t * ur
    b_n = kr * (att.w_race * cnx - (b.w_x * cnx + w_r * cnr))
    dydt[o + BALL_W_X] = a_u * ux + b_n * cnx
    dydt[o + BALL_W_R] = a_u * ur + b_n * cnr
    dydt[o + BALL_W_T] = -kr * w_t
    if ctl == 1:
        m_n = ib * b_n - (mx * cnx + (mr + ib * psid * w_t) * cnr)
        cs = b.cos_psi
        sn = b.sin_psi
        rl = RingLoad(rl.fx, rl.fy, rl.fz, rl.mx - m_n * cnx, rl.my - m_n * cnr * cs, rl.mz - m_n * cnr * sn)
    return rl


@njit(cache=True, _nrt=False, inline="always")
def guidance_reaction_on_ring(g, xc, yc, zc, ring, flags, rl):
    """An inner-ring land (`_cage_guidance`) puts the opposite of its force and torque on the ring,
    the force applied at the cage centre (so the pair conserves angular momentum)."""
    if flags[F_GUIDANCE] != 1:
        return rl
    m1, m2, m3 = cross(xc - ring.x, yc - ring.y, zc - ring.z, 0.0, -g.fy, -g.fz)
    return RingLoad(rl.fx, rl.fy - g.fy, rl.fz - g.fz, rl.mx + (m1 - g.mx), rl.my + m2, rl.mz + m3)


@njit(cache=True, _nrt=False, inline="always")
def inner_ring_equations(y, dydt, r0, omega_i, rl, work, zb, p):
    """dy/dt of the inner ring (module docstring): m_i·(x'', y'', z'') = F_ext(t) + race reactions
    (− m_i·g along Z), I_d·theta_y'' = M_y − I_p·omega_i·theta_z', I_d·theta_z'' = M_z +
    I_p·omega_i·theta_y' (gyroscopic coupling of the spinning ring), phi_i' = omega_i; the drive
    torque about X into work."""
    mi = p[P_MI]
    idr = p[P_IID]
    ipr = p[P_IIP]
    for k in range(RING_POSITIONS):
        dydt[r0 + k] = y[r0 + RING_POSITIONS + k]
    dydt[r0 + RING_VX] = (work[zb, WR_FX] + rl.fx) / mi
    dydt[r0 + RING_VY] = (work[zb, WR_FX + 1] + rl.fy) / mi
    dydt[r0 + RING_VZ] = (work[zb, WR_FX + 2] + rl.fz) / mi - p[P_GRAV]
    dydt[r0 + RING_TILT_Y_DOT] = (rl.my - ipr * omega_i * y[r0 + RING_TILT_Z_DOT]) / idr
    dydt[r0 + RING_TILT_Z_DOT] = (rl.mz + ipr * omega_i * y[r0 + RING_TILT_Y_DOT]) / idr
    dydt[r0 + RING_PHI] = omega_i
    work[zb, WR_RING_TORQUE] = rl.mx


@njit(cache=True, _nrt=False, inline="always")
def land_and_structural_power(y, m0, g, yc, zc, vyc, vzc, ring, omega_i, A, w_b, cage, flags, work, zb):
    """Dissipated power of the guide land and of the cage's modal damping (flexbearing.multibody.power_loss):
    the land's force, torque and distributed modal loads on the cage, less the rim's normal force,
    which is conservative (potential k_rim·(e − Cg)²/2); an inner land works on the cage's motion
    relative to the ring. P_structural = sum_k d_k·q_k'²."""
    lfy, lfz, lmx, frim = g.fy, g.fz, g.mx, g.rim_force
    wx_inertial = A[0, 0] * w_b[0] + A[0, 1] * w_b[1] + A[0, 2] * w_b[2]
    if flags[F_GUIDANCE] == 1:
        ey_ = yc - ring.y
        ez_ = zc - ring.z
        p_land = lfy * (vyc - ring.vy) + lfz * (vzc - ring.vz) + lmx * (wx_inertial - omega_i)
        if frim > 0.0:
            p_land += frim * (ey_ * (vyc - ring.vy) + ez_ * (vzc - ring.vz)) / math.sqrt(ey_ * ey_ + ez_ * ez_)
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


@njit(cache=True, _nrt=False)
def rhs(t, y, dydt, p, flags, htab, ttab, speed_table, load_table, impacts, work, cage):
    """dy/dt of the bearing at time t (module docstring); fills `work` with the contact results.

    p, flags, htab, ttab, cage: Model.p, Model.flags, Model.hertz_table, Model.traction_table,
    Model.cage; speed_table, load_table, impacts: flexbearing.multibody.profiles arrays; work: float64
    (Z+1, N_WORK). Allocation-free. Per ball: race contacts, pocket, churning drag, race control,
    ball equations; then the cage guidance, the inner ring, the cage (floating frame), the powers.
    """
    z = int(p[P_Z])
    zb = z
    dw = p[P_DW]
    mb = p[P_MB]
    grav = p[P_GRAV]
    r0 = ring_offset(z)
    c0 = cage_offset(z)
    m0 = modal_offset(z)
    A = cage.A
    scr = cage.scratch
    Qext = cage.Qext
    for k in range(Qext.shape[0]):
        Qext[k] = 0.0
    cage_rotation(y[c0 + CAGE_PHI], y[c0 + CAGE_TILT_Y], y[c0 + CAGE_TILT_Z], A)
    cage_body_angular_velocity(A, y, c0, scr[1])
    omega_i = speed_at(t, speed_table)
    load_at(t, load_table, impacts, work[zb, WR_FX:WR_FX + 3])
    work[zb, WR_OMEGA_I] = omega_i
    ring = ring_state(y, r0)
    xc = y[c0 + CAGE_X]
    yc = y[c0 + CAGE_Y]
    zc = y[c0 + CAGE_Z]
    vyc = y[c0 + CAGE_VY]
    vzc = y[c0 + CAGE_VZ]
    wcx = y[c0 + CAGE_OMEGA]
    rl = RingLoad(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    rho_mix, eta_mix = oil_air_mixture(cavity_oil_fraction(p[P_OILFRAC], p[P_OIL_WREF], omega_i),
                                       p[P_RHO_OIL], p[P_ETA0])
    c_roll, c_slide, c_root = pocket_film_coefficients(p, flags)
    # the scratch rows, the modal coordinates and the node loads, taken once: every array view
    # costs an atomic reference-count increment and decrement (made per ball they were ~20 % of
    # a rigid cage's rhs)
    w_body = scr[1]
    pos = scr[3]
    vel = scr[4]
    axv = scr[5]
    wn = scr[6]
    Fc = scr[7]
    Tn = scr[2]
    q_modes = y[m0:m0 + cage.stiffness.shape[0]]
    nl = cage.node_load
    node_position = cage.node_position
    node_modes = cage.node_modes
    for j in range(z):
        b = ball_state(y, j)
        load = BallLoad(0.0, -mb * grav * b.sin_psi, -mb * grav * b.cos_psi, 0.0, 0.0, 0.0)
        contacts = ball_race_contacts(j, b, ring, omega_i, p, flags, htab, ttab, work, load, rl)
        load = ball_pocket(j, b, y, c0, m0, A, w_body, pos, vel, axv, wn, Fc, Tn, q_modes, nl, node_position,
                           node_modes, Qext, xc, yc, zc, p, flags, c_roll, c_slide, c_root, work, contacts.ball)
        load = ball_churning_drag(j, b, rho_mix, eta_mix, dw, flags, work, load)
        att = race_control_couple(b, load, contacts.control, omega_i, ring, p, flags, contacts.ring)
        rl = ball_equations(j, b, load, att, p, dydt)
    g = _cage_guidance(yc, zc, vyc, vzc, wcx, ring.y, ring.z, ring.vy, ring.vz, omega_i, p, flags)
    rl = guidance_reaction_on_ring(g, xc, yc, zc, ring, flags, rl)
    inner_ring_equations(y, dydt, r0, omega_i, rl, work, zb, p)
    # the cage: guide land + pockets (floating frame; the only place the resultants become accelerations)
    work[zb, WR_LAND_FY] = g.fy
    work[zb, WR_LAND_FZ] = g.fz
    work[zb, WR_LAND_M] = g.mx
    work[zb, WR_RIM_F] = g.rim_force
    work[zb, WR_EPS] = g.eps
    if g.eps > 2.0:
        _flag(work, zb, STATUS_RIM, -1, 4, g.eps)
    cage_equations(y, dydt, c0, m0, cage, g.fy, g.fz, g.mx, p[P_GRAV])
    land_and_structural_power(y, m0, g, yc, zc, vyc, vzc, ring, omega_i, A, scr[1], cage, flags, work, zb)


# ---------------------------------------------------------------- the work array of `rhs`
def new_work(model) -> np.ndarray:
    return np.zeros((model.n_balls + 1, M.N_WORK))
