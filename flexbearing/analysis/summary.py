"""The report's summary block and its inputs table: what was simulated, with what, by which
program, how long it took, and what came out, in the engineer's units (each value says its unit).

Everything is read from the results file (flexbearing.simulation.results.Run): the scene stored in
it, its attributes (program version, git commit, status) and the run's summary (wall time, steps);
the headline results are the whole-run window of the report's tables (flexbearing.analysis.windows,
samples before --settle left out). Nothing here computes physics.
"""
from __future__ import annotations

import json
import math
from pathlib import Path
import numpy as np
import h5py

from flexbearing.analysis.windows import QUANTITY, impact_windows, speed_phases
import flexbearing.mesh.cage_mesh as cm
from flexbearing.fem_cage.reduced_cage import DEFAULT_N_KEEP, N_RIGID
from flexbearing.common.provenance import git_commit, program_version
from flexbearing.simulation.derived import cage_mass_line, guidance_words, oil_words, traction_words

INTEGRATORS = {"dopri5": "Dormand–Prince 5(4)", "bs32": "Bogacki–Shampine 3(2)"}


def _mm(x: float) -> str:
    return f"{x * 1e3:.4g}"


def bearing_line(b) -> str:
    return (f"{b.n_balls} balls of D_w = {_mm(b.ball_diameter)} mm on a pitch diameter of "
            f"{_mm(b.pitch_diameter)} mm; D × d × B = {_mm(b.outside_diameter)} × {_mm(b.bore_diameter)} × "
            f"{_mm(b.width)} mm; groove radii f_e = {b.fe:g}, f_i = {b.fi:g} (× D_w); free contact angle "
            f"{math.degrees(b.free_contact_angle):.1f}°; " + _land_words(b))


def _land_words(b) -> str:
    """The land the cage rides on (none for a ball-riding cage)."""
    if b.cage.guidance == "inner":
        return f"inner-ring guide land Ø {_mm(b.inner_land_diameter_or_default)} mm"
    if b.cage.guidance == "balls":
        return "no guide land (ball-riding cage)"
    return f"outer-ring guide land Ø {_mm(b.guide_land_diameter)} mm"


def speed_line(scene) -> str:
    return "; ".join(f"{p['t_start']:g}–{p['t_end']:g} s {p['label']}" for p in speed_phases(scene))


def load_line(scene) -> str:
    tab = np.asarray(scene.load_table)
    fa = tab[:, 1]
    fr = np.hypot(tab[:, 2], tab[:, 3])
    if len(tab) == 1 or (np.ptp(fa) == 0 and np.ptp(fr) == 0):
        text = f"F_a = {fa[0] / 1e3:g} kN, F_r = {fr[0] / 1e3:g} kN (constant)"
    else:
        text = (f"piecewise linear over {len(tab)} points: F_a {fa.min() / 1e3:g}–{fa.max() / 1e3:g} kN, "
                f"F_r {fr.min() / 1e3:g}–{fr.max() / 1e3:g} kN")
    imps = impact_windows(scene)
    if imps:
        from flexbearing.simulation.scene import IMPACT_SHAPES
        shapes = {v: k for k, v in IMPACT_SHAPES.items()}
        kinds = sorted({shapes.get(int(s), "pulse") for s in np.asarray(scene.impacts).reshape(-1, 6)[:, 5]})
        text += (f"; {len(imps)} {'/'.join(kinds)} impact(s): "
                 + ", ".join(f"{i['magnitude'] / 1e3:g} kN for {(i['t_end'] - i['t_start']) * 1e3:g} ms at "
                             f"{i['t_peak']:g} s" for i in imps))
    return text


def oil_line(oil) -> str:
    return (f"{oil_words(oil)}: η = {oil.viscosity():.4g} Pa·s, pressure–viscosity α = "
            f"{oil.pressure_viscosity_coeff:.3g} 1/Pa, density {oil.density:g} kg/m³; oil volume fraction "
            f"in the cavity {100 * oil.oil_air_fraction:g} %")


def cage_line(scene, attrs) -> str:
    c = scene.bearing.cage
    geo = (f"outside Ø {_mm(c.outside_diameter)} mm, bore Ø {_mm(c.bore_diameter)} mm, width {_mm(c.width)} mm, "
           f"pocket Ø {_mm(c.pocket_diameter)} mm; {guidance_words(scene.bearing)}")
    if scene.cage_model != "flexible":
        return f"rigid; {geo}"
    from flexbearing.coupling.flexible_cage import DEFAULT_DAMPING_BETA
    fl = scene.flexible
    n = int(fl.get("n_modes", DEFAULT_N_KEEP))
    mesh = (f"FE mesh: element size {fl.get('mesh_size', cm.DEFAULT_MESH_SIZE) * 1e3:g} mm, "
            f"P{fl.get('element_order', cm.DEFAULT_DEGREE)} tetrahedra on the curved 10-node mesh")
    nodes = _reduced_cage_size(attrs.get("reduced_cage_file"))
    return (f"flexible, Craig–Bampton reduction with {n} modes ({N_RIGID} rigid + {n - N_RIGID} elastic), "
            f"stiffness-proportional damping β = {fl.get('damping_beta', DEFAULT_DAMPING_BETA):g} s; {mesh}"
            + (f" ({nodes})" if nodes else "") + f"; {geo}")


def _reduced_cage_size(path) -> str:
    """'N nodes, M tetrahedra' of a reduced cage file ('' when it is not there)."""
    if not path or not Path(str(path)).is_file():
        return ""
    try:
        with h5py.File(path, "r") as f:
            return f"{f['mesh/vertices'].shape[0]:,} nodes, {f['mesh/tets'].shape[0]:,} tetrahedra"
    except (OSError, KeyError):
        return ""


def integrator_line(scene, run_summary: dict) -> str:
    text = (f"{scene.method} ({INTEGRATORS.get(scene.method, scene.method)}), relative tolerance "
            f"{scene.tolerance:g}, initial step {scene.initial_step:g} s"
            + (f", max step {scene.max_step:g} s" if scene.max_step else "")
            + f"; samples every {scene.sample_interval * 1e3:g} ms")
    if "n_steps" in run_summary:
        text += f"; {run_summary['n_steps']:,} steps ({run_summary.get('n_rejected', 0):,} rejected)"
    return text


def _headline(label: str, value, unit: str, fmt: str, t=None) -> tuple[str, str] | None:
    if value is None or not math.isfinite(value):
        return None
    return label, f"**{fmt.format(value)} {unit}**" + (f" at t = {t:.4g} s" if t is not None else "")


def headline_rows(whole: dict, strength: dict | None, power: dict | None) -> list[tuple[str, str]]:
    """The run's headline results (whole-run window, engineer's units)."""
    out = []
    for key in ("outer_contact_stress", "inner_contact_stress", "pocket_force", "guiding_force", "von_mises_max",
                "film_thickness_min", "slip_rate"):
        q = QUANTITY[key]
        stat = q.extreme_stat if key != "slip_rate" else "mean"
        v = whole.get(f"{key}_{stat}")
        word = {"peak": "max.", "min": "min.", "mean": "mean"}[stat]
        label = f"{q.label}, {word} ({q.display_unit})"
        row = _headline(label, None if v is None else v * q.scale, q.display_unit,
                        "{:,.3g}" if q.display_unit in ("µm", "%") else "{:,.0f}",
                        whole.get(f"{key}_t_peak") if stat != "mean" else None)
        if row:
            out.append(row)
    if strength and strength.get("utilization_peak") is not None:
        out.append(("Cage utilization σ_vM / R_e, peak",
                    f"**{strength['utilization_peak']:.2f}** (R_e = {strength['yield_strength'] / 1e6:,.0f} MPa)"))
    if power and power.get("loss") is not None:
        out.append(("Power loss, mean (W)", f"**{power['loss']:,.0f} W**; friction torque "
                                            f"{power['drive_torque']:.3g} N·m"))
    return out


def summary_rows(run, rows: list[dict], strength_rows: list[dict], power_rows: list[dict]) -> list[tuple[str, str]]:
    """(item, value) of the report's summary block (module doc) for an open Run and its report
    tables (whole run first)."""
    scene = run.scene
    attrs = run.attrs
    try:
        rs = json.loads(attrs.get("summary", "{}"))
    except (TypeError, ValueError):
        rs = {}
    out = [("Run", f"`{run.path.name}`: {run.name}, status {run.status}")]
    if scene is not None:
        if scene.description:
            out.append(("Scene", " ".join(scene.description.split())))
        out += [("Bearing", bearing_line(scene.bearing)), ("Speed spectrum (inner ring)", speed_line(scene)),
                ("Load spectrum (on the inner ring)", load_line(scene)), ("Oil", oil_line(scene.oil)),
                ("Traction law", traction_words(scene)),
                ("Cage", cage_line(scene, attrs)), ("Integrator", integrator_line(scene, rs))]
        if getattr(scene, "derived", ()):
            out.append(("Not given in the scene", "; ".join([d.line() for d in scene.derived]
                                                            + [cage_mass_line(scene.bearing)])))
        if getattr(scene, "warnings", ()):
            out.append(("Warnings", "; ".join(scene.warnings)))
    n = rows[0]["n_samples"] if rows else 0
    wall = rs.get("wall_time_s")
    simulated = f"{float(attrs.get('duration', 0.0)):g} s simulated"
    if rows:
        simulated += f", {int(run.outputs['time'].shape[0]):,} samples ({n:,} in the reported window " \
                     f"{rows[0]['t_start']:g}–{rows[0]['t_end']:g} s)"
    out.append(("Run and wall time", simulated + (
        f"; wall time {wall:,.0f} s ({wall / 60:.1f} min) + {rs.get('setup_time_s', 0):.0f} s setup"
        + (f", resumed {rs['n_resumes']} time(s)" if rs.get("n_resumes") else "") if wall is not None else
        "; wall time not recorded (the run has no summary: interrupted?)")))
    out.append(("Program", f"run by flexbearing {attrs.get('program_version', 'unknown (not recorded)')}, "
                           f"git {attrs.get('git_commit', 'unknown (not recorded)')}; report by "
                           f"flexbearing {program_version()}, git {git_commit()}"))
    if rows:
        out += settled_rows(rows, attrs)
        out += mark_unsettled(headline_rows(rows[0], strength_rows[0] if strength_rows else None,
                                            power_rows[0] if power_rows else None), rows[0])
    return out


# ---------------------------------------------------------------- settled before statistics
def settled_rows(rows: list[dict], attrs=None) -> list[tuple[str, str]]:
    """The summary's lines on the run's initial state (the results file's attribute initial_state,
    written by a run with [integrator] start = "steady"; without it the quasi-static start) and on
    whether each uniform-speed phase settled (flexbearing.analysis.settling; rows carry "settling"
    where the report tested them)."""
    from flexbearing.analysis.settling import summary_text
    start = None if attrs is None else attrs.get("initial_state")
    out = [("Initial state", str(start) if start else
            "quasi-static equilibrium without friction, balls rolling (`[integrator] start = \"steady\"` starts "
            "from the steady running state)")]
    text = summary_text(rows)
    return out + ([] if text is None else [("Settled? (per uniform-speed phase)", text)])


def mark_unsettled(headlines: list[tuple[str, str]], whole: dict) -> list[tuple[str, str]]:
    """The headline mean (the slip) of a whole-run window that did not settle, marked: a mean of a
    signal that still drifts is not its running value. Of a settled window whose start-up transient
    lies inside it (no --settle past it), the mean after the transient beside it."""
    from flexbearing.analysis.settling import MARK, SIGNALS, unsettled
    st = whole.get("settling")
    if not st:
        return headlines
    slip = st["signals"].get("slip_rate")
    out = []
    for label, value in headlines:
        if label.startswith(QUANTITY["slip_rate"].label) and ", mean" in label:
            if unsettled(whole):
                drifting = [SIGNALS[v["signal"]][0] for v in st["signals"].values() if v["settled"] is False]
                value += (f" {MARK} not settled ({', '.join(drifting)} still drifting or in its start-up): "
                          "not the running value")
            elif slip and slip.get("mean_after") is not None and st.get("transient_end") is not None \
                    and st["transient_end"] > whole["t_start"] + 1e-9:
                value += (f"; it includes the start-up transient to t = {st['transient_end']:.4g} s: "
                          f"{100 * slip['mean_after']:.3g} % after it")
        out.append((label, value))
    return out


def input_rows(data: dict, prefix: str = "") -> list[tuple[str, str]]:
    """The scene's parsed TOML flattened to (dotted key, value) rows; tables of points (load
    points, speed phases) one row per entry."""
    out = []
    for k, v in data.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out += input_rows(v, key + ".")
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            for i, x in enumerate(v):
                out.append((f"{key}[{i}]", ", ".join(f"{a} = {_value(b)}" for a, b in x.items())))
        else:
            out.append((key, _value(v)))
    return out


def _value(v) -> str:
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, bool):
        return str(v).lower()
    if isinstance(v, float):
        return f"{v:g}"
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    return str(v)
