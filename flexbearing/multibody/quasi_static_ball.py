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
from flexbearing.multibody.hertz import hertz_stiffness, race_curvature_radii
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
