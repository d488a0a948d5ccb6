"""The ball–race contacts of `rhs`: the Hertz contact with its EHL traction, rolling resistance and
damping (`_race`), a ball's three race contacts and the inner ring's share of them
(`ball_race_contacts`, `inner_race_reaction`), the controlling race (`control_race`) and the
race-control couple (`race_control_couple`). The equations and references are in each docstring
and in flexbearing.multibody.dynamics' module docstring.
"""
from __future__ import annotations

import math
from collections import namedtuple

from numba import njit

from flexbearing.multibody import numba_cache  # noqa: F401  (drops stale compiled kernels first)
from flexbearing.multibody.model import (
    F_INNER_HALVES, P_DW, P_Z, P_FE, P_FI, P_XO, P_RO, P_XIL, P_RIL, P_XIR, P_RIR, P_MB, P_IB, P_EBR,
    P_ETA0, P_T0K, P_K0, P_SLIN, P_UMIN, P_ZETA, P_ALPHA0, P_UREG, P_ETA_TRACTION, P_ALPHA_P, F_TRACTION,
    F_DRAG, F_DAMPING, F_TRANSVERSE, F_NSLICES, F_HERTZ_FIXED, F_ROLLRES, F_ATTITUDE, F_ATT_RING,
    F_TRACTION_LAW, P_SPIN_SCALE_INNER, ATTITUDE_INNER, ATTITUDE_JONES, ATTITUDE_NO_PIVOT, ATTITUDE_OUTER,
    CONTACT_INNER_LEFT, CONTACT_OUTER, RACE_INNER, RACE_OUTER, H_K, H_ELL, H_EK, H_R, H_RX, H_RY, N_HGRID, N_WC, WC_Q, WC_COS,
    WC_SIN, WC_P0, WC_UR, WC_RX, WC_RY, WC_A, WC_SLIP, WC_DELTA, WC_FT, WC_P_TRACTION, WC_P_ROLLING,
    WC_P_DAMPING, P_EHL_TAU0, P_EHL_GAMMA_L, P_EHL_SHEAR_MODULUS, P_EHL_K_SOLID, P_EHL_KAPPA_SOLID, P_EHL_BETA_T,
    P_EHL_ETA_INLET,
)
from flexbearing.multibody.geometry import (
    cross, race_contact, ring_point_in_plane, ring_velocity_at, ring_velocity_in_plane,
)
from flexbearing.multibody.drag import ehl_rolling_resistance, ehl_pressure_rolling_force
from flexbearing.multibody.traction import (
    TRACTION_LAWS, sliced_traction, sliced_traction_ehl, traction_coefficients_table,
)
from flexbearing.multibody.film import film_thickness as hamrock_dowson_film
from flexbearing.multibody.hertz import hertz_load
from flexbearing.multibody.contact_status import STATUS_DEEP_RACE, DELTA_MAX_FRAC, _flag
from flexbearing.multibody.kernel_state import BallLoad, RingLoad


TRACTION_EHL = TRACTION_LAWS.index("ehl")   # flags[F_TRACTION_LAW] of the EHL film-shear law
# which race controls a ball's attitude (`control_race`): a race code (model.RACE_OUTER, RACE_INNER)
# or one of these
CONTROL_NONE = -1          # free ball, or its controlling race unloaded
CONTROL_NO_PIVOT = -2      # no pivoting: no race controls, only the yaw is held
RaceContact = namedtuple("RaceContact", "q cos_a sin_a p0 ur rx ry a slip delta fx fr ft mx mr mt x_p r_p "
                                        "cx cr p_traction p_rolling p_damping f_h")
RaceContact.__doc__ = "One ball–race contact (`_race` docstring: fields, units SI)."


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
    if attitude == ATTITUDE_NO_PIVOT:
        return CONTROL_NO_PIVOT
    if attitude == ATTITUDE_OUTER:
        return RACE_OUTER if q_o > 0.0 else CONTROL_NONE
    if attitude == ATTITUDE_INNER:
        return RACE_INNER if q_i > 0.0 else CONTROL_NONE
    if attitude == ATTITUDE_JONES:
        if q_o > 0.0 and q_i > 0.0:
            cos_oi = -(nxo * nxi + nro * nri)
            return RACE_OUTER if q_o * a_o * cos_oi >= q_i * a_i else RACE_INNER
        if q_o > 0.0:
            return RACE_OUTER
        if q_i > 0.0:
            return RACE_INNER
    return CONTROL_NONE


@njit(cache=True, inline="always")
def _race_traction(kind, Q, q_el, nx, nr, rho, a_ax, b_ax, p0, ur, du0, vb_x, vb_r, w_x, w_r, w_t, vrace_x, vrace_r,
                   ring_speed, g2, rx, ry, Fx, Fr, Mx, Mr, p, flags, ttab):
    """The traction of one loaded ball–race contact (`_race`) added to the normal force (Fx, Fr)
    and the moment (Mx, Mr) about the ball centre on the ball: returns (Fx, Fr, Ft, Mx, Mr, Mt,
    cx, cr, P_traction), (cx, cr) the spin moment's couple. (Fewer than 31 arguments: CPython
    passes more as *args, which numba does not inline.)

    The sliced traction (flexbearing.multibody.traction: `sliced_traction_ehl` of the EHL film-shear
    law at the Hamrock–Dowson central film of the inlet viscosity, or `sliced_traction` of the
    fitted curve at UR_eff = max(|UR|, u_reg)) of the sliding du(y) = du0 + du1·y along the
    rolling direction e_t and dv across it (tau, in the contact plane): T_t along e_t, T_tau along
    tau at the contact point rho·n, and the spin moment M_n about the normal (scaled on the inner
    race by the model option spin_moment_scale_inner). P_traction = T_t·du0 − M_n·du1 + T_tau·dv.
    """
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
        # and the law's parameters, all taken once per model (slots P_EHL_*, traction.fill_ehl_parameters)
        h_c = hamrock_dowson_film(rx, ry, p[P_EBR], q_el, urr, p[P_EHL_ETA_INLET], p[P_ALPHA_P])[1]
        Tt, Ttau, Mn = sliced_traction_ehl(Q, a_ax, b_ax, p0, h_c, urr, du0, du1, 0.0, dv,
                                           flags[F_NSLICES], bool(flags[F_TRANSVERSE]), p[P_SLIN],
                                           p[P_EHL_ETA_INLET], p[P_ALPHA_P], p[P_K0], p[P_EHL_TAU0],
                                           p[P_EHL_GAMMA_L], p[P_EHL_SHEAR_MODULUS], p[P_EHL_K_SOLID],
                                           p[P_EHL_KAPPA_SOLID], p[P_EHL_BETA_T])
    else:
        # the fit at UR_eff = max(|UR|, u_reg): coefficients and slide-to-roll ratio
        # (flexbearing.multibody.traction, "Low rolling speed")
        u_s = urr if urr > p[P_UREG] else p[P_UREG]
        A, B, C, D = traction_coefficients_table(Q, u_s, rx, p[P_EBR], p[P_ETA_TRACTION], p[P_T0K], p[P_K0], ttab)
        Tt, Ttau, Mn = sliced_traction(Q, a_ax, u_s, du0, du1, 0.0, dv, A, B, C, D,
                                       flags[F_NSLICES], bool(flags[F_TRANSVERSE]), p[P_SLIN])
    if kind == RACE_INNER:
        # diagnostic of the race-control screening (model option spin_moment_scale_inner, 1 = the law)
        Mn *= p[P_SPIN_SCALE_INNER]
    # force on the ball at p: Tt·e_t + Ttau·tau (Ft, Mt: none before the traction)
    Ft = 0.0
    Mt = 0.0
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
    return Fx, Fr, Ft, Mx, Mr, Mt, cx, cr, p_trac


@njit(cache=True, inline="always")
def _race_rolling_resistance(q_el, ur, rx, ell, rho, nx, nr, du0, xb, rb, vb_t, rv_x, rv_r, rv_t0, g1, g2, ring_rc,
                             ring_speed, Ft, Mx, Mr, p):
    """The EHL rolling resistance of one loaded ball–race contact (`_race`; flexbearing.multibody.drag)
    added to the force Ft and moment (Mx, Mr) on the ball: returns (Ft, Mx, Mr, P_rolling, F_H).
    F_R at the contact, opposite to the entrainment speed, and the pressure rolling force
    F_H = −2(Rx/r_b)·F_R through the ball centre; P_rolling = F_R·du0 − F_H·(v_b,t − v_ring,t(b)).
    """
    # EHL rolling resistance (flexbearing.multibody.drag): F_R at the contact, opposite to the entrainment
    # speed, and the pressure rolling force F_H = −2(Rx/r_b)·F_R through the ball centre
    f_r = ehl_rolling_resistance(q_el, ur, rx, ell, p[P_EBR], p[P_ETA0], p[P_ALPHA_P])
    f_h = ehl_pressure_rolling_force(f_r, rx, 0.5 * p[P_DW])
    Ft += f_r + f_h
    Mx += rho * nr * f_r
    Mr += -rho * nx * f_r
    # the race takes −F_H on the same line, through the ball centre (a balanced pair): its
    # velocity there is the ring's rigid-body velocity at (xb, rb)
    vring_bt = ring_velocity_at(rv_x, rv_r, rv_t0, g1, g2, ring_rc, ring_speed, xb, rb)[2]
    p_roll = f_r * du0 - f_h * (vb_t - vring_bt)
    return Ft, Mx, Mr, p_roll, f_h


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
    q_el = hertz_load(K, delta)
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
        Fx, Fr, Ft, Mx, Mr, Mt, cx, cr, p_trac = _race_traction(
            kind, Q, q_el, nx, nr, rho, a_ax, b_ax, p0, ur, du0, vb_x, vb_r, w_x, w_r, w_t, vrace_x, vrace_r,
            ring_speed, g2, rx, ry, Fx, Fr, Mx, Mr, p, flags, ttab)
    f_h = 0.0
    if flags[F_ROLLRES] and flags[F_DRAG]:
        Ft, Mx, Mr, p_roll, f_h = _race_rolling_resistance(
            q_el, ur, rx, ell, rho, nx, nr, du0, xb, rb, vb_t, rv_x, rv_r, rv_t0, g1, g2, ring_rc, ring_speed,
            Ft, Mx, Mr, p)
    return RaceContact(Q, ca, sa, p0, ur, rx, ry, a_ax, slip, delta, Fx, Fr, Ft, Mx, Mr, Mt, x_p, r_p,
                       cx, cr, p_trac, p_roll, p_damp, f_h)


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


@njit(cache=True, _nrt=False)
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


@njit(cache=True, _nrt=False)
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
        if c == CONTACT_OUTER:
            res = _race(RACE_OUTER, b.x, b.r, p[P_XO], p[P_RO], p[P_FE], b.x_dot, b.r_dot, b.v_t, b.w_x, b.w_r, b.w_t, psid,
                        0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, p, flags, htab, ttab)
            ft = res.ft
        else:
            if c == CONTACT_INNER_LEFT:
                x0 = p[P_XIL]
                rr0 = p[P_RIL]
            else:
                x0 = p[P_XIR]
                rr0 = p[P_RIR]
            xc_g, rc_g = ring_point_in_plane(b.psi, x0, rr0, ring.x, ring.y, ring.z, ring.tilt_y, ring.tilt_z)
            th_rate = (ring.tilt_y_dot * sn - ring.tilt_z_dot * cs) + (ring.tilt_y * cs + ring.tilt_z * sn) * psid
            cd_x = ring.vx + rr0 * th_rate
            cd_r = rv_r_trans + (-ring.y * sn + ring.z * cs) * psid - x0 * th_rate
            res = _race(RACE_INNER, b.x, b.r, xc_g, rc_g, p[P_FI], b.x_dot, b.r_dot, b.v_t, b.w_x, b.w_r, b.w_t, psid,
                        rv_x, rv_r, rv_t, omega_i, ring_rc, g1, g2, cd_x, cd_r, p, flags, htab, ttab)
            ft = res.ft
            if res.q > 0.0:
                thp = ring.tilt_y * cs + ring.tilt_z * sn
                dxc = rr0 * thp
                drc = (-ring.y * sn + ring.z * cs) - x0 * thp
                ft_lean = res.q * (-res.sin_a * dxc - res.cos_a * drc) / b.r
                ft = res.ft + ft_lean
        if c == CONTACT_OUTER:      # outer: n = (sin a, cos a)
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
            if c != CONTACT_OUTER:
                rl = inner_race_reaction(res, ft, ft_lean, b, ring, x0, rr0, rl)
    return BallRaceContacts(load, rl, ctl)


@njit(cache=True, _nrt=False)
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
    if c == CONTROL_NONE:
        return Attitude(c, cnx, cnr, w_ring, ux, ur, rl)
    if c == RACE_OUTER:
        cnx, cnr, w_ring = ctl.nx_outer, ctl.nr_outer, 0.0
    elif c == RACE_INNER:
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
