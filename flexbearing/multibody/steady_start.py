"""The run's initial state from the steady running state ([integrator] start = "steady"), with the
quasi-static start (flexbearing.multibody.initial) as the fallback: `steady_start`, `start_line`.

A run from the quasi-static equilibrium (no friction, pure rolling) spends its first milliseconds
to seconds settling to the skid, cage speed and cage forces its dynamics hold; statistics and a
fatigue duty cycle over that start-up are biased (flexbearing.analysis.settling). Starting from
the steady state of the first phase shortens it where the steady solver finds that state.
"""
from __future__ import annotations

import numpy as np

from flexbearing.multibody import model as M
from flexbearing.multibody import state_layout as SL
from flexbearing.multibody import steady
START_KINDS = ("quasi_static", "steady")     # the scene's [integrator] start


def steady_start(rigid_model, speed_rad_s: float, load, y_quasi_static: np.ndarray) -> tuple[np.ndarray, dict]:
    """(y, info): the run's initial state from the steady running state at the speed and load of
    t = 0, or the quasi-static start y_quasi_static where no steady state is found.

    Solver (flexbearing.multibody.steady, through its public functions): a pure axial load without
    gravity, `steady_thrust_state` (Harris's skidding analysis, every ball alike); otherwise
    `steady_held_cage_state` (every ball at its azimuth, the cage held off-centre in its guide
    film; frozen azimuths, so the start is near the running state but not on it: the dynamics
    still settle, over less than from the quasi-static start). Both are solved on the rigid cage
    (`rigid_model`, the run's bearing, oil and options with n_modes = 0): for a flexible cage the
    balls, rings and cage of y_quasi_static take the steady values, and its modal coordinates, the
    static centrifugal deformation at the quasi-static cage speed (flexbearing.coupling.flexible_cage:
    proportional to the spin squared), are scaled by (omega_steady / omega_quasi_static)².

    Fallback: where the solver reports converged = False or raises (no fixed point in reach, a
    refused load or speed, a non-convergence exception), y is y_quasi_static unchanged and
    info["start"] = "quasi_static" with info["reason"] saying why; the caller prints it.
    info: start ("steady" | "quasi_static"), solver, reason, residual, cage_speed (rad/s), slip_rate."""
    load = np.asarray(load, dtype=float)
    lay = M.state_layout(rigid_model)
    n_rigid = lay["n_state"]
    y_qs = np.asarray(y_quasi_static, dtype=np.float64)
    thrust = load[1] == 0.0 and load[2] == 0.0 and rigid_model.p[M.P_GRAV] == 0.0
    solver = "steady_thrust_state" if thrust else "steady_held_cage_state"
    info = {"start": "quasi_static", "solver": solver, "reason": "", "residual": None, "cage_speed": None,
            "slip_rate": None}
    try:
        if thrust:
            y_s, s = steady.steady_thrust_state(rigid_model, speed_rad_s, float(load[0]))
        else:
            y_s, s = steady.steady_held_cage_state(rigid_model, speed_rad_s, load)
    except Exception as exc:                # InputError, a non-convergence exception, a singular system
        info["reason"] = f"{type(exc).__name__}: {exc}"
        return y_qs, info
    if not s.get("converged", False) or y_s is None or not np.all(np.isfinite(y_s)):
        info["reason"] = s.get("reason") or f"no root (residual {s.get('residual', float('nan')):.2e})"
        return y_qs, info
    y = y_qs.copy()
    y[:n_rigid] = y_s
    c0 = lay["cage"]
    w_qs, w_s = y_qs[c0 + SL.CAGE_OMEGA], y_s[c0 + SL.CAGE_OMEGA]
    if len(y) > n_rigid and w_qs != 0.0:    # a flexible cage: its centrifugal deformation at the new spin
        n_modes = (len(y) - n_rigid) // 2
        y[n_rigid:n_rigid + n_modes] *= (w_s / w_qs) ** 2
    info.update(start="steady", residual=float(s["residual"]), cage_speed=float(s["cage_speed"]),
                slip_rate=float(s["outputs"]["slip_rate"]) if "outputs" in s else s.get("slip_rate"))
    return y, info


def start_line(info: dict) -> str:
    """The one line a run prints about its start (steady_start's info)."""
    if info["start"] == "steady":
        slip = "" if info["slip_rate"] is None else f", slip {100 * float(info['slip_rate']):.3g} %"
        return (f"start: steady state of the first phase ({info['solver']}, residual {info['residual']:.1e}, "
                f"cage {info['cage_speed']:.6g} rad/s{slip})")
    return (f"start: the steady solve did not converge ({info['solver']}: {info['reason']}); "
            f"falling back to the quasi-static start")
