"""Steady running state of a thrust-loaded bearing: the fixed point of the dynamics' own equations.

Under a pure axial load, without gravity and with the cage centred, every ball meets the same
loads at every azimuth, so the steady state is the same for all balls and constant in the frame
that turns with the cage. It is found directly instead of by integrating until the transients
have died (which at light load and high speed takes the dynamics 5–15 s of simulated time:
benchmarks/results/slip_rate.md, "Long runs").

Unknowns (9): ball centre x, r in its plane; the ball's azimuth relative to its pocket centre
(the ball presses on the pocket wall to push the cage against its drag); the common orbital
speed = cage speed; the ball's absolute angular velocity (3 components in (e_x, e_r, e_t)); the
inner ring's axial position; the cage's axial position. Equations (9): the corresponding
accelerations of `flexbearing.multibody.dynamics.rhs` vanish (ball x, r, orbit and three angular
accelerations; ring axial; cage spin; cage axial), each scaled to a force per ball. Solved by
MINPACK's hybrid Powell method (scipy.optimize.root "hybr"), Levenberg–Marquardt as fallback,
from the quasi-static start (`flexbearing.multibody.initial.initial_state`) with the ball against the
driving side of its pocket.

This is Harris's skidding analysis of a thrust-loaded angular-contact ball bearing (T. A. Harris,
"An analytical method to predict skidding in thrust-loaded, angular-contact ball bearings",
J. Lubr. Technol. 93(1):17–24, 1971), made with the dynamics' own force models: the ball spin
follows from the traction at both contacts (no race-control hypothesis), with churning drag,
pocket and guide-land forces. The result is a state vector y of the dynamics: integrating from it
stays there (tests/test_steady.py), and a run started from it needs no settling.

Limits: a fixed point exists only where the traction can balance the drag at some skid; where the
traction law is flat over the slips involved (the 4106 fit's dead zone at light loads,
flexbearing.multibody.traction "Origin law") the equations are singular and no root is found — `converged`
is False and the dynamics must be integrated instead. Measured on the slip-rate cases (validation
oil state, Fr and gravity left out; benchmarks/bench_steady.py): roots for cases 4, 5, 6, 10, 11,
14, 15, none for 1–3, 7–9, 12, 13; 0.3–0.5 s each, most of it the quasi-static start (the root
search itself 20–40 ms). The fixed point has a centred cage. Whether the dynamics stay there is a
separate question: with the weight on (the slip validation) they settle within 0.3 points of it
(cases 5, 6); without it, at light load, the outer-ring-guided cage whirls out to its rim
(tests/test_cage_whirl.py) and the skid changes (case 4, 15 s: cage 198 against 267 rad/s).

Under a combined load (or with weight) the balls differ by azimuth: `steady_held_cage_state`
solves every ball separately with the balls frozen at their azimuths and the cage held off-centre
in its guide film (6Z + 11 unknowns, Newton with a Levenberg–Marquardt fallback, 0.3–0.7 s for the
paper bearing); its docstring says what the frozen azimuths leave out.
"""
from __future__ import annotations

import math
import time

import numpy as np

from flexbearing.common.convergence import SolverNotConverged
from flexbearing.common.validation import InputError, require_range
from flexbearing.multibody import dynamics as D
from flexbearing.multibody import outputs as O
from flexbearing.multibody import model as M
from flexbearing.multibody import state_layout as SL
from flexbearing.multibody import traction as TR
from flexbearing.multibody.initial import initial_state
from flexbearing.multibody.race_kernels import TRACTION_EHL
from flexbearing.multibody.steady_arclength import pseudo_arclength
from flexbearing.multibody.steady_existence import traction_drag_bound, turning_point
from flexbearing.multibody.steady_settle import settle_then_solve
from flexbearing.multibody.steady_hold import cage_hold_check
from flexbearing.multibody.steady_mean import settled_mean
from flexbearing.multibody.deflation import deflated_search
from flexbearing.multibody.steady_search_starts import START_FRACTIONS, physical_starts, unknowns_of_state

class SteadyNotConverged(SolverNotConverged):
    """A steady solve found no fixed point (raised unless strict=False): .result is the (y, info) it
    ended with (info["converged"] False, info["reason"] why where known), .residual its scaled
    residual, .iterations the function evaluations (thrust state) or Newton iterations (held cage)."""


def _checked(y, info, strict: bool, what: str):
    """(y, info), or SteadyNotConverged where strict and the solve did not converge."""
    if strict and not info["converged"]:
        reason = info.get("reason") or f"residual {info['residual']:.2e} above the tolerance"
        raise SteadyNotConverged(f"no {what} found: {reason}", result=(y, info), residual=info["residual"],
                                 iterations=int(info.get("iterations", info.get("nfev", 0))), diagnostic=reason)
    return y, info


UNKNOWNS = ("ball_x", "ball_r", "pocket_offset", "orbit_speed", "ball_w_x", "ball_w_r", "ball_w_t",
            "ring_x", "cage_x")


def steady_thrust_state(model, speed_rad_s: float, axial_load: float, y_start: np.ndarray | None = None,
                        tol: float = 1e-10, strict: bool = True) -> tuple[np.ndarray, dict]:
    """(y, info): the steady state (module docstring) at inner-ring speed speed_rad_s (rad/s) and
    axial load axial_load (N, along +X), as a full state vector of `model` (flexbearing.multibody.model layout,
    ball j at azimuth 2·pi·j/Z + pocket_offset, cage angle 0). info: converged, residual (max scaled
    residual, N per ball), cage_speed (rad/s), slip_rate ((nm − nc)/nm, nm at the mean loaded
    contact angle, the paper's definition), the unknowns by name, nfev, and outputs (the
    flexbearing.multibody.outputs.evaluate_outputs dict of y). tol: residual tolerance relative to the axial
    load per ball. strict (default): no root raises SteadyNotConverged; strict=False returns it with
    converged False (where the traction cannot balance the drag there is none: module docstring)."""
    require_range("steady.speed_rad_s", speed_rad_s, 0.0, 1e5, lo_open=True, unit="rad/s")
    require_range("steady.axial_load", abs(axial_load), 0.0, 1e7, lo_open=True, unit="N")
    p = model.p
    if p[M.P_GRAV] != 0.0:
        raise InputError(f"model.gravity = {p[M.P_GRAV]} m/s^2: the steady thrust state needs 0 "
                         "(with weight the balls differ by azimuth and there is no common steady state)")
    from scipy.optimize import root

    z = model.n_balls
    lay = M.state_layout(model)
    r0, c0 = lay["ring"], lay["cage"]
    speed_table = np.array([[0.0, speed_rad_s]])
    load_table = np.array([[0.0, axial_load, 0.0, 0.0]])
    impacts = np.zeros((0, 6))
    work = D.new_work(model)
    y0 = initial_state(model, speed_rad_s, axial_load, 0.0) if y_start is None else np.asarray(y_start, float)
    dydt = np.zeros_like(y0)
    # start: quasi-static ball, displaced towards the pocket side that drives the cage (the pocket
    # force is the soft linear Kc·z inside the clearance, paper §2.3.1; starting at the centre, where
    # it vanishes, slows the search at light loads)
    u0 = np.array([y0[SL.BALL_X], y0[SL.BALL_R], 0.6 * p[M.P_CP] / p[M.P_RCAGE_POCKET], y0[SL.BALL_PSI_DOT],
                   y0[SL.BALL_W_X], y0[SL.BALL_W_R], y0[SL.BALL_W_T], y0[r0 + SL.RING_X], y0[c0 + SL.CAGE_X]])
    w_ball = abs(y0[SL.BALL_W_X]) + abs(y0[SL.BALL_W_R]) + 1.0
    scale_u = np.array([1e-6, 1e-6, 1e-4, 1e-3 * abs(y0[SL.BALL_PSI_DOT]) + 1e-3, 1e-3 * w_ball, 1e-3 * w_ball,
                        1e-3 * w_ball, 1e-6, 1e-6])
    # accelerations -> forces per ball (N), relative to the axial load per ball
    half_dw, half_dm = 0.5 * p[M.P_DW], 0.5 * p[M.P_DM]
    scale_r = np.array([p[M.P_MB], p[M.P_MB], p[M.P_MB] * half_dm, p[M.P_IB] / half_dw, p[M.P_IB] / half_dw,
                        p[M.P_IB] / half_dw, p[M.P_MI] / z, p[M.P_ICP] / half_dm / z, p[M.P_MC] / z])
    scale_r /= abs(axial_load) / z

    def state(v):
        u = u0 + v * scale_u
        y = np.zeros_like(y0)
        for j in range(z):
            o = SL.ball_offset(j)
            y[o:o + SL.BALL_STATE] = (u[0], u[1], 2.0 * math.pi * j / z + u[2], 0.0, 0.0, u[3], u[4], u[5], u[6])
        y[r0 + SL.RING_X] = u[7]
        y[c0 + SL.CAGE_X] = u[8]
        y[c0 + SL.CAGE_OMEGA] = u[3]                # the cage turns with the balls
        return y

    def residual(v):
        y = state(v)
        D.rhs(0.0, y, dydt, p, model.flags, model.hertz_table, model.traction_table, speed_table, load_table,
              impacts, work, model.cage)
        return scale_r * np.array([dydt[SL.BALL_X_DOT], dydt[SL.BALL_R_DOT], dydt[SL.BALL_PSI_DOT],
                                   dydt[SL.BALL_W_X], dydt[SL.BALL_W_R], dydt[SL.BALL_W_T], dydt[r0 + SL.RING_VX],
                                   dydt[c0 + SL.CAGE_OMEGA], dydt[c0 + SL.CAGE_VX]])

    sol = root(residual, np.zeros(9), method="hybr", options=dict(xtol=1e-12))
    nfev = sol.nfev
    if np.max(np.abs(sol.fun)) > tol:
        sol = root(residual, sol.x, method="lm", options=dict(xtol=1e-14, ftol=1e-14))
        nfev += sol.nfev
    y = state(sol.x)
    res = float(np.max(np.abs(sol.fun)))
    out = O.evaluate_outputs(model, 0.0, y, speed_table, load_table, impacts)
    info = dict(converged=bool(res <= tol), residual=res, cage_speed=float(y[c0 + SL.CAGE_OMEGA]),
                slip_rate=float(out["slip_rate"]), nfev=int(nfev))
    info.update(zip(UNKNOWNS, (u0 + sol.x * scale_u).tolist()))
    info["outputs"] = out
    info["reason"] = "" if info["converged"] else \
        f"hybrid Powell and Levenberg-Marquardt ended at residual {res:.2e} (tol {tol:.0e})"
    return _checked(y, info, strict, "steady thrust state")


# ------------------------------------------------------------------ combined load, frozen azimuths
HELD_CAGE_UNKNOWNS = ("ball_x", "ball_r", "pocket_offset", "ball_w_x", "ball_w_r", "ball_w_t")


def _newton(residual, n: int, tol: float, max_iter: int = 60, h: float = 1e-3):
    """(v, f, iterations, nfev): damped Newton on residual(v) = 0 from v = 0, Jacobian by central
    differences of step h (the unknowns are scaled so that 1 is a meaningful change), Armijo
    backtracking on |f|; where the Newton direction does not decrease |f| (a kink of the piecewise
    pocket or traction law between the iterate and the root) a Levenberg–Marquardt step
    (J^T J + mu·diag(J^T J)) dv = −J^T f with growing mu. Used where MINPACK's hybrid method stalls
    (the combined-load state below: hybr ends at a residual of 2e-2 there)."""
    v = np.zeros(n)
    f = residual(v)
    nfev = 1
    jac = np.empty((n, n))
    step = np.zeros(n)
    for it in range(1, max_iter + 1):
        for k in range(n):
            step[k] = h
            jac[:, k] = (residual(v + step) - residual(v - step)) / (2.0 * h)
            step[k] = 0.0
        nfev += 2 * n
        norm0 = np.linalg.norm(f)
        dv = np.linalg.lstsq(jac, -f, rcond=None)[0]
        lam, accepted = 1.0, False
        while lam >= 1e-3:
            f_try = residual(v + lam * dv)
            nfev += 1
            if np.linalg.norm(f_try) < (1.0 - 1e-4 * lam) * norm0:
                accepted = True
                break
            lam *= 0.5
        if not accepted:
            jtj, jtf = jac.T @ jac, jac.T @ f
            d = np.diag(jtj).copy() + 1e-12
            for mu in 10.0 ** np.arange(-4, 7):
                dv = np.linalg.solve(jtj + mu * np.diag(d), -jtf)
                lam = 1.0
                f_try = residual(v + dv)
                nfev += 1
                if np.linalg.norm(f_try) < norm0:
                    accepted = True
                    break
        if not accepted:
            return v, f, it, nfev
        v, f = v + lam * dv, f_try
        if np.max(np.abs(f)) <= tol:
            return v, f, it, nfev
    return v, f, max_iter, nfev


def steady_held_cage_state(model, speed_rad_s: float, load, phase: float = 0.0, tol: float = 1e-9,
                           continuation: bool = True, strict: bool = True) -> tuple[np.ndarray, dict]:
    """(y, info): the frozen-azimuth equilibrium of the bearing under a combined load with the cage
    held off-centre in its guide film.

    The balls are frozen at their azimuths psi_j = phase + 2·pi·j/Z + pocket_offset_j and every
    acceleration of `flexbearing.multibody.dynamics.rhs` is set to zero:

        per ball j (6Z):  x'' = r'' = psi'' = 0,  dw/dt = 0 (3)    unknowns x, r, pocket_offset, w (3)
        cage (6):         translations'' = 0, omega_c' = 0, tilts'' = 0
                          unknowns: centre (x, y, z), tilts, omega_c (= every ball's orbit speed)
        inner ring (5):   translations'' = tilts'' = 0              unknowns: its 5 displacements

    6Z + 11 equations: each ball's pocket force is what its traction, drag and inertia leave over,
    the cage centre moves until the guide-land film force balances the resultant of the pocket
    forces (F_land + sum_j F_pocket,j = 0) and the cage speed until their torque balances the land
    and churning drag. This is Harris's skidding analysis (J. Lubr. Technol. 93(1):17–24, 1971,
    written for a thrust load, where all balls are alike: `steady_thrust_state`) with per-ball
    unknowns, made with the dynamics' own force models; it is the state in which
    `flexbearing.analysis.cage_motion` reports a cage as "held".

    Approximation: the balls' states are taken as functions of the azimuth that do not lag behind
    the load, i.e. d/dt of a ball's pocket offset and spin along its orbit is neglected. Measured
    against the dynamics integrated from this state (paper bearing, 14,000 rpm, Fr 4 kN, rigid cage;
    benchmarks/held_cage_mechanism.py, Fa 45–65 kN): the mean pocket force agrees within 7 %, the
    first azimuthal harmonic of the pocket force lags the frozen one by 42–56° with 74–97 % of its
    amplitude, so the cage's film force is 25–31 % smaller and turned by about 50°.

    load = (Fx, Fy, Fz) on the inner ring, N. phase: azimuth of pocket 0 (rad, from +Y to +Z); the
    solution varies with it at the ball-pass period only. Rigid cage only. info: converged,
    residual (max scaled residual, N per ball relative to the axial load per ball), iterations,
    nfev, cage_speed, cage_centre (x, y, z, m), cage_eccentricity_ratio, cage_land_force (y, z, N),
    pocket_resultant (x, y, z, N, on the cage), pocket_offset (Z,), outputs (evaluate_outputs),
    reason (why it failed; empty when converged). strict (default): a solve without a root raises
    SteadyNotConverged (the (y, info) it ended with attached); strict=False returns it.
    """
    load = np.asarray(load, dtype=float)
    if load.shape != (3,):
        raise InputError(f"steady.load = {load.tolist()}: give (Fx, Fy, Fz) in N")
    require_range("steady.speed_rad_s", speed_rad_s, 0.0, 1e5, lo_open=True, unit="rad/s")
    require_range("steady.axial_load", abs(load[0]), 0.0, 1e7, lo_open=True, unit="N")
    for name, v in zip(("Fy", "Fz"), load[1:]):
        require_range(f"steady.load {name}", v, -1e7, 1e7, unit="N")
    require_range("steady.phase", phase, -2 * math.pi, 2 * math.pi, unit="rad")
    if model.n_modes != 0:
        raise InputError(f"model.n_modes = {model.n_modes}: the held-cage state is for a rigid cage "
                         "(build the model with n_modes = 0)")
    try:
        y, info = _held_cage_solve(model, speed_rad_s, load, phase, tol)
    except InputError as e:             # the quasi-static start itself has no solution
        if not continuation:
            raise
        y, info = None, dict(converged=False, residual=math.inf, reason=f"no quasi-static start: {e}")
    if info["converged"] or not continuation:
        return _checked(y, info, strict, "held-cage state")
    y, info = _held_cage_continuation(model, speed_rad_s, load, phase, tol, (y, info))
    if not info["converged"]:
        # no root on the branch followed: other branches (deflated Newton from physical starts)
        y, info = _deflated_root_search(model, speed_rad_s, load, phase, tol, y, info)
        if info["converged"]:
            return _checked(y, info, strict, "held-cage state")
    info = _with_hold_check(model, speed_rad_s, load, y, info)
    if not info["converged"]:
        # no root found at all: the running state as the dynamics' settled mean
        y, info = _held_cage_settled(model, speed_rad_s, load, info)
    return _checked(y, info, strict, "held-cage state")


# the last attempt where the continuation found no held-cage state (_deflated_root_search): at most this
# many Newton iterations per start and this much CPU in all (measured on the uncertainty study's six
# failures: 53-55 starts, 44-48 CPU-s)
ROOT_SEARCH_ITERATIONS = 30
ROOT_SEARCH_CPU_S = 60.0


def _deflated_root_search(model, speed_rad_s: float, load: np.ndarray, phase: float, tol: float, y, info: dict):
    """(y, info): where the continuation ended without a root (a fold, or no thrust root), deflated Newton
    (flexbearing.multibody.deflation; Farrell, Birkisson & Funke 2015) on the held-cage equations at the
    full load from the branch's last root, the direct solve's end, the dynamics 30 ms from the last root
    and the grid of physical starts (flexbearing.multibody.steady_search_starts: cage speed 0.05-0.8 of
    the inner ring's, spins by either race's rolling law, pocket offsets on either wall), scaled about the
    last root (else the direct solve's end). Each root found (cage speed in (0, omega_i]) is solved again
    from itself and checked in the dynamics (steady_hold); the first whose cage stays held is returned
    (else the first found), converged, with info["root_search"] (starts, roots, cpu_s) and the hold check.
    Where none is found the failure is returned with info["root_search"] and its reason extended."""
    if info.get("unknowns") is None:
        return y, info
    t0 = time.process_time()
    u_ref = np.asarray(info["branch_last_root"][1] if "branch_last_root" in info else info["unknowns"], dtype=float)
    starts = ([u_ref] if "branch_last_root" in info else []) + [np.asarray(info["unknowns"], dtype=float)]
    hold = info.get("cage_hold")
    if hold is not None and hold.end_state is not None:
        starts.append(unknowns_of_state(model, hold.end_state, phase))
    starts += physical_starts(model, speed_rad_s, u_ref)
    residual, _, scale_u = _held_cage_equations(model, speed_rad_s, load, phase, u_ref)
    nb = 6 * model.n_balls
    search = deflated_search(residual, [(u - u_ref) / scale_u for u in starts], tol=tol,
                             max_iter=ROOT_SEARCH_ITERATIONS, cpu_budget_s=ROOT_SEARCH_CPU_S,
                             accept=lambda v: 0.0 < u_ref[nb] + v[nb] * scale_u[nb] <= speed_rad_s)
    found = []
    for v in search.roots:
        y_r, info_r = _held_cage_solve(model, speed_rad_s, load, phase, tol, start=u_ref + v * scale_u)
        if info_r["converged"]:
            check = cage_hold_check(model, speed_rad_s, load, y_r)
            info_r.update(cage_hold=check, held=check.held)
            found.append((y_r, info_r))
    summary = dict(starts=search.starts_tried, roots=[(r[1]["cage_speed"], r[1]["held"]) for r in found],
                   cpu_s=time.process_time() - t0)
    what = (f"deflated Newton from {search.starts_tried} starts over omega_c/omega_i {START_FRACTIONS[0]}-"
            f"{START_FRACTIONS[-1]} (and the branch's and the dynamics' states)")
    if not found:
        info.update(root_search=summary, reason=f"{info['reason']}; {what} found no other root "
                                                f"({summary['cpu_s']:.0f} CPU-s)")
        return y, info
    y_r, info_r = next((r for r in found if r[1]["held"]), found[0])
    info_r.update(root_search=summary, failed_continuation=info["reason"], continuation=info.get("continuation", []),
                  failed_verdict=info.get("verdict"), turning_point=info.get("turning_point"),
                  reason="" if info_r["held"] else
                  f"converged to a held-cage root, but {info_r['cage_hold'].describe()}: the equations have this "
                  "root, the bearing need not run in it (another root may exist)")
    info_r["root_search_found"] = (f"{what} found {len(found)} root(s) at the full load where the continuation "
                                   f"from the symmetric thrust state found none")
    return y_r, info_r


def _with_hold_check(model, speed_rad_s: float, load: np.ndarray, y, info: dict) -> dict:
    """info with info["cage_hold"] (steady_hold.cage_hold_check: the dynamics from the root, about 1 CPU-s)
    for a root the continuation found. Why only there: the continuation's root depends on its path (an
    uncertainty-study run reached slips of −5.1 % and +52 % on two versions of it, both roots; the
    cage stays held at the second only), the direct solve's does not. A root whose cage does not stay
    held is still returned (converged), with info["held"] = False and the reason saying so."""
    if not info["converged"] or y is None:
        return info
    check = cage_hold_check(model, speed_rad_s, load, y)
    info.update(cage_hold=check, held=check.held)
    if not check.held:
        info["reason"] = (f"converged to a held-cage root, but {check.describe()}: the equations have this root, "
                          "the bearing need not run in it (another root may exist)")
    return info


# what a run that failed is (info["verdict"], the reason's first words; steady_existence): converged; no
# steady state (the traction–drag bound proves none exists); fold (a certified turning point: no
# held-cage state on the branch followed, another branch not excluded); not converged (nothing proved)
VERDICT_CONVERGED, VERDICT_NO_STEADY_STATE, VERDICT_FOLD, VERDICT_NOT_CONVERGED = (
    "converged", "no steady state", "fold", "not converged")
# no held-cage root, but the dynamics settle to a stationary running state: its mean (steady_mean)
VERDICT_SETTLED_MEAN = "settled mean"


def _held_cage_settled(model, speed_rad_s: float, load: np.ndarray, info: dict):
    """(y, info) where the held-cage equations have no root on the path followed: the settled mean of
    the dynamics (steady_mean.settled_mean), started from the end of the last root's hold check (the
    dynamics 30 ms from it at the full load), else from the quasi-static state. Settled: converged,
    verdict VERDICT_SETTLED_MEAN, info["kind"] = "settled mean", the mean slip and cage speed with
    their confidence half widths in info["settled_mean"], info["outputs"] a snapshot of the running
    state (its last sample) with "slip_rate" the mean, residual nan (no root), and the failure's
    reason kept in info["failed_reason"]. Not settled within steady_mean.MAX_TIME: the failure as it
    was, its reason extended by what the dynamics did. Runs with a root never come here."""
    hold = info.get("cage_hold")
    if hold is not None and hold.end_state is not None and not hold.note:
        start, where = hold.end_state, "from the end of the last root's hold check"
    else:
        try:
            start = initial_state(model, speed_rad_s, 0.0, 0.0, load=tuple(load))
        except InputError as e:
            info["reason"] += f"; no settled mean either: no quasi-static start to integrate from ({e})"
            return None, info
        where = "from the quasi-static state"
    sm = settled_mean(model, speed_rad_s, load, start)
    info["settled_mean"] = sm
    if not sm.settled:
        info["reason"] += f"; the dynamics integrated {where}: {sm.describe()}"
        return sm.end_state, info
    sp, ld = np.array([[0.0, speed_rad_s]]), np.array([[0.0, load[0], load[1], load[2]]])
    out = O.evaluate_outputs(model, 0.0, sm.end_state, sp, ld, np.zeros((0, 6)))
    out["slip_rate"] = np.float64(sm.slip_rate)
    c0 = M.state_layout(model)["cage"]
    info.update(converged=True, kind="settled mean", verdict=VERDICT_SETTLED_MEAN, held=sm.held, residual=math.nan,
                cage_speed=sm.cage_speed, cage_centre=sm.end_state[c0 + SL.CAGE_X:c0 + SL.CAGE_Z + 1].copy(),
                cage_eccentricity_ratio=sm.eccentricity_mean, cage_land_force=out["cage_land_force"].copy(),
                pocket_resultant=out["pocket_force_on_cage"].sum(axis=0), outputs=out, failed_reason=info["reason"],
                reason=f"{VERDICT_SETTLED_MEAN}: no held-cage root ({info.get('verdict', VERDICT_NOT_CONVERGED)}); "
                       f"the running state is the dynamics' mean, integrated {where}: {sm.describe()}")
    return sm.end_state, info

# the continuation in the load that breaks the balls' symmetry: first step, smallest step
CONTINUATION_FIRST_STEP = 0.25
CONTINUATION_MIN_STEP = 1.0 / 1024.0
# condition number of the held-cage Jacobian (scaled unknowns and equations) read as singular: the
# damped Newton stalls beyond about 1e8 (the non-root stationary point of |F| measured at 7e8,
# _held_cage_continuation's docstring); a tenfold rise between the last two roots also marks the
# approach to a fold (the smallest singular value goes to zero like sqrt(lambda* - lambda))
FOLD_CONDITION = 1e8


def _held_cage_continuation(model, speed_rad_s: float, load: np.ndarray, phase: float, tol: float,
                            direct: tuple) -> tuple[np.ndarray, dict]:
    """Natural-parameter continuation (Allgower & Georg, *Introduction to Numerical Continuation
    Methods*, SIAM 2003, ch. 1–2) from the symmetric thrust state to the combined load with weight.

    lambda scales what makes the balls differ by azimuth: the radial load (Fy, Fz) and gravity.
    At lambda = 0 all balls are alike and the state is `steady_thrust_state`'s (9 unknowns,
    MINPACK's hybrid method: far more robust than a Newton on all 6Z + 11), copied to every ball;
    where that fails, the held-cage solve of the thrust alone from the quasi-static balls. Then
    lambda rises to 1, each solve starting from the secant predictor through the last two roots
    (then, where that fails, from the last root itself); a failed step is halved (down to
    CONTINUATION_MIN_STEP = 1/1024; 1/64 stopped the paper steady case at the design clearance at
    lambda = 0.70 and 1/256 at 0.972, where the step to 0.978 fails and the one to 0.975 converges in
    4 iterations, issue 42), a converged one enlarged by 1.5. Where the halving ends
    (a contact law switching inside the step: the residual jumps there), it jumps over the switch
    from the last root: to lambda = 1, +0.25, +0.1.

    Why: from the quasi-static start the damped Newton of `_held_cage_solve` can end on a
    near-singular stationary point of |F| that is not a root (measured on a slip-rate case: the
    Jacobian's condition ~7e8 there, the residual 2.7e-2 and smooth along the Newton direction);
    following the branch from the symmetric state keeps each iterate near it.
    info["continuation"]: the lambdas solved; info["reason"]: why a run that fails failed."""
    y_direct, direct = direct
    g = model.p[M.P_GRAV]
    axial = np.array([load[0], 0.0, 0.0])
    radial = np.array([0.0, load[1], load[2]])

    def at(lam, start, conditioning=False):
        p = model.p.copy()
        p[M.P_GRAV] = lam * g
        return _held_cage_solve(model._replace(p=p), speed_rad_s, axial + lam * radial, phase, tol, start=start,
                                conditioning=conditioning)

    y, info = _thrust_root(model, speed_rad_s, load[0], phase, at)
    if not info["converged"]:
        y, info = _failed(y_direct, direct, y, info, f"no root from the quasi-static start ({direct['reason']}) nor of the "
                                  f"symmetric thrust state without weight (residual {info['residual']:.2e}), nor from "
                                  f"the thrust-only dynamics settled for {SETTLE_CHUNK * SETTLE_CHUNKS:.2f} s: no fixed "
                                  "point in reach at this speed and thrust")
        return _with_bound_verdict(model, y, info)
    lam, step, path = 0.0, CONTINUATION_FIRST_STEP, [0.0]
    previous = None                       # (lambda, unknowns) of the root before the last one
    roots = [(0.0, info["unknowns"])]     # every root of the path

    def predict(target):
        """[the secant predictor at lambda = target] where there are two roots, else []."""
        if previous is None:
            return []
        return [info["unknowns"] + (target - lam) / (lam - previous[0]) * (info["unknowns"] - previous[1])]
    while lam < 1.0:
        trial = min(1.0, lam + step)
        # the secant predictor (Allgower & Georg 2003, §2.2: the branch extrapolated linearly
        # through the last two roots), then the last root itself
        for start in predict(trial) + [info["unknowns"]]:
            y_t, info_t = at(trial, start)
            if info_t["converged"]:
                break
        if info_t["converged"]:
            previous = (lam, info["unknowns"])
            lam, y, info = trial, y_t, info_t
            path.append(lam)
            roots.append((lam, info["unknowns"]))
            step *= 1.5
            continue
        step *= 0.5
        res_trial, lam_fail = info_t["residual"], trial
        if step < CONTINUATION_MIN_STEP:
            # a ball entering or leaving the load zone, or the cage reaching its rim, switches a
            # contact law inside the step: the residual jumps there and no root lies on the switch
            # itself, but the branch goes on beyond it. Jump over it from the last root.
            jump = _jump_over_switch(at, predict, lam, info["unknowns"])
            if jump is not None:
                previous = None
                lam, y, info = jump
                path.append(lam)
                roots.append((lam, info["unknowns"]))
                step = CONTINUATION_FIRST_STEP
                continue
            # the full load from the earlier roots of the path: where this branch folds, another one
            # may carry the state at lambda = 1 (measured: a sample run whose branch folds at 0.88
            # has a root at 1 reached from an earlier root)
            for lam_k, u_k in reversed(roots[:-1]):
                y_t, info_t = at(1.0, u_k)
                if info_t["converged"]:
                    path.append(1.0)
                    info_t["continuation"] = path
                    return y_t, info_t
            y_t, info_t = _arclength_past_stop(model, speed_rad_s, load, phase, tol, at, (lam, info), previous, path)
            if info_t["converged"]:
                return y_t, info_t
            return _stopped(model, speed_rad_s, load, phase, at, (lam, y, info), previous, (lam_fail, res_trial), path,
                            (y_direct, direct), info_t["arclength"])
    info["continuation"] = path
    return y, info


def _stopped(model, speed_rad_s: float, load: np.ndarray, phase: float, at, last: tuple, previous, failed: tuple,
             path: list, direct: tuple, arclength=None):
    """(y, info) where the held-cage continuation stopped: at its last root last = (lambda, y, info),
    the root before it `previous`, the first lambda that failed and its residual `failed`; the
    reason says fold or kink (_fold_or_kink) and the verdict rests on the second-order turning-point
    test at the last root (steady_existence, item 1), made only after the continuation has stopped."""
    lam, y, info = last
    lam_fail, res_trial = failed
    fold, what = _fold_or_kink(at, lam, info, previous, lam_fail)
    t0 = time.process_time()
    tp = _branch_turning_point(model, speed_rad_s, load, phase, lam, info["unknowns"])
    cpu = time.process_time() - t0
    y, info = _failed(*direct, y, info, f"the continuation from the symmetric thrust state stopped at lambda = {lam:.4f} "
                                        f"of the radial load and weight (residual {res_trial:.2e} at {lam_fail:.4f}): {what}")
    # the branch followed by pseudo-arclength round a turning point back below lambda = 0: every root
    # it passed lies below the full load, so this branch does not reach it (whatever the local test says)
    returned = arclength is not None and bool(arclength.turning_points) and (arclength.lam < 0.0 or arclength.closed)
    verdict = VERDICT_FOLD if tp.certified or returned else VERDICT_NOT_CONVERGED
    beyond = "" if arclength is None else arclength.describe()
    hold = cage_hold_check(model, speed_rad_s, load, last[1])   # the last root, at the full load
    if returned:
        beyond += (" without reaching the full load: the branch through the symmetric thrust state has no held-cage "
                   "state at lambda = 1 between its two ends at lambda = 0 (a branch not connected to it is not "
                   "excluded)" if not arclength.closed else " without reaching the full load: the branch through the "
                   "last root is a closed curve below lambda = 1 (a branch not connected to it is not excluded)")
    # the evidence the verdict rests on first: the local test where it certifies, else the branch's return
    if tp.certified or not returned:
        head, tail = tp.describe(), (f"; beyond it, {beyond}" if beyond else "")
    else:
        head, tail = f"{beyond}; {tp.describe()}", ""
    info.update(fold=bool(fold), continuation=path, turning_point=tp, verdict=verdict, verdict_cpu_s=cpu,
                arclength=arclength, cage_hold=hold, branch_last_root=(lam, np.array(last[2]["unknowns"])),
                reason=f"{verdict}: {head}; {info['reason']}{tail}; at the full load from the last root, "
                       f"{hold.describe()}")
    return y, info


# pseudo-arclength continuation past the natural continuation's stop (steady_arclength): its first
# step (scaled unknowns and lambda), its smallest step, the most points it takes and its CPU budget
# (a fold run of the natural continuation costs about 60 CPU-s; a point of the arclength path about 0.06)
ARCLENGTH_FIRST_STEP = 0.05
ARCLENGTH_MIN_STEP = 1e-4
ARCLENGTH_MAX_STEPS = 1000
ARCLENGTH_CPU_S = 60.0


def _arclength_past_stop(model, speed_rad_s: float, load: np.ndarray, phase: float, tol: float, at, last: tuple,
                         previous, path: list):
    """(y, info) at the full load where the branch, followed around the turning point (or kink) at which
    the natural continuation stopped by pseudo-arclength continuation in (unknowns, lambda)
    (steady_arclength; Keller 1977), reaches lambda = 1 and the held-cage solve there converges from
    the point it found; else (None, {converged: False, arclength: what it found}). last = (lambda,
    info) of the last root, previous = (lambda, unknowns) of the one before it (the direction of
    travel) or None (then lambda increasing)."""
    lam, info = last
    u_k = np.asarray(info["unknowns"], dtype=float)
    residual = _branch_residual(model, speed_rad_s, load, phase, u_k)
    scale_u = _held_cage_equations(model, speed_rad_s, load, phase, u_k)[2]
    n = u_k.size
    direction = np.zeros(n + 1)
    direction[n] = 1.0
    if previous is not None:
        direction[:n], direction[n] = (u_k - previous[1]) / scale_u, lam - previous[0]
    arc = pseudo_arclength(residual, np.zeros(n), lam, direction, ds=ARCLENGTH_FIRST_STEP, ds_min=ARCLENGTH_MIN_STEP,
                           max_steps=ARCLENGTH_MAX_STEPS, tol=tol, cpu_budget_s=ARCLENGTH_CPU_S)
    if arc.reached:
        y, info_t = at(1.0, u_k + arc.v * scale_u)
        if info_t["converged"]:
            info_t.update(continuation=path + arc.lam_path[1:], arclength=arc)
            return y, info_t
        arc.stop = f"the held-cage solve at lambda = 1 from its point ended at residual {info_t['residual']:.2e}"
        arc.reached = False
    return None, dict(converged=False, arclength=arc)


def _with_bound_verdict(model, y, info: dict):
    """(y, info) of a run with no root at all, its verdict from the traction–drag bound
    (steady_existence, item 2) at the end state: "no steady state" where the bound proves it, else
    "not converged"; info["traction_drag_bound"] the bound."""
    t0 = time.process_time()
    out = info["outputs"]
    p = model.p
    r_out = 0.5 * (p[M.P_DM] + p[M.P_DW])           # the outer race's contact radius bounds every lever
    if model.flags[M.F_TRACTION_LAW] == TRACTION_EHL:
        mu_max = TR.ehl_traction_coefficient_bound(model.traction_table)
    else:                                          # no bound of that law's coefficient is derived here
        mu_max = math.inf
    q = np.asarray(out["contact_load"])
    drag = abs(float(np.ravel(out["cage_land_torque"])[0])) + \
        float(np.sum(np.abs(out["churning_drag"]))) * 0.5 * p[M.P_DM]
    bound = traction_drag_bound(mu_max, q[:, 1:], q[:, 0], r_out, drag)
    verdict = VERDICT_NO_STEADY_STATE if bound.proves_no_steady_state else VERDICT_NOT_CONVERGED
    info.update(traction_drag_bound=bound, verdict=verdict, verdict_cpu_s=time.process_time() - t0,
                reason=f"{verdict}: {bound.describe()}; {info['reason']}")
    return y, info


def _branch_turning_point(model, speed_rad_s: float, load: np.ndarray, phase: float, lam: float, unknowns):
    """steady_existence.turning_point of the held-cage branch (lambda scales the radial load and the
    weight, _held_cage_continuation) at its root `unknowns` at lambda = lam."""
    return turning_point(_branch_residual(model, speed_rad_s, load, phase, unknowns), lam, 6 * model.n_balls + 11)


def _branch_residual(model, speed_rad_s: float, load: np.ndarray, phase: float, unknowns):
    """residual(v, lam): the held-cage equations (_held_cage_equations, about the unknowns `unknowns`,
    v scaled as there) along the continuation's branch, lambda scaling the radial load and the weight
    (_held_cage_continuation). The equations of the last few lambdas are kept: building them copies
    the model, and the turning-point test and the arclength corrector call one lambda many times."""
    g = model.p[M.P_GRAV]
    axial = np.array([load[0], 0.0, 0.0])
    radial = np.array([0.0, load[1], load[2]])
    u0 = np.asarray(unknowns, dtype=float)
    equations = {}

    def residual(v, lam):
        if lam not in equations:
            if len(equations) > 4:
                equations.clear()
            p = model.p.copy()
            p[M.P_GRAV] = lam * g
            equations[lam] = _held_cage_equations(model._replace(p=p), speed_rad_s, axial + lam * radial, phase, u0)[0]
        return equations[lam](v)
    return residual


def _failed(y_direct, direct: dict, y, info: dict, reason: str):
    """The direct solve's end (or, where it had no start, the continuation's), not converged, with why."""
    if y_direct is not None:
        y, info = y_direct, direct
    info.update(converged=False, reason=reason)
    return y, info


def _jump_over_switch(at, predict, lam: float, last_root):
    """(lambda, y, info) of the first root found beyond a contact law's switch that the halved steps
    could not cross: at lambda = 1, +0.25, +0.1, +0.02, +0.005 from lam (the farthest first), each
    from the secant predictor `predict(lambda)`, then from the last root; None where none converges."""
    for far in sorted({1.0, min(1.0, lam + 0.25), min(1.0, lam + 0.1), min(1.0, lam + 0.02),
                       min(1.0, lam + 0.005)}, reverse=True):
        for start in predict(far) + [last_root]:
            y_t, info_t = at(far, start)
            if info_t["converged"]:
                return far, y_t, info_t
    return None


def _fold_or_kink(at, lam: float, info: dict, previous, lam_fail: float) -> tuple[bool, str]:
    """(fold?, why in words) where the held-cage continuation stopped at lambda = lam (its last
    root's `info`, the root before it `previous` = (lambda, unknowns) or None, the first lambda that
    failed `lam_fail`; `at(lambda, start, conditioning)` solves there)."""
    # the branch's conditioning at the last two roots tells a fold (a limit point: the
    # Jacobian turns singular as lambda approaches it, beyond it this branch has no root) from
    # a switch of a contact law (a kink: the Jacobian stays regular)
    c_last = at(lam, info["unknowns"], conditioning=True)[1]["jacobian_condition"]
    c_prev = at(previous[0], previous[1], conditioning=True)[1]["jacobian_condition"] \
        if previous is not None else math.nan
    # near a fold (a simple limit point) the smallest singular value goes to zero like
    # sqrt(lambda* - lambda) (Allgower & Georg 2003, §2.3), so the condition c obeys
    # c1²·(lambda* - l1) = c2²·(lambda* - l2): lambda* from the last two roots; a fold where it
    # lies between the last root and the first lambda that failed
    lam_star = math.nan
    if previous is not None and c_last > c_prev > 0.0:
        lam_star = (c_last ** 2 * lam - c_prev ** 2 * previous[0]) / (c_last ** 2 - c_prev ** 2)
    fold = c_last > FOLD_CONDITION or lam <= lam_star <= lam_fail
    what = (f"a fold: the Jacobian's condition number rises from {c_prev:.2e} at lambda = "
            f"{previous[0] if previous is not None else math.nan:.4f} to {c_last:.2e} at {lam:.4f}, as "
            f"1/sqrt(lambda* - lambda) with lambda* = {lam_star:.4f} (no root at {lam_fail:.4f}): the branch "
            "of held-cage states ends there, and no held-cage state at the full load was reached from any of "
            "its roots (the cage is not held there: integrate the dynamics)") if fold else \
        (f"the Jacobian stays regular there (condition {c_last:.2e}): a contact law switching that the "
         "steps could not cross (a ball leaving the load zone, the cage reaching its rim, or a ball "
         "pressed past its pocket clearance, where the pocket law's stiffness drops from Kc to 0)")
    return fold, what


def _thrust_root(model, speed_rad_s: float, axial_load: float, phase: float, at) -> tuple[np.ndarray, dict]:
    """(y, info) of the held-cage state at lambda = 0 (thrust alone, no weight; `at(0.0, start)`
    solves it, _held_cage_continuation): from the symmetric thrust state (_thrust_state_by_speed),
    else from the quasi-static balls, else from the symmetric thrust state found after settling the
    thrust-only dynamics (_thrust_state_from_dynamics); the last tried where none converges."""
    y, info = at(0.0, _symmetric_start(model, speed_rad_s, axial_load, phase))
    if not info["converged"]:
        y, info = at(0.0, None)
    if info["converged"]:
        return y, info
    p = model.p.copy()
    p[M.P_GRAV] = 0.0
    s = _thrust_state_from_dynamics(model._replace(p=p), speed_rad_s, axial_load)
    if s is None:
        return y, info
    y_s, info_s = at(0.0, _symmetric_unknowns(model, s))
    info_s["settled_time"] = s["settled_time"]
    return (y_s, info_s) if info_s["converged"] else (y, info)


# the last fallback for the thrust state (_thrust_state_from_dynamics): the thrust-only dynamics
# integrated in chunks of SETTLE_CHUNK s of simulated time, the thrust state tried after each, for
# at most SETTLE_CHUNKS chunks. The ball spin's gyroscopic swing about its axis (period ~13 ms,
# amplitude falling ~30 % a half period, measured on the cold-oil study run 47/11) has to die to a
# few per cent before the hybrid method converges: 20-40 ms there; the integration costs ~15 CPU-s
# per simulated second (dopri5, the dynamics' own step control)
SETTLE_CHUNK = 0.01
SETTLE_CHUNKS = 20


def _thrust_state_from_dynamics(model, speed_rad_s: float, axial_load: float) -> dict | None:
    """steady_thrust_state's info (plus settled_time, s) started from the thrust-only dynamics
    (`model` without weight) integrated from the quasi-static state (flexbearing.multibody.steady_settle:
    the real flow as pseudo-time, Kelley & Keyes 1998), every chunk's end state symmetrised (ball 0's
    x, r, orbit speed and spin, which steady_thrust_state reads as every ball's, replaced by the mean
    over the balls, alike under a pure thrust without weight); None where no chunk's start converges or the integration stops."""
    from flexbearing.multibody.integrator import SimulationUnstable, Workspace, advance

    z = model.n_balls
    speed_table = np.array([[0.0, speed_rad_s]])
    load_table = np.array([[0.0, axial_load, 0.0, 0.0]])
    impacts = np.zeros((0, 6))
    ws = Workspace(model, "dopri5")
    h = [1e-6]

    def flow(y, t0, t1):
        y, _, h[0], _, _ = advance(model, y, t0, t1, speed_table, load_table, impacts, ws=ws, h=h[0])
        return y

    def solve(y):
        ys = y.copy()
        mean = y[:SL.ball_offset(z)].reshape(z, SL.BALL_STATE).mean(axis=0)
        for k in (SL.BALL_X, SL.BALL_R, SL.BALL_PSI_DOT, SL.BALL_W_X, SL.BALL_W_R, SL.BALL_W_T):
            ys[k] = mean[k]
        s = steady_thrust_state(model, speed_rad_s, axial_load, y_start=ys, strict=False)[1]
        return s if s["converged"] else None
    try:
        found = settle_then_solve(flow, solve, initial_state(model, speed_rad_s, axial_load, 0.0), SETTLE_CHUNK,
                                  SETTLE_CHUNKS)
    except SimulationUnstable:
        return None
    if found.root is None:
        return None
    return dict(found.root, settled_time=found.settled_time)


def _symmetric_start(model, speed_rad_s: float, axial_load: float, phase: float) -> np.ndarray | None:
    """The unknowns of `_held_cage_solve` from steady_thrust_state's solution without weight (every
    ball alike, the inner ring and the cage displaced axially only), or None where it has none."""
    p = model.p.copy()
    p[M.P_GRAV] = 0.0
    s = _thrust_state_by_speed(model._replace(p=p), speed_rad_s, axial_load)
    if s is None:
        return None
    return _symmetric_unknowns(model, s)


def _symmetric_unknowns(model, s: dict) -> np.ndarray:
    """The unknowns of `_held_cage_solve` from steady_thrust_state's info s (every ball alike)."""
    z = model.n_balls
    nb = 6 * z
    u = np.zeros(nb + 11)
    u[:nb] = np.tile([s["ball_x"], s["ball_r"], s["pocket_offset"], s["ball_w_x"], s["ball_w_r"], s["ball_w_t"]], z)
    u[nb] = s["orbit_speed"]
    u[nb + 1] = s["ring_x"]
    u[nb + 6] = s["cage_x"]
    return u


def _thrust_state_by_speed(model, speed_rad_s: float, axial_load: float) -> dict | None:
    """steady_thrust_state's info at speed_rad_s, by natural-parameter continuation in the speed
    where the direct solve fails (Allgower & Georg 2003, ch. 1–2): the state at a lower speed
    (1/2, 1/4, 1/8 of it: less centrifugal force, the contact angles nearer the quasi-static ones)
    is followed up to the full speed, each solve starting from the previous state, the step
    halved on failure (down to CONTINUATION_MIN_STEP) and enlarged by 1.5 on success. None where
    no speed fraction converges or the branch ends before the full speed."""
    y, s = steady_thrust_state(model, speed_rad_s, axial_load, strict=False)
    if s["converged"]:
        return s
    for mu in (0.5, 0.25, 0.125):
        y, s = steady_thrust_state(model, mu * speed_rad_s, axial_load, strict=False)
        if s["converged"]:
            break
    else:
        return None
    step = 0.5 * mu
    while mu < 1.0:
        trial = min(1.0, mu + step)
        y_t, s_t = steady_thrust_state(model, trial * speed_rad_s, axial_load, y_start=y, strict=False)
        if s_t["converged"]:
            mu, y, s = trial, y_t, s_t
            step *= 1.5
            continue
        step *= 0.5
        if step < CONTINUATION_MIN_STEP:
            return None
    return s


def _held_cage_solve(model, speed_rad_s: float, load: np.ndarray, phase: float, tol: float,
                     start: np.ndarray | None = None, conditioning: bool = False) -> tuple[np.ndarray, dict]:
    """One damped-Newton solve of the held-cage equations (steady_held_cage_state's docstring) from
    the quasi-static balls, or from `start` (the unknowns of an earlier solution, info["unknowns"]).
    conditioning: also info["jacobian_condition"], the 2-norm condition number of the scaled
    equations' Jacobian (central differences) at the end point."""
    p = model.p
    z = model.n_balls
    lay = M.state_layout(model)
    r0, c0 = lay["ring"], lay["cage"]
    speed_table = np.array([[0.0, speed_rad_s]])
    load_table = np.array([[0.0, load[0], load[1], load[2]]])
    impacts = np.zeros((0, 6))
    n = 6 * z + 11
    nb = 6 * z
    if start is None:
        # start: the quasi-static balls, each against the driving side of its pocket (as
        # steady_thrust_state), the cage centred axially on the balls so that the pocket walls do
        # not push it sideways from the first iterate
        y0 = initial_state(model, speed_rad_s, 0.0, 0.0, load=tuple(load))
        u0 = np.zeros(n)
        for j in range(z):
            b = y0[SL.ball_offset(j):SL.ball_offset(j) + SL.BALL_STATE]
            u0[6 * j:6 * j + 6] = (b[SL.BALL_X], b[SL.BALL_R], 0.6 * p[M.P_CP] / p[M.P_RCAGE_POCKET], b[SL.BALL_W_X],
                                   b[SL.BALL_W_R], b[SL.BALL_W_T])
        u0[nb] = np.mean(y0[SL.BALL_PSI_DOT:r0:SL.BALL_STATE])
        u0[nb + 1:nb + 6] = y0[r0:r0 + SL.RING_POSITIONS]
        u0[nb + 6] = np.mean(y0[SL.BALL_X:r0:SL.BALL_STATE])
    else:
        u0 = np.array(start, dtype=float)
    residual, state, scale_u = _held_cage_equations(model, speed_rad_s, load, phase, u0)
    v, f, iterations, nfev = _newton(residual, n, tol)
    cond = math.nan
    if conditioning:
        jac = np.empty((n, n))
        for k in range(n):
            e = np.zeros(n)
            e[k] = 1e-3
            jac[:, k] = (residual(v + e) - residual(v - e)) / 2e-3
        sv = np.linalg.svd(jac, compute_uv=False)
        cond = float(sv[0] / sv[-1]) if sv[-1] > 0.0 else math.inf
    y = state(v)
    res = float(np.max(np.abs(f)))
    out = O.evaluate_outputs(model, 0.0, y, speed_table, load_table, impacts)
    info = dict(converged=bool(res <= tol), residual=res, iterations=int(iterations), nfev=int(nfev),
                cage_speed=float(y[c0 + SL.CAGE_OMEGA]), cage_centre=y[c0 + SL.CAGE_X:c0 + SL.CAGE_Z + 1].copy(),
                cage_eccentricity_ratio=float(out["cage_eccentricity_ratio"]),
                cage_land_force=out["cage_land_force"].copy(),
                pocket_resultant=out["pocket_force_on_cage"].sum(axis=0),
                pocket_offset=(u0 + v * scale_u)[2:nb:6].copy(), outputs=out,
                unknowns=u0 + v * scale_u, continuation=[], reason="", jacobian_condition=cond)
    if not info["converged"]:
        info["reason"] = f"damped Newton ended at residual {res:.2e} after {iterations} iterations"
    return y, info


def _held_cage_equations(model, speed_rad_s: float, load: np.ndarray, phase: float, u0: np.ndarray):
    """(residual, state, scale_u) of the held-cage equations (steady_held_cage_state's docstring) about
    the unknowns u0: residual(v) the scaled accelerations at u = u0 + v·scale_u, state(v) the state
    vector there."""
    p = model.p
    z = model.n_balls
    lay = M.state_layout(model)
    r0, c0 = lay["ring"], lay["cage"]
    speed_table = np.array([[0.0, speed_rad_s]])
    load_table = np.array([[0.0, load[0], load[1], load[2]]])
    impacts = np.zeros((0, 6))
    work = D.new_work(model)
    n = 6 * z + 11
    nb = 6 * z
    dydt = np.zeros(lay["n_state"])
    half_dw, half_dm = 0.5 * p[M.P_DW], 0.5 * p[M.P_DM]
    # the scale of a ball's spin: its w_x and w_r (what y0[6], y0[7] hold in the quasi-static start)
    w_ball = np.mean(np.abs(u0[3:nb:6])) + np.mean(np.abs(u0[4:nb:6])) + 1.0
    scale_u = np.empty(n)
    scale_r = np.empty(n)
    scale_u[:nb] = np.tile([1e-6, 1e-6, 1e-4, 1e-3 * w_ball, 1e-3 * w_ball, 1e-3 * w_ball], z)
    scale_r[:nb] = np.tile([p[M.P_MB], p[M.P_MB], p[M.P_MB] * half_dm, p[M.P_IB] / half_dw,
                            p[M.P_IB] / half_dw, p[M.P_IB] / half_dw], z)
    scale_u[nb] = 1e-3 * abs(u0[nb]) + 1e-3
    scale_r[nb] = p[M.P_ICP] / half_dm
    scale_u[nb + 1:] = (1e-6, 1e-6, 1e-6, 1e-5, 1e-5, 1e-6, 1e-6, 1e-6, 1e-5, 1e-5)
    scale_r[nb + 1:] = (p[M.P_MI], p[M.P_MI], p[M.P_MI], p[M.P_IID] / half_dm, p[M.P_IID] / half_dm,
                        p[M.P_MC], p[M.P_MC], p[M.P_MC], p[M.P_ICD] / half_dm, p[M.P_ICD] / half_dm)
    scale_r /= abs(load[0]) / z

    def state(v):
        u = u0 + v * scale_u
        y = np.zeros(lay["n_state"])
        omega_c = u[nb]
        for j in range(z):
            x, r, offset, wx, wr, wt = u[6 * j:6 * j + 6]
            o = SL.ball_offset(j)
            y[o:o + SL.BALL_STATE] = (x, r, phase + 2.0 * math.pi * j / z + offset, 0.0, 0.0, omega_c, wx, wr, wt)
        y[r0:r0 + SL.RING_POSITIONS] = u[nb + 1:nb + 6]
        y[c0:c0 + SL.CAGE_POSITIONS] = (u[nb + 6], u[nb + 7], u[nb + 8], phase, u[nb + 9], u[nb + 10])
        y[c0 + SL.CAGE_OMEGA] = omega_c
        return y

    def residual(v):
        D.rhs(0.0, state(v), dydt, p, model.flags, model.hertz_table, model.traction_table, speed_table,
              load_table, impacts, work, model.cage)
        f = np.empty(n)
        f[:nb] = dydt[:r0].reshape(z, SL.BALL_STATE)[:, SL.BALL_X_DOT:].ravel()
        f[nb] = dydt[c0 + SL.CAGE_OMEGA]
        f[nb + 1:nb + 6] = dydt[r0 + SL.RING_VX:r0 + SL.RING_TILT_Z_DOT + 1]
        f[nb + 6:nb + 9] = dydt[c0 + SL.CAGE_VX:c0 + SL.CAGE_VZ + 1]
        f[nb + 9:nb + 11] = dydt[c0 + SL.CAGE_TILT_Y_DOT:c0 + SL.CAGE_TILT_Z_DOT + 1]
        return scale_r * f
    return residual, state, scale_u
