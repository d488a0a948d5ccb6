"""`flexbearing quasi-static`: the Jones–Harris equilibrium of a scene's bearing at one instant.

    flexbearing quasi-static SCENE.toml [--time T | --times T0:T1:N] [--control outer|inner|jones|friction]
                                        [--friction-share LO,LI] [--no-gyroscopic] [--balls]
                                        [--stiffness updated|frozen] [--modes N] [--json FILE]

Reads the scene (validated as for `run`), takes the inner-ring speed and the load on the inner
ring at time T (s, default 0; impacts active at T included), and solves `flexbearing.multibody.quasi_static`
for the bearing of the scene (5-DOF ring: tilts free). Prints the per-contact extremes (load,
Hertz pressure, contact angle) and the cage speed; `--balls` adds one line per ball;
`--stiffness` the 5×5 bearing stiffness matrix at that point (`flexbearing.multibody.quasi_static.
bearing_stiffness`: "updated" = tangent of the quasi-static curve, "frozen" = ball kinematics held);
`--json` writes the whole result in SI. `--control friction` replaces the race-control hypothesis
by the ball spin that the traction sets: the steady running state of `flexbearing.multibody.steady` (the
dynamics' accelerations set to zero with the scene's oil, drag, pocket and land models, rigid
cage): for a pure axial load without gravity the fixed point of the dynamics (cage speed, slip,
ball spin); with a radial load or weight the frozen-azimuth state with the cage held off-centre
in its guide film (cage centre, film force against the pockets' resultant, every ball's pocket
force; `--balls` one line per ball). `--times T0:T1:N` solves at N instants from T0 to T1 (s) along the
scene's speed and load profiles, each warm-started from the previous one (a cold solve where the
warm one fails), and prints one row per instant: the quasi-static history of the operating
profile (contact loads, Hertz pressures and angles through a speed ramp or an impact, and with
`--stiffness` the bearing stiffness along it for a rotor-dynamic model), the reference against
which the dynamic run's amplification is read. `--modes N` adds the N lowest natural frequencies
of the ring on its balls about that equilibrium (`flexbearing.multibody.vibration`): the modes with the ring's
participation at rest, the fixed-frame forward/backward/axial lines at speed under a purely axial
load (about the equilibrium of the chosen --control; `--no-gyroscopic` gives the frictionless one
that tests/test_vibration.py checks against the struck dynamic model); at speed with a radial
load the system is time-periodic and the option is refused. What the quasi-static model leaves out (traction, drag, the cage,
gravity) is the dynamics' business: use `flexbearing run` for those. Exit status 0 when the
equilibrium was found, 1 with the solver's diagnostic when not, 2 for invalid input.
"""
from __future__ import annotations

import dataclasses
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from flexbearing.common.safe_files import OutputPlan, write_text_atomic
from flexbearing.common.validation import InputError, require_range
from flexbearing.multibody import state_layout as SL


def register(subparsers) -> None:
    p = subparsers.add_parser("quasi-static", help="Jones-Harris quasi-static equilibrium of a scene's bearing",
                              description=__doc__.splitlines()[0])
    p.add_argument("scene", help="scene file (TOML), e.g. scenes/paper_steady_rigid.toml")
    p.add_argument("--time", type=float, default=0.0,
                   help="instant of the scene's speed and load profiles, s (default 0)")
    p.add_argument("--times", default=None, metavar="T0:T1:N",
                   help="N instants from T0 to T1 (s) along the profiles, one row each (replaces --time)")
    p.add_argument("--control", default="outer", choices=("outer", "inner", "jones", "friction"),
                   help="race that controls the balls: outer, inner, or per ball by Jones's criterion; or "
                        "friction: ball spin from the traction (steady thrust state; with a radial load or weight the frozen-azimuth held-cage state)")
    p.add_argument("--friction-share", default=None, metavar="LO,LI",
                   help="share of the gyroscopic friction between the races, lambda_o + lambda_i = 2 "
                        "(default: all on the controlling race; 1,1 = the dynamics' race-control couple)")
    p.add_argument("--no-gyroscopic", action="store_true", help="leave the gyroscopic moment out")
    p.add_argument("--balls", action="store_true", help="print one line per ball")
    p.add_argument("--stiffness", choices=("updated", "frozen"), default=None,
                   help="also compute the 5x5 stiffness matrix (x, y, z, theta_y, theta_z), SI")
    p.add_argument("--modes", type=int, default=None, metavar="N",
                   help="also the N lowest natural frequencies of the ring on its balls (at rest, or at speed "
                        "under a purely axial load)")
    p.add_argument("--json", metavar="FILE", help="also write the result (SI units) as JSON")
    p.set_defaults(func=cmd_quasi_static)


def _friction_share(text):
    if text is None:
        return None
    try:
        lo, li = (float(v) for v in str(text).split(","))
    except ValueError:
        raise InputError(f"--friction-share = {text!r}: give two numbers LO,LI with LO + LI = 2, e.g. 1,1") from None
    return lo, li


def parse_times(text: str, duration: float):
    """The instants of `--times T0:T1:N` (s): N >= 2 points from T0 to T1 within [0, duration]."""
    try:
        t0, t1, n = str(text).split(":")
        t0, t1 = float(t0), float(t1)
        if float(n) != int(float(n)):
            raise ValueError
        n = int(float(n))
    except ValueError:
        raise InputError(f"--times = {text!r}: give T0:T1:N, start and end in s and a whole number of "
                         "instants, e.g. 0:0.6:13") from None
    require_range("--times T0", t0, 0.0, duration, unit="s")
    require_range("--times T1", t1, t0, duration, unit="s")
    require_range("--times N", n, 2, 10000)
    return np.linspace(t0, t1, n)


def sweep_lines(rows) -> list[str]:
    """The printed table of `sweep_scene` (rpm, kN, MPa, degrees; stiffness diagonal in N/m, N·m/rad)."""
    head = ("    t s      rpm   Fa kN   Fr kN | Qo max N  p0o MPa  a_o deg | Qi max N  p0i MPa  a_i deg |"
            " cage rpm")
    stiff = any("stiffness" in r for r in rows)
    if stiff:
        head += " | Kxx N/m    Kyy N/m    Kzz N/m    Kty N.m/rad"
    lines = [head]
    for r in rows:
        fx, fy, fz = r["load"]
        k = 1 if r["max_load"][1] >= r["max_load"][2] else 2          # the loaded inner half
        line = (f"{r['time']:7.4f} {r['inner_speed'] * 30 / math.pi:8.1f} {fx / 1e3:7.2f} {math.hypot(fy, fz) / 1e3:7.2f} | "
                f"{r['max_load'][0]:8.1f} {r['max_p0'][0] / 1e6:8.1f} {math.degrees(r['angle_at_max_load'][0]):8.2f} | "
                f"{r['max_load'][k]:8.1f} {r['max_p0'][k] / 1e6:8.1f} {math.degrees(abs(r['angle_at_max_load'][k])):8.2f} | "
                f"{r['cage_speed'] * 30 / math.pi:8.1f}")
        if "stiffness" in r:
            d = r["stiffness"].diagonal()
            line += f" | {d[0]:10.4e} {d[1]:10.4e} {d[2]:10.4e} {d[3]:10.4e}"
        if not r["converged"]:
            line += f"  NOT CONVERGED: {r['diagnostic']}"
        lines.append(line)
    return lines


def ball_lines(result) -> list[str]:
    """One line per ball: azimuth, loads and angles of the three contacts, orbit speed, controlling race."""
    lines = [" ball  psi deg |  Q outer N  a_o deg | Q in-left N  a_il deg | Q in-right N  a_ir deg | orbit rpm  race"]
    for j in range(len(result.psi)):
        q, a = result.load[j], [math.degrees(v) for v in result.contact_angle[j]]
        race = "outer" if result.controlling_race is None or result.controlling_race[j] == 0 else "inner"
        lines.append(f"{j:5d} {math.degrees(result.psi[j]):8.1f} | {q[0]:10.1f} {a[0]:8.2f} | {q[1]:11.1f} {a[1]:9.2f} | "
                     f"{q[2]:12.1f} {a[2]:9.2f} | {result.orbit_speed[j] * 30 / math.pi:9.1f}  {race}")
    return lines


def _json_ready(value):
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        # a solver's named result (a hold check, a turning point, a settled mean): its shown fields (a
        # field kept out of its repr, e.g. a whole state vector, stays out of the file too)
        return {f.name: _json_ready(getattr(value, f.name)) for f in dataclasses.fields(value) if f.repr}
    if hasattr(value, "_asdict"):                       # a NamedTuple: by name, not by position
        return _json_ready(value._asdict())
    if isinstance(value, dict):
        return {k: _json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_ready(v) for v in value]
    if isinstance(value, np.ndarray):
        return _json_ready(value.tolist())
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None                     # e.g. the approach of a groove the bearing does not have
    return value


def write_json(path, data) -> None:
    """`data` as strict JSON (SI; non-finite values as null, `_json_ready`), folders created."""
    out = Path(path)
    write_text_atomic(out, json.dumps(_json_ready(data), indent=1, allow_nan=False))
    print(f"json: {out}")


def planned_outputs(args) -> OutputPlan:
    """Every file `flexbearing quasi-static` writes: --json FILE (write_json)."""
    plan = OutputPlan("flexbearing quasi-static", inputs=[args.scene])
    if args.json:
        plan.file(args.json, "--json")
    return plan


def cmd_quasi_static(args) -> int:
    # the library is imported when the command runs: it loads numba and the compiled dynamics
    # (~0.6 s), which `flexbearing --help` and every other command would pay at the top
    from flexbearing.simulation.quasi_static_scene import check_modes_instant, scene_modes, solve_scene
    from flexbearing.simulation.scene import load_scene

    planned_outputs(args).check()                       # the one output rule, before any work
    scene = load_scene(args.scene)                      # refuses bad scenes before any work
    if args.times is not None:
        for flag, given in (("--control friction", args.control == "friction"), ("--balls", args.balls),
                            ("--modes", args.modes is not None)):
            if given:
                raise InputError(f"--times cannot be combined with {flag} (one instant only: use --time T)")
        return _cmd_sweep(scene, args)
    if args.control == "friction":
        return _cmd_friction(scene, args)
    if args.modes is not None:
        check_modes_instant(scene, args.time, args.modes)      # before any work
    result, inputs = solve_scene(scene, args.time, args.control, _friction_share(args.friction_share),
                                 not args.no_gyroscopic)
    fx, fy, fz = inputs["load"]
    print(f"{scene.name} at t = {args.time:g} s: inner ring {inputs['inner_speed'] * 30 / math.pi:.1f} rpm, "
          f"Fa = {fx:.1f} N, Fr = {math.hypot(fy, fz):.1f} N; {args.control} race control")
    print(result.summary())
    if result.notes:                    # a converged state at or near a fold: not unique
        print(f"note: {result.notes}")
    if args.balls:
        print("\n".join(ball_lines(result)))
    stiffness = None
    if args.stiffness and result.converged:
        from flexbearing.multibody.quasi_static import bearing_stiffness, grooves_from_bearing
        stiffness = bearing_stiffness(grooves_from_bearing(scene.bearing), result, kinematics=args.stiffness)
        print(f"stiffness ({args.stiffness} kinematics), rows/columns x, y, z [m], theta_y, theta_z [rad]; "
              f"N/m, N/rad, N·m/m, N·m/rad:")
        for row in stiffness:
            print("  " + " ".join(f"{v:11.4e}" for v in row))
    modes = None
    if args.modes is not None and result.converged:
        modes = scene_modes(scene, result, inputs, args.modes)
        print("\n".join(modes_lines(modes)))
    if args.json:
        data = dict(inputs=inputs, units="SI (N, m, rad, rad/s, Pa)", **result.to_dict())
        if stiffness is not None:
            data.update(stiffness=stiffness, stiffness_kinematics=args.stiffness)
        if modes is not None:
            data["modes"] = modes
        write_json(args.json, data)
    if not result.converged:
        print(f"flexbearing quasi-static: no equilibrium: {result.diagnostic}", file=sys.stderr)
        return 1
    return 0


def modes_lines(modes) -> list[str]:
    """The printed table of `scene_modes`."""
    if modes["kind"] == "at rest":
        out = ["natural frequencies at rest (ring participation x, y, z, theta_y, theta_z):"]
        for f, part in zip(modes["frequency"], modes["participation"]):
            out.append(f"  {f:10.1f} Hz   " + " ".join(f"{v:5.2f}" for v in part))
        return out
    out = ["ring lines in the fixed frame at speed (modes of the frame orbiting with the balls; weight, kind):"]
    for f, w, kind in zip(modes["frequency"], modes["weight"], modes["line"]):
        out.append(f"  {f:10.1f} Hz   {w:5.3f}  {kind}")
    return out


def _cmd_sweep(scene, args) -> int:
    """--times: one row per instant (`sweep_scene`)."""
    from flexbearing.simulation.quasi_static_scene import sweep_scene
    times = parse_times(args.times, scene.duration)
    wall = time.perf_counter()
    rows = sweep_scene(scene, times, args.control, _friction_share(args.friction_share), not args.no_gyroscopic,
                       args.stiffness)
    wall = time.perf_counter() - wall
    print(f"{scene.name}: {len(rows)} instants from {times[0]:g} to {times[-1]:g} s; {args.control} race control; "
          f"{wall:.2f} s")
    print("\n".join(sweep_lines(rows)))
    if args.json:
        write_json(args.json, dict(inputs=dict(scene=scene.name, times=times, control=args.control,
                                               friction_share=_friction_share(args.friction_share),
                                               gyroscopic=not args.no_gyroscopic, stiffness=args.stiffness),
                                   units="SI (N, m, rad, rad/s, Pa)", contacts=["outer", "inner_left", "inner_right"],
                                   rows=rows, wall_s=wall))
    failed = [r["time"] for r in rows if not r["converged"]]
    if failed:
        print(f"flexbearing quasi-static: no equilibrium at t = {failed} s", file=sys.stderr)
        return 1
    return 0


def _cmd_friction(scene, args) -> int:
    """--control friction: print and write the steady running state (module docstring)."""
    from flexbearing.simulation.quasi_static_scene import steady_scene
    y, info, out, inputs = steady_scene(scene, args.time)
    held = inputs["state"] == "held_cage"
    fx, fy, fz = inputs["load"]
    print(f"{scene.name} at t = {args.time:g} s: inner ring {inputs['inner_speed'] * 30 / math.pi:.1f} rpm, "
          f"load ({fx:.1f}, {fy:.1f}, {fz:.1f}) N; ball spin from the traction "
          + ("(steady thrust state)" if not held else "(the dynamics' settled mean, flexbearing.multibody.steady_mean)"
             if info.get("kind") == "settled mean" else "(frozen-azimuth held-cage state, flexbearing.multibody.steady)"))
    sm = info.get("settled_mean") if info.get("kind") == "settled mean" else None
    if sm is not None:
        # no held-cage root: the running state is the dynamics' settled mean (flexbearing.multibody.steady_mean)
        print(f"no frozen-azimuth root; the settled mean of the dynamics over {1e3 * (sm.duration - sm.transient_end):.0f} ms: "
              f"cage speed {sm.cage_speed * 30 / math.pi:.2f} ± {sm.cage_speed_half_width * 30 / math.pi:.2f} rpm, "
              f"slip {100 * sm.slip_rate:.3f} ± {100 * sm.slip_half_width:.3f} % (95 %), "
              f"{'cage held' if sm.held else 'cage not held'} (whirl ratio {sm.whirl_ratio:.2f}); the loads below are "
              "a snapshot of its last sample")
    else:
        print(f"cage speed {info['cage_speed'] * 30 / math.pi:.2f} rpm, slip {100 * info['slip_rate']:.3f} %; "
              f"converged={info['converged']} (residual {info['residual']:.2e})")
    q, ang, p0 = out["contact_load"], out["contact_angle"], out["contact_stress"]
    if held:
        c, land, res = info["cage_centre"], info["cage_land_force"], info["pocket_resultant"]
        ft = out["pocket_force_tangential"]
        print(f"cage centre (y, z) = ({c[1] * 1e6:.1f}, {c[2] * 1e6:.1f}) um, eccentricity ratio "
              f"{info['cage_eccentricity_ratio']:.3f}; guide-land film force ({land[0]:.1f}, {land[1]:.1f}) N "
              f"against the pockets' resultant ({res[1]:.1f}, {res[2]:.1f}) N")
        print(f"pocket force {np.min(out['pocket_force']):.1f} to {np.max(out['pocket_force']):.1f} N "
              f"(tangential on the balls {np.min(ft):.1f} to {np.max(ft):.1f} N)")
        if sm is None:
            print("frozen azimuths: the dynamics' pocket-force pattern lags this one by about 50 deg "
                  "(flexbearing.multibody.steady.steady_held_cage_state); `flexbearing run` for the cage's motion")
        for k, name in enumerate(("outer", "inner_left", "inner_right")):
            print(f"{name:12s}: Qmax {q[:, k].max():9.1f} N  p0max {p0[:, k].max() / 1e6:7.1f} MPa  alpha "
                  f"{math.degrees(ang[:, k].min()):6.2f} to {math.degrees(ang[:, k].max()):6.2f} deg")
        if args.balls:
            psi = y[SL.BALL_PSI:SL.ring_offset(len(q)):SL.BALL_STATE]
            print("ball  psi(deg)   Q_o(N)  Q_il(N)  Q_ir(N)  alpha_o(deg)  pocket_t(N)")
            for j in range(len(q)):
                print(f"{j:4d} {math.degrees(psi[j]) % 360:9.2f} {q[j, 0]:8.1f} {q[j, 1]:8.1f} {q[j, 2]:8.1f} "
                      f"{math.degrees(ang[j, 0]):13.2f} {ft[j]:12.2f}")
    else:
        print(f"ball angular velocity (x, r, t) = ({info['ball_w_x']:.1f}, {info['ball_w_r']:.1f}, "
              f"{info['ball_w_t']:.1f}) rad/s")
        for k, name in enumerate(("outer", "inner_left", "inner_right")):
            print(f"{name:12s}: Q {q[0, k]:9.1f} N  p0 {p0[0, k] / 1e6:7.1f} MPa  alpha {math.degrees(ang[0, k]):6.2f} deg")
    if args.json:
        per_ball = dict(contact_load=q, contact_angle=ang, contact_stress=p0) if held else \
            dict(contact_load=q[0], contact_angle=ang[0], contact_stress=p0[0])
        if held:
            per_ball.update(pocket_force=out["pocket_force"], pocket_force_tangential=out["pocket_force_tangential"])
        write_json(args.json, dict(inputs=inputs, units="SI (N, m, rad, rad/s, Pa)", **info, **per_ball, state=y))
    if not info["converged"]:
        # the solver's reason says which failure it is (a fold, no thrust root, a cage that does not stay held)
        print(f"flexbearing quasi-static: no steady running state: {info.get('reason') or 'the solve did not converge'}; "
              "run the dynamics instead (`flexbearing run`)", file=sys.stderr)
        return 1
    return 0
