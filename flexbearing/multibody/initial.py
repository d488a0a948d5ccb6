"""Initial state of a dynamic run from a quasi-static equilibrium (Jones–Harris without friction).

`initial_state(model, speed_rad_s, Fa, Fr)` returns y0 (layout: flexbearing.multibody.model): every ball at
its quasi-static position in its azimuthal plane, orbiting at the pure-rolling cage speed
nm = 0.5·omega_i·(1 − Dw·cos(alpha)/dm) (alpha the mean loaded contact angle), spinning so that
the outer and the loaded inner contact roll without sliding; the inner ring at its equilibrium
displacement and tilt; the cage centred, spinning at nm, each pocket centred on its ball.

Quasi-static model (`quasi_static`; Harris & Kotzalas, Rolling Bearing Analysis Vol. 2, ch. 3,
the Jones model with the gyroscopic moment and friction left out): for ball j at azimuth psi_j,

    sum_c (−Q_c·n_c) + m_b·r_j·Omega² e_r = 0          (2 equations in the ball plane: x_j, r_j)
    F_ext + sum_j sum_inner (Q·n, at the contact point) = 0   (5 ring equations: forces + moments)

with Q_c = K(alpha_c)·delta_c^1.5 from the same geometry (flexbearing.multibody.geometry) and Hertz tables as
the dynamics. Nested solution: for a trial ring position each ball is solved by Newton's method
(2x2, finite-difference Jacobian); the 5 ring equations are solved by scipy's hybrid Powell
method. Radial load Fr acts along −Z (the scene default) unless a full load vector is given.

Race-control balls (model option ball_attitude "outer", "inner", "jones"; flexbearing.multibody.dynamics
"Ball attitude"): the orbit is the mean over the balls of Jones's race-control orbital speed
(`race_control_ball_kinematics`: both contacts roll, the controlling race does not spin), and each
ball's angular velocity makes its controlling contact roll without spin, so the constrained run
starts on its constraint. "no_pivot" balls start as free ones (no race controls them).

`flexbearing.multibody.quasi_static` (Jones with the gyroscopic moment and race control) is the independent
reference; this solver is the dynamics' own equilibrium (same force law and Hertz tables as the
right-hand side), so that a run starts at rest in its own equations. Without the gyroscopic moment
the two agree to 2e-9 on the loads at rest (tests/test_quasi_static.py).
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.optimize import root

from flexbearing.common.validation import InputError, require_range
from flexbearing.multibody import model as M
from flexbearing.multibody.dynamics import CONTROL_NONE, _hertz_lookup, control_race
from flexbearing.multibody.model_layout import (
    CONTACT_INNER, CONTACT_INNER_LEFT, CONTACT_INNER_RIGHT, CONTACT_OUTER, CONTACT_RACE, RACE_CONTACTS, RACE_INNER,
    RACE_OUTER,
)
from flexbearing.multibody import state_layout as SL
from flexbearing.multibody.geometry import nominal_cage_speed
from flexbearing.multibody.geometry import race_contact, ring_point_in_plane


def _semi_major_axis(model, kind, Q, ca):
    """Hertz semi-major axis a (m) of a race contact, as in flexbearing.multibody.dynamics._race."""
    if Q <= 0.0:
        return 0.0
    K, ell, ek, R, rx, ry = _hertz_lookup(model.hertz_table, kind, ca)
    b = (6.0 * ek * Q * R / (math.pi * ell * model.p[M.P_EBR])) ** (1.0 / 3.0)
    return ell * b


def deepest_contact(model, qs) -> tuple[float, int, int, float]:
    """(approach [m], ball, contact (CONTACT_OUTER, CONTACT_INNER_LEFT, CONTACT_INNER_RIGHT), load [N])
    of the race contact with the largest Hertz approach delta = (Q/K(alpha))^(2/3) in the equilibrium `qs`
    (Q = K·delta^1.5 with the dynamics' Hertz tables, Harris & Kotzalas Vol. 1 eq. 6.41)."""
    best = (0.0, 0, 0, 0.0)
    for j, res in enumerate(qs["contacts"]):
        for c in range(len(RACE_CONTACTS)):
            Q, ca = res[c][0], res[c][1]
            if Q > 0.0:
                K = _hertz_lookup(model.hertz_table, CONTACT_RACE[c], ca)[0]
                d = (Q / K) ** (2.0 / 3.0)
                if d > best[0]:
                    best = (d, j, c, Q)
    return best


def check_contact_range(model, speed_rad_s: float, load, qs=None) -> None:
    """InputError if the quasi-static equilibrium under `load` (Fx, Fy, Fz, N) puts a race contact
    deeper than the dynamics' plausibility limit delta_max = DELTA_MAX_FRAC·Dw (flexbearing.multibody.dynamics:
    beyond it the right-hand side stops the run at its first step, and a resume from the same state
    stops again). The message gives the largest multiple of the load inside the limit (within 2 %),
    found with the same solver (only on this failure path: 2-4 solves of ~0.35 s)."""
    from flexbearing.multibody.dynamics import CONTACT_NAMES, DELTA_MAX_FRAC
    load = np.asarray(load, dtype=float)
    qs = quasi_static(model, speed_rad_s, load) if qs is None else qs
    limit = DELTA_MAX_FRAC * model.p[M.P_DW]
    d, j, c, Q = deepest_contact(model, qs)
    if d <= limit:
        return
    # the largest load factor inside the limit: fixed-point iteration on the Hertz scaling
    # delta ~ Q^(2/3) ~ s^(2/3) (the contact angle's growth makes it converge in 2-4 solves), aimed at
    # 0.995 of the limit, keeping the largest factor found inside
    lo, s_k, d_k = 0.0, 1.0, d
    for _ in range(8):
        s_k *= (0.995 * limit / d_k) ** 1.5
        d_k = deepest_contact(model, quasi_static(model, speed_rad_s, s_k * load))[0]
        if d_k <= limit:
            lo = max(lo, s_k)
            if d_k > 0.985 * limit:
                break
    f = ", ".join(f"{v + 0.0:.4g}" for v in load)      # + 0.0: no "-0"
    raise InputError(
        f"operation.load = ({f}) N is beyond what the model's contacts carry: in its quasi-static "
        f"equilibrium ball {j}'s {CONTACT_NAMES[c]} contact has a Hertz approach of {d * 1e6:.0f} um "
        f"(Q = {Q:.3g} N), beyond the model's limit {DELTA_MAX_FRAC:g}·Dw = {limit * 1e6:.0f} um (Hertz's "
        f"small-strain range; the rings would yield long before). This bearing carries this load "
        f"direction up to about {lo * np.linalg.norm(load):.3g} N within the model (allowed range "
        f"[0, {lo * np.linalg.norm(load):.3g}] N): reduce the load")


def _loaded_inner(res) -> int:
    """The inner contact (CONTACT_INNER_LEFT or _RIGHT) with the larger load in res [(Q, ...) x 3]."""
    return CONTACT_INNER_LEFT if res[CONTACT_INNER_LEFT][0] >= res[CONTACT_INNER_RIGHT][0] else CONTACT_INNER_RIGHT


def control_contact(model, res) -> int:
    """Contact index (CONTACT_OUTER, or the more loaded of the inner halves) of the race that
    controls the ball's attitude under the model option ball_attitude (flexbearing.multibody.dynamics
    docstring, "Ball attitude"), CONTROL_NONE for free or non-pivoting balls and an unloaded
    controlling race. res: [(Q, ca, sa, nx, nr, x_p, r_p) x 3]."""
    ci = _loaded_inner(res)
    out = res[CONTACT_OUTER]
    qo, qi = out[0], res[ci][0]
    ao = _semi_major_axis(model, RACE_OUTER, qo, out[1])
    ai = _semi_major_axis(model, RACE_INNER, qi, res[ci][1])
    c = control_race(int(model.flags[M.F_ATTITUDE]), qo, ao, out[3], out[4], qi, ai, res[ci][3], res[ci][4])
    if c == RACE_OUTER:
        return CONTACT_OUTER
    return ci if c == RACE_INNER else CONTROL_NONE


class _Races(NamedTuple):
    """The model parameters the ball equilibrium reads, as Python floats.

    Why: `_ball_forces` runs ~15,000 times per initial state; arithmetic on Python floats is
    bit-identical to that on the float64 entries of model.p and several times cheaper than on numpy
    scalars. cos_fixed is cos(alpha0) with the option hertz_fixed_angle (the Hertz constants at the
    free contact angle), else None (at each contact's own angle).
    """
    dw: float
    mb: float
    xo: float
    ro: float
    fe: float
    xil: float
    ril: float
    xir: float
    rir: float
    fi: float
    cos_fixed: float | None
    htab: np.ndarray
    n_inner: int = 2                  # inner race contacts (model.F_INNER_HALVES): 1 for a one-piece ring


def _races(model) -> _Races:
    """The model's `_Races`."""
    p = model.p
    fixed = math.cos(p[M.P_ALPHA0]) if model.flags[M.F_HERTZ_FIXED] else None
    return _Races(*(float(p[k]) for k in (M.P_DW, M.P_MB, M.P_XO, M.P_RO, M.P_FE, M.P_XIL, M.P_RIL,
                                          M.P_XIR, M.P_RIR, M.P_FI)), fixed, model.hertz_table,
                  int(model.flags[M.F_INNER_HALVES]))


def _ball_forces(g: _Races, psi, xb, rb, ring, omega_orbit, keep: bool = True):
    """Net in-plane force on a ball (x, r) (module docstring: sum_c(−Q_c·n_c) + m_b·r·Omega² e_r),
    the sum of its contact loads, and with `keep` the contact results
    [(Q, ca, sa, nx, nr, x_p, r_p) x 3] (None without: the Newton's difference quotients need only
    the forces). Q_c = K(alpha_c)·delta_c^1.5 (Harris & Kotzalas Vol. 1 eq. 6.41)."""
    dw = g.dw
    fx = 0.0
    fr = g.mb * rb * omega_orbit ** 2
    q_sum = 0.0
    res = [] if keep else None
    for c in range(len(RACE_CONTACTS)):
        if c > g.n_inner:                 # the removed second half of a one-piece ring
            if keep:
                res.append((0.0, 1.0, 0.0, 0.0, -1.0, xb, rb))
            continue
        if c == CONTACT_OUTER:
            xc, rc, f = g.xo, g.ro, g.fe
        else:
            if c == CONTACT_INNER_LEFT:
                xc, rc = ring_point_in_plane(psi, g.xil, g.ril, *ring)
            else:
                xc, rc = ring_point_in_plane(psi, g.xir, g.rir, *ring)
            f = g.fi
        kind = CONTACT_RACE[c]
        delta, ca, sa = race_contact(xb, rb, xc, rc, f, dw)
        dx, dr = xb - xc, rb - rc
        d = math.hypot(dx, dr)
        nx, nr = dx / d, dr / d
        if delta > 0.0:
            K = _hertz_lookup(g.htab, kind, ca if g.cos_fixed is None else g.cos_fixed)[0]
            Q = K * delta ** 1.5
        else:
            Q = 0.0
        fx -= Q * nx
        fr -= Q * nr
        q_sum += Q
        if keep:
            rho = 0.5 * dw - 0.5 * max(delta, 0.0)
            res.append((Q, ca, sa, nx, nr, xb + rho * nx, rb + rho * nr))
    return fx, fr, q_sum, res


def _solve_ball(g: _Races, psi, ring, omega_orbit, x0, r0):
    """Newton on the 2 ball equilibrium equations (finite-difference Jacobian, steps limited to
    20 um); returns (x, r, contacts, converged)."""
    x, r = x0, r0
    h = 1e-9
    for _ in range(60):
        fx, fr, q_sum, res = _ball_forces(g, psi, x, r, ring, omega_orbit)
        if abs(fx) + abs(fr) < 1e-9 * (1.0 + q_sum):
            return x, r, res, True
        fx1, fr1, _, _ = _ball_forces(g, psi, x + h, r, ring, omega_orbit, keep=False)
        fx2, fr2, _, _ = _ball_forces(g, psi, x, r + h, ring, omega_orbit, keep=False)
        J = np.array([[fx1 - fx, fx2 - fx], [fr1 - fr, fr2 - fr]]) / h
        try:
            dx, dr = np.linalg.solve(J, [-fx, -fr])
        except np.linalg.LinAlgError:
            dx, dr = 0.0, 1e-7
        step = math.hypot(dx, dr)
        lim = 2e-5
        if step > lim:
            dx, dr = dx * lim / step, dr * lim / step
        x, r = x + dx, r + dr
    fx, fr, q_sum, res = _ball_forces(g, psi, x, r, ring, omega_orbit)
    return x, r, res, False


def _ring_loads(g: _Races, angles, balls, v, omega_orbit, load, dm):
    """The 5 ring equations at the ring position v = (x, y, z, tilt_y, tilt_z) (module docstring):
    each ball solved in its plane (warm-started from and updating `balls`, [[x, r]] per ball), the
    inner contacts' reactions +Q·n and their moments about the ring centre (p − c) × (Q·n)
    summed with the load. Returns (residual [N x 3, the moments scaled to forces by the pitch
    radius], contacts per ball, every ball converged).

    Plain floats throughout, in the order of the former numpy version (np.cross's
    a1·b2 − a2·b1, ...), so that the result is bit-identical to it.
    """
    ring = tuple(float(t) for t in v)
    vx, vy, vz = ring[:3]
    Fx, Fy, Fz = load
    My = Mz = 0.0
    out = []
    ok = True
    for j, (psi, cs, sn) in enumerate(angles):
        x, r, res, conv = _solve_ball(g, psi, ring, omega_orbit, balls[j][0], balls[j][1])
        balls[j] = [x, r]
        ok = ok and conv
        for c in CONTACT_INNER:
            Q, ca, sa, nx, nr, xp, rp = res[c]
            gx, gy, gz = Q * nx, Q * nr * cs, Q * nr * sn      # reaction on the ring: +Q n
            Fx, Fy, Fz = Fx + gx, Fy + gy, Fz + gz
            lx, ly, lz = xp - vx, rp * cs - vy, rp * sn - vz   # lever from the ring centre
            My += lz * gx - lx * gz
            Mz += lx * gy - ly * gx
        out.append(res)
    arm = 0.5 * dm
    return np.array([Fx, Fy, Fz, My / arm, Mz / arm]), out, ok


def quasi_static(model, speed_rad_s: float, load, ring_guess=None, omega_orbit: float | None = None) -> dict:
    """Quasi-static equilibrium (module docstring). load = (Fx, Fy, Fz) on the inner ring, N.

    Returns dict: ring (x, y, z, tilt_y, tilt_z), ball_x, ball_r, psi (Z,), contact_load (Z, 3),
    contact_angle (Z, 3) signed, omega_orbit (rad/s), residual (N, N·m).
    """
    p = model.p
    z = model.n_balls
    dw, dm = p[M.P_DW], p[M.P_DM]
    psi = 2.0 * math.pi * np.arange(z) / z
    angles = [(float(a), math.cos(a), math.sin(a)) for a in psi]
    load = np.asarray(load, dtype=float)
    load_f = tuple(float(f) for f in load)
    if omega_orbit is None:
        omega_orbit = nominal_cage_speed(speed_rad_s, dw, dm, p[M.P_ALPHA0])
    g = _races(model)
    balls = [[0.0, 0.5 * dm] for _ in range(z)]     # each ball's Newton start: its last solution

    def ring_residual(v):
        return _ring_loads(g, angles, balls, v, omega_orbit, load_f, dm)[0]

    v0 = np.zeros(5) if ring_guess is None else np.asarray(ring_guess, float)
    # first guess: the ring displaced along the load until the force along it balances (bracketed
    # 1-D search from 0.1 um doubling up to 2 mm, then bisection): it engages the contacts even
    # through a radial clearance, where a Newton start at zero has a zero Jacobian
    if ring_guess is None:
        fn = np.linalg.norm(load)
        if fn > 0:
            d = load / fn

            def along(s):
                v = np.zeros(5)
                v[:3] = s * d
                return float(ring_residual(v)[:3] @ d)

            lo, f_lo = 0.0, along(0.0)
            s = 1e-7
            while s < 2e-3:
                f_s = along(s)
                if f_s * f_lo <= 0.0:
                    for _ in range(60):
                        mid = 0.5 * (lo + s)
                        if mid == lo or mid == s:
                            break           # the bracket is two adjacent floats: no solve can narrow it
                        f_m = along(mid)
                        if f_m * f_lo <= 0.0:
                            s = mid
                        else:
                            lo, f_lo = mid, f_m
                    break
                lo, f_lo = s, f_s
                s *= 2.0
            v0[:3] = s * d
            balls[:] = [[0.0, 0.5 * dm] for _ in range(z)]
    scale = np.array([1e-5, 1e-5, 1e-5, 1e-4, 1e-4])
    sol = root(lambda u: ring_residual(u * scale), v0 / scale, method="hybr", options={"xtol": 1e-12})
    ring = sol.x * scale
    resid, res, ok = _ring_loads(g, angles, balls, ring, omega_orbit, load_f, dm)
    if not ok:
        # a ball's Newton stopped at its 60 steps: continue it from there once more
        resid, res, ok = _ring_loads(g, angles, balls, ring, omega_orbit, load_f, dm)
    Q = np.array([[c[0] for c in r] for r in res])
    ang = np.array([[math.atan2(c[2], c[1]) for c in r] for r in res])
    return {"ring": ring, "ball_x": np.array([b[0] for b in balls]), "ball_r": np.array([b[1] for b in balls]),
            "psi": psi, "contact_load": Q, "contact_angle": ang, "omega_orbit": omega_orbit,
            "residual": resid, "contacts": res, "converged": bool(sol.success)}


def race_control_ball_kinematics(model, qs, j: int, speed_rad_s: float):
    """(omega_m, w_x, w_r) of ball j of a quasi-static result under race control, or None for a
    free ball: the three linear conditions of Jones's kinematics (flexbearing.multibody.quasi_static module
    docstring) at the ball's own contact points, w absolute (rad/s):

        r·omega_m + rho_o·(w_x·n_or − w_r·n_ox) = 0                           (outer rolls)
        r·omega_m + rho_i·(w_x·n_ir − w_r·n_ix) = omega_i·(r_pi − r_ring)    (inner rolls)
        w_x·n_cx + w_r·n_cr = w_race·n_cx                                    (no spin, race c)
    """
    cont = qs["contacts"][j]
    cc = control_contact(model, cont)
    if cc == CONTROL_NONE:
        return None
    x, r, psi = qs["ball_x"][j], qs["ball_r"][j], qs["psi"][j]
    ring = qs["ring"]
    ci = _loaded_inner(cont)
    ring_rc = ring[1] * math.cos(psi) + ring[2] * math.sin(psi)
    a, b = [], []
    for c in (CONTACT_OUTER, ci):
        Q, ca, sa, nx, nr, xp, rp = cont[c]
        rho = math.hypot(xp - x, rp - r)
        a.append([r, rho * nr, -rho * nx])
        b.append(0.0 if c == CONTACT_OUTER else speed_rad_s * (rp - ring_rc))
    nx, nr = cont[cc][3], cont[cc][4]
    a.append([0.0, nx, nr])
    b.append((0.0 if cc == CONTACT_OUTER else speed_rad_s) * nx)
    om, wx, wr = np.linalg.solve(np.array(a), np.array(b))
    return float(om), float(wx), float(wr)


def _mean_alpha(qs) -> float:
    Q, ang = qs["contact_load"], qs["contact_angle"]
    pick = np.where(Q[:, 1] >= Q[:, 2], 1, 2)
    ai = np.abs(ang[np.arange(len(pick)), pick])
    return 0.5 * (float(np.mean(ang[:, 0])) + float(np.mean(ai)))


def initial_state(model, speed_rad_s: float, Fa: float, Fr: float, load=None, refine: bool = True) -> np.ndarray:
    """y0 from the quasi-static equilibrium at inner-ring speed speed_rad_s, axial load Fa (+X) and
    radial load Fr (along −Z), N; or a full `load` (Fx, Fy, Fz). Module docstring."""
    require_range("initial.speed_rad_s", speed_rad_s, 0.0, 1e5, unit="rad/s")
    if load is None:
        require_range("initial.Fa", Fa, -1e6, 1e6, unit="N")
        require_range("initial.Fr", Fr, 0.0, 1e6, unit="N")
        load = (Fa, 0.0, -Fr)
    p = model.p
    z = model.n_balls
    dw, dm = p[M.P_DW], p[M.P_DM]
    qs = quasi_static(model, speed_rad_s, load)
    if refine:
        om = nominal_cage_speed(speed_rad_s, dw, dm, _mean_alpha(qs))
        qs = quasi_static(model, speed_rad_s, load, ring_guess=qs["ring"], omega_orbit=om)
        if model.flags[M.F_ATTITUDE] != M.ATTITUDE_FREE and speed_rad_s > 0.0:
            # race control: orbit at the mean race-control orbital speed (module docstring)
            oms = [k[0] for k in (race_control_ball_kinematics(model, qs, j, speed_rad_s) for j in range(z))
                   if k is not None]
            if oms:
                qs = quasi_static(model, speed_rad_s, load, ring_guess=qs["ring"], omega_orbit=float(np.mean(oms)))
    check_contact_range(model, speed_rad_s, load, qs)
    if not qs["converged"] and np.max(np.abs(qs["residual"])) > 1e-3 * (1.0 + np.linalg.norm(load)):
        raise InputError(f"quasi-static initial state did not converge for load {tuple(load)} N "
                         f"(residual {qs['residual']})")
    om = qs["omega_orbit"]
    lay = M.state_layout(model)
    y = np.zeros(lay["n_state"])
    ring = qs["ring"]
    for j in range(z):
        o = SL.ball_offset(j)
        x, r, psi = qs["ball_x"][j], qs["ball_r"][j], qs["psi"][j]
        y[o + SL.BALL_X], y[o + SL.BALL_R], y[o + SL.BALL_PSI] = x, r, psi
        y[o + SL.BALL_PSI_DOT] = om
        # pure rolling at the outer and the loaded inner contact: rolling-direction slide = 0
        cont = qs["contacts"][j]
        ci = _loaded_inner(cont)
        rows, rhs = [], []
        ring_rc = ring[1] * math.cos(psi) + ring[2] * math.sin(psi)
        rolling = (CONTACT_OUTER, ci)              # the contacts that roll, one row each
        for c in rolling:
            Q, ca, sa, nx, nr, xp, rp = cont[c]
            rho = math.hypot(xp - x, rp - r)
            # v_ball,t = r·om + rho(w_x n_r − w_r n_x);  v_race,t = 0 (outer) or omega_i (r_p − rc)
            vrace = 0.0 if c == CONTACT_OUTER else speed_rad_s * (rp - ring_rc)
            rows.append([rho * nr, -rho * nx])
            rhs.append(vrace - r * om)
        cc = control_contact(model, cont)
        if cc != CONTROL_NONE:
            # race control: the controlling contact rolls and does not spin (module docstring)
            Q, ca, sa, nx, nr, xp, rp = cont[cc]
            w_race = 0.0 if cc == CONTACT_OUTER else speed_rad_s
            k = rolling.index(cc)
            rows = [rows[k], [nx, nr]]
            rhs = [rhs[k], w_race * nx]
        w = np.linalg.solve(np.array(rows), np.array(rhs))
        y[o + SL.BALL_W_X], y[o + SL.BALL_W_R] = w
    r0 = lay["ring"]
    y[r0:r0 + SL.RING_POSITIONS] = ring
    c0 = lay["cage"]
    y[c0 + SL.CAGE_OMEGA] = om
    y[c0 + SL.CAGE_X] = float(np.mean(qs["ball_x"]))  # cage follows the balls axially
    return y
