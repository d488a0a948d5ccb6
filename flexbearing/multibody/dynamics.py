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
(flexbearing.studies.validation.slip_rate docstring): the two hypotheses bracket what the EHL traction can hold.

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

import numpy as np
from numba import njit

from flexbearing.multibody import model as M
from flexbearing.multibody.model import (
    P_OIL_WREF, P_DW, P_Z, P_MB, P_IB, P_MI, P_IID, P_IIP, P_ETA0, P_RHO_OIL, P_OILFRAC, P_GRAV, P_ATT_RATE,
    WR_FX, WR_LAND_FY, WR_LAND_FZ, WR_LAND_M,
    WR_RIM_F, WR_RING_TORQUE, WR_EPS, WR_OMEGA_I, RACE_INNER,
)
from flexbearing.multibody.profiles import load_at, speed_at
from flexbearing.multibody.oil_supply import cavity_oil_fraction
from flexbearing.multibody.drag import ball_churning_drag, oil_air_mixture
from flexbearing.multibody.cage_body import cage_body_angular_velocity, cage_equations, cage_rotation
from flexbearing.multibody.state_layout import (
    BALL_PSI, BALL_PSI_DOT, BALL_R, BALL_R_DOT, BALL_W_R, BALL_W_T, BALL_W_X, BALL_X, BALL_X_DOT,
    CAGE_OMEGA, CAGE_PHI, CAGE_TILT_Y, CAGE_TILT_Z, CAGE_VX, CAGE_VY, CAGE_VZ, CAGE_X, CAGE_Y, CAGE_Z, RING_PHI,
    RING_POSITIONS, RING_TILT_Y_DOT, RING_TILT_Z_DOT, RING_VX, RING_VY, RING_VZ, ball_offset, cage_offset,
    modal_offset, ring_offset,
)
from flexbearing.multibody import numba_cache  # noqa: F401  (drops stale compiled kernels first)
# the kernels of `rhs`, each in its module (one idea each); their names stay reachable here
from flexbearing.multibody.contact_status import (  # noqa: F401
    STATUS_OK, STATUS_DEEP_RACE, STATUS_DEEP_POCKET, STATUS_RIM, STATUS_NONFINITE, DELTA_MAX_FRAC, CONTACT_NAMES,
    _flag,
)
from flexbearing.multibody.kernel_state import (  # noqa: F401
    BallState, RingState, BallLoad, RingLoad, ball_state, ring_state,
)
from flexbearing.multibody.race_kernels import (  # noqa: F401
    CONTROL_NONE, CONTROL_NO_PIVOT, TRACTION_EHL, RaceContact, _hertz_lookup, control_race, _race, RaceControl, BallRaceContacts, Attitude,
    _record_race_contact, inner_race_reaction, ball_race_contacts, race_control_couple,
)
from flexbearing.multibody.pocket_kernels import (  # noqa: F401
    POCKET_H_MIN, PocketContact, pocket_film_coefficients, _pocket_interface, _pocket_force, ball_pocket,
)
from flexbearing.multibody.guidance_kernels import (  # noqa: F401
    GuidanceLoad, _guide_land, _cage_guidance, guidance_reaction_on_ring, land_and_structural_power,
)


# ---------------------------------------------------------------- the kernels of `rhs`


@njit(cache=True, _nrt=False)
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
    if ctl == CONTROL_NONE or ctl == CONTROL_NO_PIVOT:
        dydt[o + BALL_W_X] = mx / ib
        dydt[o + BALL_W_R] = mr / ib + psid * w_t
        if ctl == CONTROL_NO_PIVOT:
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
    if ctl == RACE_INNER:
        m_n = ib * b_n - (mx * cnx + (mr + ib * psid * w_t) * cnr)
        cs = b.cos_psi
        sn = b.sin_psi
        rl = RingLoad(rl.fx, rl.fy, rl.fz, rl.mx - m_n * cnx, rl.my - m_n * cnr * cs, rl.mz - m_n * cnr * sn)
    return rl


@njit(cache=True, _nrt=False)
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
    vxc = y[c0 + CAGE_VX]
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
    g = _cage_guidance(xc, yc, zc, vxc, vyc, vzc, wcx, ring, omega_i, p, flags)
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
    Qext[0] += g.fx              # an inner land tilted with its ring: the force's axial part
    cage_equations(y, dydt, c0, m0, cage, g.fy, g.fz, g.mx, p[P_GRAV])
    land_and_structural_power(y, m0, g, xc, yc, zc, vxc, vyc, vzc, ring, omega_i, A, scr[1], cage, flags, work, zb)


# ---------------------------------------------------------------- the work array of `rhs`
def new_work(model) -> np.ndarray:
    return np.zeros((model.n_balls + 1, M.N_WORK))
