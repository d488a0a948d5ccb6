"""One ball's quasi-static equilibrium in its azimuthal plane, compiled: the per-ball kernels of the
Jones–Harris solver (flexbearing.multibody.quasi_static, whose docstring states the model).

For a ring displacement u each ball j is solved for its centre (x_j, r_j) by a damped 2×2 Newton
iteration on

    sum_k (−Q_k·n_k + f_k·tau_k) + (0, F_c) = 0,   Q_k = K_k·max(delta_k, 0)^1.5,
    delta_k = |b − c_k| − (f_k − 0.5)·Dw,

(Hertz contact stiffness K_k at the current contact angle, flexbearing.multibody.hertz; friction
forces f_k carrying the gyroscopic moment held during the iteration), and the balls' forces and
moments on the inner ring are summed (`solve_all_balls`). References: A. B. Jones, J. Basic Eng.
82 (1960) 309; T. A. Harris & M. N. Kotzalas, Rolling Bearing Analysis, 5th ed., Vol. 2 (2007), ch. 3.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from flexbearing.multibody import geometry as geo
from flexbearing.multibody.hertz import _elliptic_kde, ellipticity, hertz_stiffness, race_curvature_radii
from flexbearing.multibody.model_layout import CONTACT_OUTER

EPS = float(np.finfo(np.float64).eps)
# a residual that sums n forces of size F carries round-off of about sqrt(n)..n·eps·F; 32·eps of the
# sum of the magnitudes bounds it for the handful of terms of one ball (and of one ring) with margin
ROUNDOFF_FACTOR = 32.0


@njit(cache=True)
def _contact(xb, rb, xc, rc, f, dw, dm, e_eff, inner):
    """One contact: (delta, Q, dQ/ddelta, nx, nr, d, cos a, sin a, K)."""
    dx = xb - xc
    dr = rb - rc
    d = math.sqrt(dx * dx + dr * dr)
    nx = dx / d
    nr = dr / d
    delta = d - (f - 0.5) * dw
    ca = abs(nr)
    sa = nx if nr >= 0.0 else -nx
    rx, ry = race_curvature_radii(dw, dm, f, math.acos(min(1.0, ca)), inner)
    k = hertz_stiffness(rx, ry, e_eff)
    if delta > 0.0:
        sq = math.sqrt(delta)
        q = k * delta * sq
        dq = 1.5 * k * sq
    else:
        q = 0.0
        dq = 0.0
    return delta, q, dq, nx, nr, d, ca, sa, k


@njit(cache=True)
def _ball_residual(xb, rb, cx, cr, cf, active, dw, dm, e_eff, m_w2, mg, lam_o, lam_i, out_q, out_n):
    """Residual (Rx, Rr) of the ball's equilibrium and its Jacobian (4 entries, friction frozen).

    out_q[k] = Q_k; out_n[k, :] = (nx, nr, cos a, sin a, delta).
    """
    rx = 0.0
    rr = m_w2 * rb
    jxx = 0.0
    jxr = 0.0
    jrx = 0.0
    jrr = m_w2
    qin = 0.0
    for k in range(3):
        out_q[k] = 0.0
        if not active[k]:
            continue
        delta, q, dq, nx, nr, d, ca, sa, kk = _contact(xb, rb, cx[k], cr[k], cf[k], dw, dm, e_eff, k != CONTACT_OUTER)
        out_q[k] = q
        out_n[k, 0] = nx
        out_n[k, 1] = nr
        out_n[k, 2] = ca
        out_n[k, 3] = sa
        out_n[k, 4] = delta
        if k != CONTACT_OUTER:
            qin += q
        rx -= q * nx
        rr -= q * nr
        t = q / d
        jxx -= dq * nx * nx + t * (1.0 - nx * nx)
        jxr -= dq * nx * nr - t * nx * nr
        jrx -= dq * nr * nx - t * nr * nx
        jrr -= dq * nr * nr + t * (1.0 - nr * nr)
    # gyroscopic friction along tau = (cos a, -sin a)
    if mg != 0.0:
        fo = -lam_o * mg / dw
        if out_q[0] > 0.0:
            rx += fo * out_n[0, 2]
            rr -= fo * out_n[0, 3]
        if qin > 0.0:
            for k in range(1, 3):
                if out_q[k] > 0.0:
                    fk = lam_i * mg / dw * out_q[k] / qin
                    rx += fk * out_n[k, 2]
                    rr -= fk * out_n[k, 3]
    return rx, rr, jxx, jxr, jrx, jrr


@njit(cache=True)
def _solve_ball(xb, rb, cx, cr, cf, active, dw, dm, e_eff, m_w2, mg, lam_o, lam_i, ball_tol, out_q, out_n):
    """Damped Newton for one ball's centre (x, r). Returns (x, r, |R|, iterations).

    Stops at |R| <= max(ball_tol, ROUNDOFF_FACTOR·eps·(sum of the force magnitudes on the ball)): the
    second term is the round-off floor of the residual (a sum of forces of that size cannot cancel to
    better than a few eps of them), so a tolerance below it ends at the floor on every processor
    instead of after a processor-dependent number of steps that do not change the state."""
    smax = 0.02 * dw
    rx, rr, jxx, jxr, jrx, jrr = _ball_residual(xb, rb, cx, cr, cf, active, dw, dm, e_eff, m_w2,
                                                 mg, lam_o, lam_i, out_q, out_n)
    res = math.sqrt(rx * rx + rr * rr)
    it = 0
    for it in range(200):
        tol = max(ball_tol, ROUNDOFF_FACTOR * EPS * (out_q[0] + out_q[1] + out_q[2] + abs(m_w2 * rb)
                                                    + 2.0 * abs(mg) / dw))
        if res <= tol:
            break
        if out_q[0] == 0.0 and out_q[1] == 0.0 and out_q[2] == 0.0:
            if m_w2 == 0.0:
                break                   # no load, no contact: a free ball is in equilibrium
            # only the centrifugal force: move outward onto the outer race (delta ~ 1 nm)
            dx = xb - cx[0]
            drr = rb - cr[0]
            d = math.sqrt(dx * dx + drr * drr)
            need = (cf[0] - 0.5) * dw + 1e-9 - d
            rb += need * 1.0001 if need > 0.0 else 0.0
            if need <= 0.0:
                rb += 1e-9
            rx, rr, jxx, jxr, jrx, jrr = _ball_residual(xb, rb, cx, cr, cf, active, dw, dm, e_eff,
                                                         m_w2, mg, lam_o, lam_i, out_q, out_n)
            res = math.sqrt(rx * rx + rr * rr)
            continue
        det = jxx * jrr - jxr * jrx
        if det == 0.0 or not math.isfinite(det):
            break
        sx = -(jrr * rx - jxr * rr) / det
        sr = -(-jrx * rx + jxx * rr) / det
        sn = math.sqrt(sx * sx + sr * sr)
        if sn > smax:
            sx *= smax / sn
            sr *= smax / sn
        lam = 1.0
        accepted = False
        for _ in range(30):
            xn = xb + lam * sx
            rn = rb + lam * sr
            rx2, rr2, a1, a2, a3, a4 = _ball_residual(xn, rn, cx, cr, cf, active, dw, dm, e_eff,
                                                       m_w2, mg, lam_o, lam_i, out_q, out_n)
            res2 = math.sqrt(rx2 * rx2 + rr2 * rr2)
            if res2 < res or res2 <= tol:
                accepted = True
                break
            lam *= 0.5
        if not accepted:
            # no step along the Newton direction lowers |R| (2^-30 of it included): the ball has no
            # equilibrium nearby (e.g. friction asked of an unloaded contact) or sits at the residual's
            # round-off floor; further iterations would repeat this search
            break
        xb = xn
        rb = rn
        rx, rr, jxx, jxr, jrx, jrr = rx2, rr2, a1, a2, a3, a4
        res = res2
    _ball_residual(xb, rb, cx, cr, cf, active, dw, dm, e_eff, m_w2, mg, lam_o, lam_i, out_q, out_n)
    return xb, rb, res, it


@njit(cache=True)
def solve_all_balls(u, psi, gx, gr, cf, active, dw, dm, e_eff, m_w2, mg, lam_o, lam_i, ball_tol,
                     xb, rb, q, nrm, ring_force, ball_res):
    """Solve every ball for ring displacement u (5) and accumulate the balls' force on the ring.

    ball_tol: each ball's residual tolerance, N (`_solve_ball`: never below its round-off floor).
    ring_force = (Fx, Fy, Fz, My, Mz) exerted by the balls on the inner ring (moments about the
    displaced ring centre, from the forces at the contact points).
    """
    cx = np.empty(3)
    cr = np.empty(3)
    qq = np.empty(3)
    nn = np.zeros((3, 5))
    for i in range(5):
        ring_force[i] = 0.0
    for j in range(psi.shape[0]):
        cx[0] = gx[0]
        cr[0] = gr[0]
        for k in range(1, 3):
            cx[k], cr[k] = geo.ring_point_in_plane(psi[j], gx[k], gr[k], u[0], u[1], u[2], u[3], u[4])
        x1, r1, res, it = _solve_ball(xb[j], rb[j], cx, cr, cf, active, dw, dm, e_eff, m_w2[j],
                                      mg[j], lam_o[j], lam_i[j], ball_tol, qq, nn)
        xb[j] = x1
        rb[j] = r1
        ball_res[j] = res
        c = math.cos(psi[j])
        s = math.sin(psi[j])
        qin = qq[1] + qq[2]
        for k in range(3):
            q[j, k] = qq[k]
            for i in range(5):
                nrm[j, k, i] = nn[k, i]
        for k in range(1, 3):
            if qq[k] <= 0.0:
                continue
            nx, nr, ca, sa, delta = nn[k, 0], nn[k, 1], nn[k, 2], nn[k, 3], nn[k, 4]
            fk = lam_i[j] * mg[j] / dw * qq[k] / qin if qin > 0.0 else 0.0
            fx = qq[k] * nx - fk * ca          # force on the ring, in-plane
            fr = qq[k] * nr + fk * sa
            fy = fr * c
            fz = fr * s
            rho = 0.5 * dw - 0.5 * delta
            px = x1 + rho * nx - u[0]
            pr = r1 + rho * nr
            py = pr * c - u[1]
            pz = pr * s - u[2]
            ring_force[0] += fx
            ring_force[1] += fy
            ring_force[2] += fz
            ring_force[3] += pz * fx - px * fz     # M_y = z·Fx − x·Fz
            ring_force[4] += px * fy - py * fx     # M_z = x·Fy − y·Fx


# ---------------------------------------------------------------- the ring Jacobian
@njit(cache=True)
def hertz_stiffness_slope(rx, ry, e_eff):
    """Hertz constant K_H(Rx, Ry) of Q = K_H·delta^1.5 (flexbearing.multibody.hertz.hertz_stiffness)
    and its derivative dK_H/dRx, N/m^1.5 and N/m^2.5.

    K_H = pi·k·E'·sqrt(2·E(m)·R/(9·K(m)³)), k = (1 − m)^(−1/2), R = Rx·Ry/(Rx + Ry), with m the root
    of rho = (m·K − (K − E))/((1 − m)(K − E)) for the radius ratio rho (hertz.ellipticity). Hence

        d ln K_H/dRx = [1/(2(1 − m)) + E'(m)/(2E) − 3K'(m)/(2K)]·(dm/drho)·(drho/dRx) + Ry/(Rx(Rx + Ry)),

    K'(m) = (E − (1 − m)K)/(2m(1 − m)), E'(m) = −(K − E)/(2m) (Abramowitz & Stegun 17.3.37/17.3.38;
    Byrd & Friedman 710.00), dm/drho = 1/(drho/dm) by the implicit-function theorem, drho/dm from
    the same expressions. K and E are the module's A&S values (absolute error 2e-8 for m >= 0.1),
    so the slope is that of the exact-integral K_H to about that relative accuracy; the contact's
    curvature term it enters is a few per cent of the contact stiffness.
    """
    k = hertz_stiffness(rx, ry, e_eff)
    if ry >= rx:
        ratio = ry / rx
        dratio = -ry / (rx * rx)
    else:
        ratio = rx / ry
        dratio = 1.0 / ry
    dlog = ry / (rx * (rx + ry))          # 0.5·d ln R/dRx is half of this; added below
    if ratio <= 1.0 + 1e-12:
        return k, k * 0.5 * dlog          # circular contact: k = 1 to first order
    kk_, ek_, kk = ellipticity(ratio)
    m = 1.0 - 1.0 / (kk_ * kk_)
    kk, ek, d = _elliptic_kde(m)
    m1 = 1.0 - m
    num = m * kk - d                      # E − (1 − m)K
    den = m1 * d
    dk_dm = num / (2.0 * m * m1)
    de_dm = -d / (2.0 * m)
    dd_dm = dk_dm - de_dm
    dnum = kk + m * dk_dm - dd_dm
    dden = -d + m1 * dd_dm
    drho_dm = (dnum * den - num * dden) / (den * den)
    dlnk_dm = 0.5 / m1 + 0.5 * de_dm / ek - 1.5 * dk_dm / kk
    return k, k * (dlnk_dm / drho_dm * dratio + 0.5 * dlog)


@njit(cache=True)
def _contact_slopes(k, xb, rb, xc, rc, f, dw, dm, e_eff, q, gq, nv, dn, tau, dtau, delta):
    """Contact k's load Q_k, normal n_k, friction direction tau_k and approach delta_k at the ball
    centre b, with their derivatives with respect to d_k = b − c_k (`ring_jacobian`), into the
    scratch arrays at slot k."""
    dx = xb - xc
    dr = rb - rc
    dd = math.sqrt(dx * dx + dr * dr)
    nx = dx / dd
    nr = dr / dd
    dl = dd - (f - 0.5) * dw
    delta[k] = dl
    sr = 1.0 if nr >= 0.0 else -1.0
    ca = abs(nr)
    nv[2 * k] = nx
    nv[2 * k + 1] = nr
    dn[4 * k + 0] = (1.0 - nx * nx) / dd
    dn[4 * k + 1] = -nx * nr / dd
    dn[4 * k + 2] = -nr * nx / dd
    dn[4 * k + 3] = (1.0 - nr * nr) / dd
    # tau = (cos a, −sin a) = sr·(n_r, −n_x)
    tau[2 * k] = ca
    tau[2 * k + 1] = -sr * nx
    dtau[4 * k + 0] = sr * dn[4 * k + 2]
    dtau[4 * k + 1] = sr * dn[4 * k + 3]
    dtau[4 * k + 2] = -sr * dn[4 * k + 0]
    dtau[4 * k + 3] = -sr * dn[4 * k + 1]
    q[k] = 0.0
    gq[2 * k] = 0.0
    gq[2 * k + 1] = 0.0
    if dl > 0.0:
        rxx, ryy = race_curvature_radii(dw, dm, f, math.acos(min(1.0, ca)), k != CONTACT_OUTER)
        kh, dkh = hertz_stiffness_slope(rxx, ryy, e_eff)
        sq = math.sqrt(dl)
        q[k] = kh * dl * sq
        # Rx = Dw·(1 ∓ Dw·cos a/dm)/2 (inner −, outer +); d(cos a)/dd = sr·dn_r/dd
        dk_dca = dkh * dw * dw / (2.0 * dm) * (-1.0 if k != CONTACT_OUTER else 1.0)
        for a in range(2):
            gq[2 * k + a] = 1.5 * kh * sq * nv[2 * k + a] + dl * sq * dk_dca * sr * dn[4 * k + 2 + a]


@njit(cache=True)
def _ball_force_slopes(q, gq, nv, dn, tau, dtau, fr, big, gd):
    """gd[(k·3 + m)·4 + 2a + b] = dP_k/dd_m (2×2 blocks), P_k = −Q_k·n_k + f_k·tau_k the force of
    contact k on the ball; the inner frictions f_k = big·Q_k/(Q_1 + Q_2) couple the inner contacts."""
    qin = q[1] + q[2]
    for m in range(36):
        gd[m] = 0.0
    for k in range(3):
        if q[k] <= 0.0:
            continue
        b0 = (k * 3 + k) * 4
        for a in range(2):
            for bb in range(2):
                gd[b0 + 2 * a + bb] = (-nv[2 * k + a] * gq[2 * k + bb] - q[k] * dn[4 * k + 2 * a + bb]
                                       + fr[k] * dtau[4 * k + 2 * a + bb])
        if k != CONTACT_OUTER:
            for m in range(1, 3):
                if q[m] <= 0.0:
                    continue
                dfdq = big * ((qin if m == k else 0.0) - q[k]) / (qin * qin)
                b1 = (k * 3 + m) * 4
                for a in range(2):
                    for bb in range(2):
                        gd[b1 + 2 * a + bb] += tau[2 * k + a] * dfdq * gq[2 * m + bb]


@njit(cache=True)
def _ring_force_slopes(xb, rb, u, c, s, dw, q, nv, dn, tau, fr, delta, gd, fd, db, jac):
    """Derivatives of ball j's force on the ring F_j (5) (`solve_all_balls`): fd[m·10 + 2i + b] =
    dF_i/dd_m, db[2i + b] = dF_i/db through the contact points, and the explicit u terms (the moment
    arms p − u) added to jac. The ring force of inner contact k is −P_k in the plane, at the contact
    point p_k = b + (Dw − delta_k)/2·n_k: F = (Fx, Fr·c, Fr·s, (p_r·s − u_z)·Fx − (p_x − u_x)·Fr·s,
    (p_x − u_x)·Fr·c − (p_r·c − u_y)·Fx)."""
    for m in range(30):
        fd[m] = 0.0
    for m in range(10):
        db[m] = 0.0
    for k in range(1, 3):
        if q[k] <= 0.0:
            continue
        fxp = q[k] * nv[2 * k] - fr[k] * tau[2 * k]
        frp = q[k] * nv[2 * k + 1] - fr[k] * tau[2 * k + 1]
        rho = 0.5 * dw - 0.5 * delta[k]
        px = xb + rho * nv[2 * k] - u[0]
        pr = rb + rho * nv[2 * k + 1]
        py = pr * c - u[1]
        pz = pr * s - u[2]
        # dF/dFpl (rows a_i0, a_i1) and dF/dp (rows 3, 4)
        a30, a31 = pz, -px * s
        a40, a41 = -py, px * c
        p30, p31 = -frp * s, fxp * s
        p40, p41 = frp * c, -fxp * c
        jac[3, 0] += frp * s
        jac[3, 2] += -fxp
        jac[4, 0] += -frp * c
        jac[4, 1] += fxp
        db[6] += p30
        db[7] += p31
        db[8] += p40
        db[9] += p41
        # dp/dd_k = −0.5·n·nᵀ + rho·dn/dd
        dp00 = -0.5 * nv[2 * k] * nv[2 * k] + rho * dn[4 * k + 0]
        dp01 = -0.5 * nv[2 * k] * nv[2 * k + 1] + rho * dn[4 * k + 1]
        dp10 = -0.5 * nv[2 * k + 1] * nv[2 * k] + rho * dn[4 * k + 2]
        dp11 = -0.5 * nv[2 * k + 1] * nv[2 * k + 1] + rho * dn[4 * k + 3]
        fd[k * 10 + 6] += p30 * dp00 + p31 * dp10
        fd[k * 10 + 7] += p30 * dp01 + p31 * dp11
        fd[k * 10 + 8] += p40 * dp00 + p41 * dp10
        fd[k * 10 + 9] += p40 * dp01 + p41 * dp11
        # through the force: dFpl_k/dd_m = −dP_k/dd_m
        for m in range(3):
            b1 = (k * 3 + m) * 4
            g00 = -gd[b1 + 0]
            g01 = -gd[b1 + 1]
            g10 = -gd[b1 + 2]
            g11 = -gd[b1 + 3]
            fd[m * 10 + 0] += g00
            fd[m * 10 + 1] += g01
            fd[m * 10 + 2] += c * g10
            fd[m * 10 + 3] += c * g11
            fd[m * 10 + 4] += s * g10
            fd[m * 10 + 5] += s * g11
            fd[m * 10 + 6] += a30 * g00 + a31 * g10
            fd[m * 10 + 7] += a30 * g01 + a31 * g11
            fd[m * 10 + 8] += a40 * g00 + a41 * g10
            fd[m * 10 + 9] += a40 * g01 + a41 * g11


@njit(cache=True)
def ring_jacobian(u, psi, gx, gr, cf, active, dw, dm, e_eff, m_w2, mg, lam_o, lam_i, xb, rb, jac, work):
    """Exact Jacobian dF/du (5×5) of the balls' force on the inner ring F = (Fx, Fy, Fz, My, Mz)
    (`solve_all_balls`) with every ball kept in its own equilibrium, the kinematics (m·omega_m², M_g,
    friction shares) held, at the ball seats xb, rb (solved for this u).

    Implicit-function theorem, ball by ball: ball j's seat x_j = (x_j, r_j) solves G_j(x_j; u) = 0
    (the in-plane equilibrium of the module docstring) and its force on the ring is F_j(x_j; u), so

        dF/du = sum_j [dF_j/du − dF_j/dx_j·(dG_j/dx_j)^(−1)·dG_j/du]

    (the Schur complement of the balls' block; Jones 1960; Harris & Kotzalas, Rolling Bearing
    Analysis, 5th ed., Vol. 2 (2007), ch. 1–3). Every term is differentiated exactly: per contact k,
    with d_k = b − c_k, n_k = d_k/|d_k| (dn/dd = (I − n·nᵀ)/|d|), delta_k = |d_k| − (f_k − 0.5)·Dw,

        dQ/dd = 1.5·K·delta^0.5·nᵀ + delta^1.5·(dK/dRx)(dRx/dcos a)·d(cos a)/dd

    (Hertz Q = K·delta^1.5 with K at the current contact angle, `hertz_stiffness_slope`), the
    rotation of the friction direction tau = (cos a, −sin a), the inner friction's share
    f_k = lambda_i·M_g/Dw·Q_k/(Q_1 + Q_2), the centrifugal force m·omega_m²·r (dG_r/dr = m·omega_m²),
    the contact points p_k = b + (Dw − delta_k)/2·n_k (moment arms) and the contact centres' motion
    with the ring (`geometry.ring_point_in_plane`, linear in u: c_k = C_k·u + const). With
    d_k = b − c_k: dG/dx = sum_m dG/dd_m + diag(0, m·omega_m²), dG/du = −sum_m dG/dd_m·C_m, and the
    same for F plus its explicit moment-arm terms. The kinematics are held as the ring Newton holds
    them. work: scratch, at least 200 floats (no allocation in the ball loop). Balls without a
    loaded inner contact exert no force on the ring and are skipped."""
    q = work[0:3]
    gq = work[3:9]          # dQ_k/dd_k (2 per contact)
    nv = work[9:15]         # n_k
    dn = work[15:27]        # dn_k/dd_k (2×2 per contact, row-major)
    tau = work[27:33]
    dtau = work[33:45]
    fr = work[45:48]        # friction force along tau_k
    delta = work[48:51]
    gd = work[51:87]        # dP_k/dd_m
    fd = work[87:117]       # dF/dd_m
    cmat = work[117:147]    # dc_m/du, m = 0..2, 2×5 each: index (m·10 + 5a + i)
    db = work[153:163]      # dF/db through the contact points (5×2)
    for i in range(5):
        for jj in range(5):
            jac[i, jj] = 0.0
    for m in range(30):
        cmat[m] = 0.0
    for j in range(psi.shape[0]):
        c = math.cos(psi[j])
        s = math.sin(psi[j])
        for k in range(3):
            q[k] = 0.0
            if not active[k]:
                continue
            xc, rc = gx[0], gr[0]
            if k != CONTACT_OUTER:
                xc, rc = geo.ring_point_in_plane(psi[j], gx[k], gr[k], u[0], u[1], u[2], u[3], u[4])
                # x = x0 + u_x + r0·th, r = r0 + u_y·c + u_z·s − x0·th, th = theta_y·s − theta_z·c
                b0 = k * 10
                cmat[b0 + 0] = 1.0
                cmat[b0 + 3] = gr[k] * s
                cmat[b0 + 4] = -gr[k] * c
                cmat[b0 + 6] = c
                cmat[b0 + 7] = s
                cmat[b0 + 8] = -gx[k] * s
                cmat[b0 + 9] = gx[k] * c
            _contact_slopes(k, xb[j], rb[j], xc, rc, cf[k], dw, dm, e_eff, q, gq, nv, dn, tau, dtau, delta)
        qin = q[1] + q[2]
        if qin <= 0.0:
            continue
        fr[0] = -lam_o[j] * mg[j] / dw if q[0] > 0.0 else 0.0
        big = lam_i[j] * mg[j] / dw
        for k in range(1, 3):
            fr[k] = big * q[k] / qin if q[k] > 0.0 else 0.0
        _ball_force_slopes(q, gq, nv, dn, tau, dtau, fr, big, gd)
        gxx, gxr, grx, grr = 0.0, 0.0, 0.0, m_w2[j]
        for m in range(9):
            gxx += gd[4 * m + 0]
            gxr += gd[4 * m + 1]
            grx += gd[4 * m + 2]
            grr += gd[4 * m + 3]
        det = gxx * grr - gxr * grx
        if det == 0.0 or not math.isfinite(det):
            continue
        _ring_force_slopes(xb[j], rb[j], u, c, s, dw, q, nv, dn, tau, fr, delta, gd, fd, db, jac)
        _schur_add(gd, fd, db, cmat, gxx, gxr, grx, grr, det, jac)


@njit(cache=True)
def _schur_add(gd, fd, db, cmat, gxx, gxr, grx, grr, det, jac):
    """jac += F_u − F_x·G_x⁻¹·G_u for one ball, F_x = db + sum_m fd_m, G_u = −sum_m (sum_k gd_km)·C_m,
    F_u (through the contact centres) = −sum_m fd_m·C_m."""
    ixx = grr / det
    ixr = -gxr / det
    irx = -grx / det
    irr = gxx / det
    for i in range(5):
        fxb0 = db[2 * i]
        fxb1 = db[2 * i + 1]
        for m in range(3):
            fxb0 += fd[m * 10 + 2 * i]
            fxb1 += fd[m * 10 + 2 * i + 1]
        h0 = fxb0 * ixx + fxb1 * irx          # row i of F_x·G_x⁻¹
        h1 = fxb0 * ixr + fxb1 * irr
        for m in range(1, 3):
            s00 = 0.0
            s01 = 0.0
            s10 = 0.0
            s11 = 0.0
            for k in range(3):
                b1 = (k * 3 + m) * 4
                s00 += gd[b1 + 0]
                s01 += gd[b1 + 1]
                s10 += gd[b1 + 2]
                s11 += gd[b1 + 3]
            for ju in range(5):
                c0 = cmat[m * 10 + ju]
                c1 = cmat[m * 10 + 5 + ju]
                gu0 = -(s00 * c0 + s01 * c1)
                gu1 = -(s10 * c0 + s11 * c1)
                fu = -(fd[m * 10 + 2 * i] * c0 + fd[m * 10 + 2 * i + 1] * c1)
                jac[i, ju] += fu - (h0 * gu0 + h1 * gu1)
