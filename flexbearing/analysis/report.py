"""`report.md`, `report.json` and `report.html` of a run: the tables, the plots and the cage's stress.

`write_report` assembles the report of a run (and of a run to compare with): the statistics per
phase and impact (flexbearing.analysis.windows, whose docstring defines the quantities and the peak, p99 and
mean), the cage's stress against its yield strength, the contact stress at each impact against the
quasi-static equilibrium (flexbearing.analysis.amplification), the cage's motion and the power loss; the plots
(flexbearing.analysis.plots); for a flexible cage the picture of the cage's von Mises field at the run's
maximum (flexbearing.analysis.stress_picture) and the field for ParaView at the peaks and, with a series
window, over it with the balls (flexbearing.analysis.field_export). Files stay SI; only the printed tables
and the plot axes use the engineer's units (MPa, N, µm, rpm, %) and say so. Command line:
`flexbearing report` (flexbearing.cli.report).
"""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

from flexbearing.common.validation import InputError
from flexbearing.analysis.plots import write_orbit_plot, write_plots
from flexbearing.simulation.results import check_run
from flexbearing.analysis.windows import (MOTION_ROWS, QUANTITIES, QUANTITY, Quantity, cage_motion_rows, cage_strength_rows,
                              phase_rows, phase_table, power_loss_rows, read_motion, read_power, read_run,
                              window_title)


def _motion_markdown(rows: list[dict]) -> str:
    head = ["quantity"] + [window_title(r) for r in rows]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" + "---:|" * len(rows)]
    for label, key, scale, fmt in MOTION_ROWS:
        cells = [label] + ["–" if r.get(key) is None else fmt.format(r[key] * scale) for r in rows]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _power_markdown(rows: list[dict]) -> str:
    from flexbearing.multibody.power_loss import BREAKDOWN
    head = ["quantity"] + [window_title(r) for r in rows]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" + "---:|" * len(rows)]

    def line(label, cells):
        lines.append("| " + " | ".join([label] + cells) + " |")

    def watts(v):
        return "–" if v is None else f"{(v if abs(v) >= 0.5 else 0.0):,.0f}"

    line("Friction torque (drive torque of the inner ring), N·m", [f"{r['drive_torque']:.3g}" for r in rows])
    line("**Power loss, W**", [f"**{watts(r['loss'])}**" for r in rows])
    for label, key in BREAKDOWN:
        line(f"&nbsp;&nbsp;{label}, W (%)",
             [f"{watts(r[key])} ({100.0 * r[key] / r['loss']:.1f})" if r["loss"] else watts(r[key]) for r in rows])
    line("Drive power T·omega_i, W", [watts(r["drive_power"]) for r in rows])
    line("External load power F·v_ring, W", [watts(r["load_power"]) for r in rows])
    line("Rate of change of the mechanical energy, W", [watts(r["energy_rate"]) for r in rows])
    line("Balance residual (drive + load − loss − energy rate), W", [watts(r["residual"]) for r in rows])
    return "\n".join(lines)


def _strength_markdown(rows: list[dict]) -> str:
    head = ["quantity"] + [window_title(r) for r in rows]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" + "---:|" * len(rows)]

    def line(label, key, fmt, scale=1.0):
        cells = ["–" if r[key] is None else fmt.format(r[key] if scale == 1.0 else r[key] * scale) for r in rows]
        lines.append("| " + " | ".join([label] + cells) + " |")
    line("Max. von Mises stress, peak (MPa)", "von_mises_max_peak", "{:,.0f}", 1e-6)
    line("Utilization peak / R_e", "utilization_peak", "{:.2f}")
    line("Utilization p99 / R_e", "utilization_p99", "{:.2f}")
    line("Sample intervals above R_e", "intervals_above_yield", "{:d}")
    line("Share of the window above R_e (%)", "share_above_yield", "{:.2f}", 100.0)
    return "\n".join(lines)


def _fmt(v, scale: float) -> str:
    if v is None or not np.isfinite(v):
        return "–"
    x = v * scale
    ax = abs(x)
    if ax >= 100:
        return f"{x:,.0f}"
    if ax >= 10:
        return f"{x:.1f}"
    return f"{x:.2f}" if ax >= 0.1 or x == 0 else f"{x:.3g}"


def _stat_rows(keys) -> list[tuple[str, str, Quantity]]:
    rows = []
    for k in keys:
        qd = QUANTITY[k]
        for stat in qd.stats:
            rows.append((f"{qd.label}, {stat} ({qd.display_unit})", f"{k}_{stat}", qd))
    return rows


def _markdown_table(columns: list[tuple[str, dict]], keys, increase_from: int | None = None) -> str:
    head = ["quantity"] + [c for c, _ in columns]
    if increase_from is not None:
        head.append(f"change vs {columns[increase_from][0]}")
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" + "---:|" * (len(head) - 1)]
    for label, field, qd in _stat_rows(keys):
        cells = [label] + [_fmt(row.get(field), qd.scale) for _, row in columns]
        if increase_from is not None:
            a, b = columns[increase_from][1].get(field), columns[-1][1].get(field)
            if a is None or b is None:
                cells.append("–")
            elif qd.display_unit == "%":      # a signed ratio (slip): the difference, in points
                cells.append(f"{(b - a) * qd.scale:+.2f} points")
            else:
                cells.append(f"{100 * (b - a) / abs(a):+.1f} %" if a != 0 else "–")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _check_frames(path, frames) -> None:
    """InputError if `frames` (--frames) is not 'auto' or times inside the run, or names times of a
    run without a flexible cage (whose von Mises field they would select)."""
    import h5py

    from flexbearing.analysis import field_export
    from flexbearing.simulation.results import sample_interval
    if frames is None or (isinstance(frames, str) and frames.strip() == "auto"):
        return
    with h5py.File(path, "r") as f:
        t = f["outputs/time"][...]
        dt = sample_interval(f, t)
        flexible = "cage_modal_coordinates_full" in f["outputs"]
    field_export.parse_frames(frames, t, dt)
    if not flexible:
        raise InputError(f"--frames = {frames!r}: {path} has no flexible-cage field (rigid cage, no modal "
                         f"coordinates); --frames selects von Mises frames of a flexible-cage run")


# the files a report writes by these names (plots: *.png; the field export's: field_export.FIELD_FILES)
REPORT_FILES = ("report.md", "report.html", "report.json")


def write_report(run_h5, out_dir, compare=None, frames="auto", reduced_cage=None,
                 quiet: bool = True, settle: float = 0.0, series: str | None = None,
                 displacement_scale: float | None = None) -> dict:
    """Plots, the per-phase table (report.md, report.json), the same as one self-contained page
    with the plots embedded (report.html, flexbearing.analysis.html_page) and, for a flexible-cage run, the
    picture of the cage's stress field at the run's maximum and the von Mises XDMF frames; with
    `series` ("T0:T1[:N]") the ParaView time series of that window (flexbearing.analysis.field_export.
    write_series, written first: a bad window stops the report). Returns {"report", "html",
    "json", "plots", "xdmf", "stress_picture", "series"} (None where not written)."""
    import h5py

    from flexbearing.analysis import field_export
    from flexbearing.common.safe_files import check_output_folder
    path = check_run(run_h5)
    cmp_path = check_run(compare) if compare is not None else None
    _check_frames(path, frames)                  # a bad --frames stops the report before any file
    out_dir = Path(out_dir)
    # nothing the report writes may replace an input or go through a link planted in its folder
    check_output_folder(out_dir, REPORT_FILES + field_export.FIELD_FILES, [path, cmp_path, reduced_cage],
                        patterns=("*.png",))
    out_dir.mkdir(parents=True, exist_ok=True)
    say = (lambda *a: None) if quiet else (lambda *a: print(*a, file=sys.stderr))
    series_out = None
    if series is not None:
        say(f"report: ParaView series {series} of {path.name}")
        series_out = field_export.write_series(path, out_dir, series, reduced_cage=reduced_cage,
                                               displacement_scale=displacement_scale)
    run = read_run(path)
    rows = phase_rows(*run, True, settle)
    cmp_rows = phase_table(cmp_path, settle=settle) if cmp_path else None
    amplification = _impact_amplification(*run)
    motion_rows = cage_motion_rows(*read_motion(path), True, settle)
    power_rows = power_loss_rows(*read_power(path), True, settle)
    strength_rows = cage_strength_rows(*run, True, settle)
    say(f"report: plots of {path.name} -> {out_dir}")
    plots = write_plots(path, out_dir, compare=cmp_path)
    orbit_png = write_orbit_plot(path, out_dir, settle=settle) if motion_rows else None
    with h5py.File(path, "r") as f:
        name = str(f.attrs.get("scene_name", path.stem))
        status = str(f.attrs.get("status", ""))
        cage = str(f.attrs.get("cage_model", ""))
        flexible = "cage_modal_coordinates_full" in f["outputs"]
    cmp_name = None
    if cmp_path:
        with h5py.File(cmp_path, "r") as f:
            cmp_name = str(f.attrs.get("scene_name", cmp_path.stem))
    xdmf, xdmf_note = None, "not written: the run has no flexible-cage modal coordinates (rigid cage)."
    picture, picture_md = None, []
    if flexible:
        try:
            say("report: von Mises XDMF frames and the stress picture")
            xdmf = field_export.write_von_mises_xdmf(path, out_dir, frames, reduced_cage=reduced_cage)
            xdmf_note = f"`{xdmf.name}` (+ `{xdmf.with_suffix('.h5').name}`; frames in `{xdmf.with_suffix('.json').name}`)"
        except InputError as exc:
            xdmf_note = f"not written: {exc}"
            say(f"report: {xdmf_note}")
        from flexbearing.analysis.stress_picture import picture_markdown, write_stress_picture
        try:
            picture, facts = write_stress_picture(path, out_dir, reduced_cage=reduced_cage, settle=settle,
                                                  yield_strength=strength_rows[0]["yield_strength"]
                                                  if strength_rows else None)
            picture_md = picture_markdown(picture, facts)
        except InputError as exc:
            picture_md = ["## Cage von Mises stress at the run's maximum", "", f"Not drawn: {exc}", ""]
            say(f"report: stress picture not drawn: {exc}")
    keys = [q.key for q in QUANTITIES if rows and f"{q.key}_mean" in rows[0]]
    md = [f"# Run report: {name}", "",
          f"- results file: `{path}` (status: {status}, cage: {cage}, "
          f"{rows[0]['n_samples'] if rows else 0} samples, {rows[0]['t_start'] if rows else 0:g}–"
          f"{rows[0]['t_end'] if rows else 0:g} s)"]
    if cmp_path:
        md.append(f"- compared with: `{cmp_path}` ({cmp_name})")
    md += ["- source: the SI datasets of the results file (Pa, N, m, rad/s, 1); shown here in MPa, N, "
           "µm, rpm and %. Machine-readable SI values: `report.json`.",
           "- peak = maximum over the window and over the balls (the worst ball); min for the film "
           "thickness; for the slip rate the signed value of largest magnitude. p99 = the 99th percentile over the window's "
           "samples of the worst ball's value, the level it exceeds in 1 % of the time (p1 of the thinnest film; "
           "robust where the peak is one ball–cage collision). mean = mean over the window and over the balls (= one ball's time average over "
           "whole cage revolutions, the paper's \"average value\"). Inner-race contact stress: the "
           "loaded one of the two inner halves; film: the smallest over a ball's loaded contacts; "
           "guiding force: cage–land film force magnitude.",
           "- phase windows [t_start, t_end), the last one closed; impact windows = the load pulse"
           + (f"; samples before t = {settle:g} s (start-up transient) left out of every window." if settle
              else "; the start-up transient from the quasi-static initial state is included "
                   "(`--settle S` leaves it out)."), ""]
    if cmp_rows:
        md += [f"## {cmp_name} vs {name} (whole runs)", "",
               _markdown_table([(cmp_name, cmp_rows[0]), (name, rows[0])], keys, increase_from=0), ""]
    if rows:
        md += [f"## {name}: per phase of the speed profile and per impact", "",
               _markdown_table([(window_title(r), r) for r in rows], keys), ""]
        peaks = [(r["label"], r.get(f"{k}_t_peak")) for r in rows[1:] for k in ("von_mises_max",)
                 if r.get(f"{k}_t_peak") is not None]
        if peaks:
            md += ["Instants of maximum von Mises stress: " + "; ".join(f"{lab}: {tp:g} s" for lab, tp in peaks), ""]
    if strength_rows:
        ys = strength_rows[0]["yield_strength"]
        above = strength_rows[0]["intervals_above_yield"]
        md += ["## Cage stress against the yield strength", "",
               _strength_markdown(strength_rows), "",
               f"R_e = {ys / 1e6:,.0f} MPa (the scene's cage.yield_strength; default the minimum yield strength "
               "of quenched and tempered 40CrNiMoA, GB/T 3077). The von Mises stress of a sample interval is "
               "the maximum over the cage's mesh nodes and every integrator step in it (flexbearing.multibody.stress_peak). "
               "The cage model is linear elastic: where the utilization exceeds 1 its stress is the elastic "
               "one, an upper bound of the real stress with a local plastic zone, and the model is outside "
               "its validity there. "
               + ("No sample interval of the run exceeds R_e." if above == 0 else
                  f"{above} sample interval(s) of the run exceed R_e. Peaks that are single ball–cage collisions "
                  "scatter by a few percent between equally valid integrations (benchmarks/results/study/README.md), "
                  "so read the p99 utilization beside the peak."), ""]
    if amplification:
        md += ["## Contact stress at the impacts against the quasi-static equilibrium", "",
               _amplification_table(amplification), "",
               "Quasi-static: flexbearing.multibody.quasi_static at the pulse's peak instant (speed and load of that instant, a "
               "ball on the load line, Jones's race control); run: the worst ball's peak from the start of the pulse to "
               "5 T_n after its end (a short pulse's largest response comes after it). Amplification = run / "
               "quasi-static (flexbearing.analysis.amplification). One-DOF estimate: the inner ring's mass on the bearing's secant "
               "radial stiffness from the load before the pulse to its peak, natural period T_n, and the undamped "
               "shock spectrum of the displacement under a half-sine pulse of duration t_d (the contact stress "
               "amplifies less: p0 grows as Q^(1/3)); near 1 when t_d >> T_n: the pulse is then quasi-static for the "
               "contacts, and the stress it adds is the static response to the larger load.", ""]
    if motion_rows:
        md += ["## Cage motion in the guide clearance", "",
               _motion_markdown(motion_rows), "",
               "From the recorded cage centre (its offset from the guide-land centre) and cage speed "
               "(flexbearing.analysis.cage_motion): e/Cg the eccentricity ratio (1 = on the guide rim); whirl ratio = the "
               "centre's net whirl angle over the cage's rotation angle in the window (> 0 forward; 1 synchronous "
               "whirl, 0.5 half-frequency whirl on the land film, near 0 a centre held at one azimuth by a "
               "static load); velocity dispersion = std/mean of the centre's speed, the stability index of "
               "Ghaisas, Wassgren & Sadeghi (2004): 0 for a steady circular whirl, of order 1 for the "
               "irregular, collision-driven motion of an unstable cage, but also for a whirl that decays to rest "
               "inside the window (a cage that settles at one azimuth after an impact): read it with the orbit, "
               "`cage_orbit.png`, and the time held: the share of samples whose centre moves slower than a "
               "half-frequency whirl at a tenth of the clearance would (a cage at rest at one azimuth).", ""]
    if power_rows:
        md += ["## Friction torque and power loss", "",
               _power_markdown(power_rows), "",
               "Window means of the power each dissipative force pair of the model dissipates "
               "(flexbearing.multibody.power_loss): the sliced EHL traction (sliding and spin) and the EHL rolling "
               "forces of the race contacts, the contact damping, the lubricated pockets, the churning "
               "drag of the balls, the guide-land film and rim and, for a flexible cage, its modal "
               "damping. The drive torque is what holds the inner ring at its prescribed speed, the "
               "bearing's friction torque; in a steady window the drive power equals the loss (the "
               "work–energy theorem of the model, exact to rounding at single states, "
               "tests/test_power_loss.py); the residual is the sampling error of the window means "
               "(and the small non-conservative part of the angle-dependent Hertz constant). The "
               "oil's viscosity is isothermal (no inlet shear heating), which overestimates the EHL "
               "rolling resistance at high speed.", ""]
    if cmp_rows and len(cmp_rows) > 2:
        md += [f"## {cmp_name}: per phase", "", _markdown_table([(window_title(r), r) for r in cmp_rows], keys), ""]
    if orbit_png is not None:
        plots = plots + [orbit_png]
    md += ["## Plots", ""] + [f"![{p.stem}]({p.name})" for p in plots] + [""]
    md += picture_md
    md += ["## Cage von Mises field (ParaView)", "", f"Frames at the peaks: {xdmf_note}", "",
           field_export.series_markdown(series_out, series), ""]
    report = out_dir / "report.md"
    report.write_text("\n".join(md))
    from flexbearing.analysis.html_page import write_html
    page = write_html(report)
    js = out_dir / "report.json"
    js.write_text(json.dumps({"run": str(path), "scene": name, "status": status, "units": {
        q.key: q.unit for q in QUANTITIES}, "phases": rows, "compare": str(cmp_path) if cmp_path else None,
        "compare_phases": cmp_rows, "impact_amplification": amplification, "cage_motion": motion_rows,
        "power_loss": power_rows, "cage_strength": strength_rows}, indent=1, allow_nan=False,
        default=float) + "\n")
    return {"report": report, "html": page, "json": js, "plots": plots, "xdmf": xdmf,
            "stress_picture": picture, "series": series_out}


def _impact_amplification(t, arrays, scene, dt) -> list[dict]:
    """flexbearing.analysis.amplification.impact_amplification for the run's impacts (data of `read_run`; [] without
    impacts, contact stresses or a readable scene, or where the quasi-static solve refuses the instant)."""
    if scene is None or len(scene.impacts) == 0 or "outer_contact_stress" not in arrays:
        return []
    from flexbearing.analysis.amplification import impact_amplification
    try:
        return impact_amplification(scene, t, arrays)
    except InputError:
        return []


def _amplification_table(items) -> str:
    lines = ["| impact | Fr at peak (kN) | outer p0 quasi-static (MPa) | outer p0 run (MPa) | amplification | "
             "inner p0 quasi-static (MPa) | inner p0 run (MPa) | amplification | t_d/T_n | one-DOF estimate |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for a in items:
        cells = [a["label"], f"{math.hypot(a['load'][1], a['load'][2]) / 1e3:.1f}"]
        for key in ("outer_contact_stress", "inner_contact_stress"):
            cells += [f"{a[f'quasi_static_{key}'] / 1e6:,.0f}",
                      f"{a[f'dynamic_{key}'] / 1e6:,.0f}" if f"dynamic_{key}" in a else "–",
                      f"{a[f'{key}_amplification']:.4f}" if f"{key}_amplification" in a else "–"]
        cells += [f"{a['duration_over_period']:.3g}" if "duration_over_period" in a else "–",
                  f"{a['one_dof_amplification']:.4f}" if "one_dof_amplification" in a else "–"]
        if not a["converged"]:
            cells[0] += " (quasi-static not converged)"
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)
