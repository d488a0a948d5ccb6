"""The quasi-static and steady solutions of a scene's bearing at its instants (the `quasi-static` command's work).

A scene (flexbearing.simulation.scene) gives the bearing, the oil and the speed and load profiles; these functions
take its speed and load at an instant (`scene_instant`, impacts included) and solve:

- `solve_scene`: the Jones–Harris equilibrium (flexbearing.multibody.quasi_static, 5-DOF ring, tilts free)
  under a race-control hypothesis, optionally warm-started;
- `sweep_scene`: the same along the profiles at many instants, each warm-started from the
  previous one, with the bearing stiffness if asked (flexbearing.multibody.quasi_static.bearing_stiffness);
- `steady_scene`: the running state whose ball spin the traction sets (flexbearing.multibody.steady): the
  steady thrust state for a pure axial load without gravity, the frozen-azimuth held-cage state
  otherwise;
- `scene_modes`: the natural frequencies of the ring on its balls about an equilibrium
  (flexbearing.multibody.vibration).

flexbearing.analysis.amplification reads the quasi-static contact stress at each impact from `solve_scene`.
"""
from __future__ import annotations

import math

import numpy as np

from flexbearing.common.validation import InputError, require_range
from flexbearing.multibody import model as M
from flexbearing.multibody.model import build_model, P_IID, P_IIP, P_MI
from flexbearing.multibody.profiles import load_at, speed_at
from flexbearing.multibody.quasi_static import bearing_stiffness, grooves_from_bearing, solve_quasi_static
from flexbearing.multibody.steady import steady_held_cage_state, steady_thrust_state
from flexbearing.multibody.vibration import linear_model, lines_at_speed, natural_modes


def scene_instant(scene, time: float):
    """(omega rad/s, force (Fx, Fy, Fz) N) of `scene` at `time`: the speed and the load (table
    plus the impacts active then) from the scene's profiles (flexbearing.multibody.profiles)."""
    require_range("--time", time, 0.0, scene.duration, unit="s")
    force = np.zeros(3)
    load_at(time, scene.load_table, scene.impacts, force)
    return float(speed_at(time, scene.speed_table)), force


def solve_scene(scene, time: float = 0.0, control: str = "outer", friction_share=None, gyroscopic: bool = True,
                initial=None, psi0: float = 0.0):
    """(result, inputs) of flexbearing.multibody.quasi_static for `scene` at `time` (`scene_instant`); `initial`:
    a previous result to start from (when it does not converge, the solver repeats the solve cold); psi0:
    azimuth of ball 0 (rad, from +Y towards +Z). A solve that does not converge is returned with
    result.converged False and result.diagnostic saying why (strict=False): the callers (command line,
    sweeps, the impact amplification) report it."""
    omega, force = scene_instant(scene, time)
    result = solve_quasi_static(grooves_from_bearing(scene.bearing), omega, fx=force[0], fy=force[1], fz=force[2],
                                control=control, friction_share=friction_share, gyroscopic=gyroscopic,
                                initial=initial, psi0=psi0, strict=False)
    inputs = dict(scene=scene.name, time=time, inner_speed=omega, load=force.tolist(), control=control,
                  friction_share=friction_share, gyroscopic=gyroscopic)
    return result, inputs


def sweep_scene(scene, times, control: str = "outer", friction_share=None, gyroscopic: bool = True,
                stiffness: str | None = None) -> list[dict]:
    """Quasi-static equilibrium of `scene` at each of `times` (s), each solve warm-started from the
    previous one (`solve_scene`). One dict per instant, SI: time, inner_speed, load (3,),
    cage_speed, converged, diagnostic, and per contact (outer, inner_left, inner_right) the
    largest ball load, the largest Hertz pressure and the contact angle of the most loaded ball;
    `stiffness` ("updated" | "frozen"): also the 5×5 bearing stiffness (`bearing_stiffness`)."""
    grooves = grooves_from_bearing(scene.bearing)
    rows, previous = [], None
    for t in times:
        r, inputs = solve_scene(scene, float(t), control, friction_share, gyroscopic, initial=previous)
        most = np.argmax(r.load, axis=0)
        row = dict(time=float(t), inner_speed=inputs["inner_speed"], load=inputs["load"], cage_speed=r.cage_speed,
                   converged=bool(r.converged), diagnostic=r.diagnostic, max_load=r.load.max(axis=0),
                   max_p0=r.p0.max(axis=0), angle_at_max_load=r.contact_angle[most, np.arange(3)])
        if stiffness and r.converged:
            row["stiffness"] = bearing_stiffness(grooves, r, kinematics=stiffness)
        rows.append(row)
        previous = r if r.converged else None
    return rows


def steady_scene(scene, time: float = 0.0):
    """(y, info, outputs, inputs): the steady running state of `scene` at `time` (rigid cage, the
    scene's model options): flexbearing.multibody.steady's steady thrust state for a pure axial load without
    gravity, its frozen-azimuth held-cage state otherwise (a radial load or weight: the balls
    differ by azimuth and the cage sits off-centre in its guide film)."""

    omega, force = scene_instant(scene, time)
    model = build_model(scene.bearing, scene.oil, scene.model_options)
    held = math.hypot(force[1], force[2]) != 0.0 or model.p[M.P_GRAV] != 0.0
    if held:
        y, info = steady_held_cage_state(model, omega, force, strict=False)
    else:
        y, info = steady_thrust_state(model, omega, float(force[0]), strict=False)
    info["slip_rate"] = float(info["outputs"]["slip_rate"])
    out = info.pop("outputs")
    inputs = dict(scene=scene.name, time=time, inner_speed=omega, load=force.tolist(), control="friction",
                  state="held_cage" if held else "thrust")
    return y, info, out, inputs


def scene_modes(scene, result, inputs, n_modes: int) -> dict:
    """The `n_modes` lowest natural frequencies of the ring on its balls about `result`
    (flexbearing.multibody.vibration; ring mass and inertias of the scene's model): at rest {"kind": "at rest",
    "frequency" (Hz), "participation" (n, 5: ring x, y, z, theta_y, theta_z)}; at speed under a
    purely axial load {"kind": "orbiting frame", "frequency", "weight", "line"} (fixed-frame lines).
    At speed with a radial load the system is time-periodic: refused (InputError)."""

    check_modes_instant(scene, inputs["time"], n_modes)
    p = build_model(scene.bearing, scene.oil, scene.model_options).p
    K, M = linear_model(grooves_from_bearing(scene.bearing), result, p[P_MI], p[P_IID])
    speed = inputs["inner_speed"]
    if speed == 0.0:
        freq, _, part = natural_modes(K, M)
        keep = freq > 1e-6 * freq.max()                   # the balls' free orbit directions have no stiffness
        return {"kind": "at rest", "frequency": freq[keep][:n_modes], "participation": part[:, keep][:, :n_modes].T}
    lines = lines_at_speed(K, M, p[P_MI], p[P_IID], p[P_IIP], speed, float(np.mean(result.orbit_speed)),
                           min_weight=1e-2)
    lines = [ln for ln in lines if ln[0] > 1.0][:n_modes]
    return {"kind": "orbiting frame", "frequency": [ln[0] for ln in lines], "weight": [ln[1] for ln in lines],
            "line": [ln[2] for ln in lines]}


def check_modes_instant(scene, time: float, n_modes: int) -> None:
    """--modes: N in range; at speed the load must be purely axial (`scene_modes`)."""
    require_range("--modes", n_modes, 1, 1000)
    speed, force = scene_instant(scene, time)
    fr = math.hypot(force[1], force[2])
    if speed != 0.0 and fr > 0.0:
        raise InputError(f"--modes at speed needs a purely axial load: the radial load of {fr:.6g} N at t = {time:g} s "
                         "makes the balls differ around the orbit (a time-periodic system); take an instant at rest "
                         "(speed 0) or a scene without radial load")
