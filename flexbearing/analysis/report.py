"""`report.md`, `report.json` and `report.html` of a run: the tables, the plots and the cage's stress.

`write_report` assembles the report of a run (and of a run to compare with): the statistics per
phase and impact (flexbearing.analysis.windows, whose docstring defines the quantities and the peak, p99 and
mean), the cage's stress against its yield strength, the contact stress at each impact against the
quasi-static equilibrium (flexbearing.analysis.amplification), the cage's motion and the power loss; the plots
(flexbearing.analysis.plots); for a flexible cage the picture of the cage's von Mises field at the run's
maximum (flexbearing.analysis.stress_picture) and the field for ParaView at the peaks and, with a series
window, over it with the balls and the rings (flexbearing.analysis.field_export) and the ParaView scene
(flexbearing.analysis.paraview_state). Files stay SI; only the printed tables and the plot axes use the
engineer's units (MPa, N, µm, rpm, %) and say so. Command line: `flexbearing report`
(flexbearing.cli.report).

The page is a list of sections, SECTIONS: each a function of the Report (the run opened once, the
tables, the files written) returning Markdown lines; the summary block comes first
(flexbearing.analysis.summary), the inputs table last. A new section is a function added to the
list.
"""
from __future__ import annotations

import json
import math
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from contextlib import ExitStack

import numpy as np

from flexbearing.common.validation import InputError
from flexbearing.analysis.plots import caption, write_orbit_plot, write_plots
from flexbearing.simulation.results import Run
from flexbearing.analysis.windows import (MOTION_ROWS, QUANTITIES, QUANTITY, Quantity, cage_motion_rows, cage_strength_rows,
                              phase_rows, phase_table, power_loss_rows, read_motion, read_power, read_run,
                              report_windows, speed_phases, window_title)
from flexbearing.analysis import field_export
from flexbearing.analysis.summary import summary_rows, input_rows
from flexbearing.analysis.settling import MARK, MARK_NOTE, attach_settling, settling_signals, unsettled
from flexbearing.analysis.paraview_state import NEEDS, pvpython_command, write_paraview_scene
from flexbearing.analysis import paraview_state
from flexbearing.common.progress import Stages
from flexbearing.common.safe_files import OutputPlan
from flexbearing.analysis.html_page import write_html


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
    for label, name, qd in _stat_rows(keys):
        mark = f" {MARK}" if not name.endswith(f"_{qd.extreme_stat}") else ""
        cells = [label] + [_fmt(row.get(name), qd.scale) + (mark if unsettled(row) and row.get(name) is not None
                                                            else "") for _, row in columns]
        if increase_from is not None:
            a, b = columns[increase_from][1].get(name), columns[-1][1].get(name)
            if a is None or b is None:
                cells.append("–")
            elif qd.display_unit == "%":      # a signed ratio (slip): the difference, in points
                cells.append(f"{(b - a) * qd.scale:+.2f} points")
            else:
                cells.append(f"{100 * (b - a) / abs(a):+.1f} %" if a != 0 else "–")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _check_frames(run: Run, frames) -> None:
    """InputError if `frames` (--frames) is not 'auto' or times inside the run, or names times of a
    run without a flexible cage (whose von Mises field they would select)."""
    if frames is None or (isinstance(frames, str) and frames.strip() == "auto"):
        return
    field_export.parse_frames(frames, run.t, run.dt)
    if not run.flexible:
        raise InputError(f"--frames = {frames!r}: {run.path} has no flexible-cage field (rigid cage, no modal "
                         f"coordinates); --frames selects von Mises frames of a flexible-cage run")


@dataclass
class Report:
    """What the report's sections read: the run (and the run compared with), opened once, the
    tables computed from them and the files written beside the report. A section is a function
    Report -> list of Markdown lines (SECTIONS)."""
    run: Run
    compare: Run | None
    out_dir: Path
    settle: float
    series_spec: str | None
    rows: list[dict]                   # flexbearing.analysis.windows.phase_rows: whole run, phases, impacts
    cmp_rows: list[dict] | None
    keys: list[str]                    # the report quantities the run recorded
    amplification: list[dict]
    motion_rows: list[dict]
    power_rows: list[dict]
    strength_rows: list[dict]
    plots: list[Path]
    xdmf: Path | None = None
    xdmf_note: str = "not written: the run has no flexible-cage modal coordinates (rigid cage)."
    picture: Path | None = None
    picture_md: list[str] = field(default_factory=list)
    series: dict | None = None
    fatigue_md: list[str] = field(default_factory=list)


def title_section(r: Report) -> list[str]:
    return [f"# Run report: {r.run.name}", ""]


def summary_section(r: Report) -> list[str]:
    """The summary block: what was simulated, with what, by which program, and what came out."""
    return ["## Summary", "", "| item | value |", "|---|---|"] + [
        f"| {label} | {value} |" for label, value in summary_rows(r.run, r.rows, r.strength_rows, r.power_rows)] + [""]


def notes_section(r: Report) -> list[str]:
    """Where the numbers come from and what peak, p99 and mean mean."""
    rows, path = r.rows, r.run.path
    md = [f"- results file: `{path}` (status: {r.run.status}, cage: {r.run.cage_model}, "
          f"{rows[0]['n_samples'] if rows else 0} samples, {rows[0]['t_start'] if rows else 0:g}–"
          f"{rows[0]['t_end'] if rows else 0:g} s)"]
    if r.compare is not None:
        md.append(f"- compared with: `{r.compare.path}` ({r.compare.name})")
    settle = r.settle
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
    return md


def inputs_section(r: Report) -> list[str]:
    """The scene as the run read it, one row per input (the scene's TOML, flattened)."""
    scene = r.run.scene
    if scene is None:
        return ["## Inputs", "", "The run's scene could not be read from its results file.", ""]
    return (["## Inputs", "", f"The scene `{scene.path or scene.name}` as stored in the results file; "
             "every input it does not set is the paper preset's (flexbearing.multibody.bearing, "
             "flexbearing.simulation.scene).", "", "| input | value |", "|---|---|"]
            + [f"| `{k}` | {v} |" for k, v in input_rows(scene.data)] + [""])


def comparison_section(r: Report) -> list[str]:
    if not r.cmp_rows:
        return []
    a, b = r.compare.name, r.run.name
    return [f"## {a} vs {b} (whole runs)", "",
            _markdown_table([(a, r.cmp_rows[0]), (b, r.rows[0])], r.keys, increase_from=0), ""] + (
        [MARK_NOTE, ""] if unsettled(r.rows[0]) else [])


def phases_section(r: Report) -> list[str]:
    if not r.rows:
        return []
    md = [f"## {r.run.name}: per phase of the speed profile and per impact", "",
          _markdown_table([(window_title(w), w) for w in r.rows], r.keys), ""]
    if any(unsettled(w) for w in r.rows):
        md += [MARK_NOTE, ""]
    peaks = [(w["label"], w.get("von_mises_max_t_peak")) for w in r.rows[1:]
             if w.get("von_mises_max_t_peak") is not None]
    if peaks:
        md += ["Instants of maximum von Mises stress: " + "; ".join(f"{lab}: {tp:g} s" for lab, tp in peaks), ""]
    return md


def strength_section(r: Report) -> list[str]:
    if not r.strength_rows:
        return []
    ys = r.strength_rows[0]["yield_strength"]
    above = r.strength_rows[0]["intervals_above_yield"]
    return ["## Cage stress against the yield strength", "",
            _strength_markdown(r.strength_rows), "",
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


def amplification_section(r: Report) -> list[str]:
    if not r.amplification:
        return []
    return ["## Contact stress at the impacts against the quasi-static equilibrium", "",
            _amplification_table(r.amplification), "",
            "Quasi-static: flexbearing.multibody.quasi_static at the pulse's peak instant (speed and load of that instant, a "
            "ball on the load line, Jones's race control); run: the worst ball's peak from the start of the pulse to "
            "5 T_n after its end (a short pulse's largest response comes after it). Amplification = run / "
            "quasi-static (flexbearing.analysis.amplification). One-DOF estimate: the inner ring's mass on the bearing's secant "
            "radial stiffness from the load before the pulse to its peak, natural period T_n, and the undamped "
            "shock spectrum of the displacement under a half-sine pulse of duration t_d (the contact stress "
            "amplifies less: p0 grows as Q^(1/3)); near 1 when t_d >> T_n: the pulse is then quasi-static for the "
            "contacts, and the stress it adds is the static response to the larger load.", ""]


def motion_section(r: Report) -> list[str]:
    if not r.motion_rows:
        return []
    reference = r.motion_rows[0].get("centre_reference") or "the guide-land centre"
    return ["## Cage motion in the guide clearance", "",
            _motion_markdown(r.motion_rows), "",
            f"Cage centre relative to {reference}. "
            "From the recorded cage centre (its offset from the guiding ring's centre) and cage speed "
            "(flexbearing.analysis.cage_motion): e/Cg the eccentricity ratio (1 = on the guide rim); whirl ratio = the "
            "centre's net whirl angle over the cage's rotation angle in the window (> 0 forward; 1 synchronous "
            "whirl, 0.5 half-frequency whirl on the land film, near 0 a centre held at one azimuth by a "
            "static load); velocity dispersion = std/mean of the centre's speed, the stability index of "
            "Ghaisas, Wassgren & Sadeghi (2004): 0 for a steady circular whirl, of order 1 for the "
            "irregular, collision-driven motion of an unstable cage, but also for a whirl that decays to rest "
            "inside the window (a cage that settles at one azimuth after an impact): read it with the orbit, "
            "`cage_orbit.png`, and the time held: the share of samples whose centre moves slower than a "
            "half-frequency whirl at a tenth of the clearance would (a cage at rest at one azimuth).", ""]


def power_section(r: Report) -> list[str]:
    if not r.power_rows:
        return []
    return ["## Friction torque and power loss", "",
            _power_markdown(r.power_rows), "",
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


def compare_phases_section(r: Report) -> list[str]:
    if not r.cmp_rows or len(r.cmp_rows) <= 2:
        return []
    return [f"## {r.compare.name}: per phase", "",
            _markdown_table([(window_title(w), w) for w in r.cmp_rows], r.keys), ""]


def plots_section(r: Report) -> list[str]:
    """The figures, each with a caption that says what it draws (flexbearing.analysis.plots.caption)."""
    md = ["## Plots", ""]
    for p in r.plots:
        md += [f"![{caption(p)}]({p.name})", ""]
    return md


def stress_picture_section(r: Report) -> list[str]:
    return list(r.picture_md)


def paraview_section(r: Report) -> list[str]:
    md = ["## Cage von Mises field (ParaView)", "", f"Frames at the peaks: {r.xdmf_note}", "",
          field_export.series_markdown(r.series, r.series_spec), ""]
    pv = (r.series or {}).get("paraview")
    if pv:
        if pv.get("state"):
            cage = ("the cage warped by displacement_scaled and coloured by its von Mises stress in MPa over "
                    f"[0, {pv['recorded_max_mpa']:,.0f}] MPa (the largest maximum the run recorded in the "
                    "window), " if "recorded_max_mpa" in pv else "no cage (the run has no stress field), ")
            md += [f"The whole bearing in ParaView: `{Path(pv['state']).name}` (File > Load State; from another "
                   "folder tick \"Search files under specified directory\"): " + cage + "the balls, the rings "
                   "(the outer one cut away towards the camera), the camera at the azimuth of the window's "
                   f"stress maximum (without one: of the radial load), t = {pv['time']:.6g} s"
                   + (f"; movie `{Path(pv['movie']).name}`" if pv.get("movie") else "") + ".", ""]
        elif pv.get("note"):
            md += [pv["note"] + ".", ""]
    return md


# The report's stages with their wall times (s) for the demo's unsteady run against its steady one,
# series 0.29:0.31:4, 2 shared cores: the progress bar's estimate (flexbearing.common.progress)
REPORT_STAGES = {"series": 21.0, "ParaView scene": 54.0, "tables": 6.4, "plots": 29.5, "von Mises frames": 5.3,
                 "stress picture": 8.6, "fatigue": 83.0, "page": 0.4, "pdf": 4.3}
SERIES_STAGES = ("series", "ParaView scene")
FLEXIBLE_STAGES = ("von Mises frames", "stress picture")

def cage_fatigue_section(r: Report) -> list[str]:
    """The cage's fatigue at the run's duty cycle (flexbearing.analysis.fatigue_report), when asked."""
    return r.fatigue_md


# the files a report writes by these names (plots: *.png; the field export's: field_export.FIELD_FILES)
REPORT_FILES = ("report.md", "report.html", "report.json")
PDF_FILE = "report.pdf"          # flexbearing.analysis.pdf.print_pdf: the page's name, .pdf
PLOT_PATTERNS = ("*.png",)       # flexbearing.analysis.plots: one per quantity the run recorded
# flexbearing.analysis.cage_fatigue's FATIGUE_H5, FATIGUE_XDMF, FATIGUE_JSON (that module compiles
# numba kernels on import; tests/test_output_paths.py checks that these are its names)
FATIGUE_FILES = ("fatigue.h5", "fatigue.xdmf", "fatigue.json")


def report_outputs(run_h5, out_dir, compare=None, reduced_cage=None, command: str = "flexbearing report",
                   option: str = "-o") -> OutputPlan:
    """Every file write_report can write into out_dir (flexbearing.common.safe_files.OutputPlan),
    whatever the run and the options (a folder used for reports holds no input and no link at any
    of these names): the page (md, html, json, pdf), the plots (*.png), a flexible cage's von Mises
    frames and stress picture with its facts, a series' files and ParaView scene (its settings,
    state and movie), the fatigue files and picture. The inputs: the run, the run compared with
    and the reduced cage given. write_report writes through this plan: a file it did not declare
    is refused when the staged files are renamed into place."""
    from flexbearing.analysis import stress_picture, fatigue_picture
    plan = OutputPlan(command, inputs=[run_h5, compare, reduced_cage])
    names = list(REPORT_FILES) + [PDF_FILE]
    names += [field_export.PEAKS_XDMF, "von_mises.h5", "von_mises.json", stress_picture.PICTURE,
              Path(stress_picture.PICTURE).with_suffix(".json").name]
    names += [field_export.SERIES_CAGE, field_export.SERIES_POINTS, field_export.SERIES_RINGS,
              field_export.SERIES_H5, field_export.SERIES_JSON,
              paraview_state.SETTINGS, paraview_state.STATE, paraview_state.MOVIE]
    names += list(FATIGUE_FILES) + [fatigue_picture.PICTURE]
    plan.folder(out_dir, option, names=names, patterns=PLOT_PATTERNS)
    return plan


def _final_paths(obj, stage: Path, out_dir: Path):
    """obj with every path (Path or str) inside the staging folder `stage` moved to out_dir."""
    if isinstance(obj, dict):
        return {k: _final_paths(v, stage, out_dir) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return type(obj)(_final_paths(v, stage, out_dir) for v in obj)
    if isinstance(obj, (str, Path)):
        p = Path(obj)
        if p.parent == stage:
            return out_dir / p.name if isinstance(obj, Path) else str(out_dir / p.name)
    return obj

# The report, in page order: a section is a function Report -> Markdown lines ([] leaves it out).
SECTIONS = [title_section, summary_section, notes_section, comparison_section, phases_section,
            strength_section, amplification_section, motion_section, power_section,
            compare_phases_section, plots_section, stress_picture_section, cage_fatigue_section,
            paraview_section, inputs_section]


def write_report(run_h5, out_dir, compare=None, frames="auto", reduced_cage=None,
                 quiet: bool = True, settle: float = 0.0, series: str | None = None,
                 displacement_scale: float | None = None, sections=None, movie: bool = False,
                 pdf: bool = False, fatigue=None) -> dict:
    """Plots, the report (report.md, report.json), the same as one self-contained page with the
    plots embedded (report.html, flexbearing.analysis.html_page) and, for a flexible-cage run, the
    picture of the cage's stress field at the run's maximum and the von Mises XDMF frames; with
    `series` ("T0:T1[:N]") the ParaView time series of that window (flexbearing.analysis.field_export.
    write_series, written first: a bad window stops the report). The results files are opened
    once (flexbearing.simulation.results.Run) and handed to every reader. `sections`: the
    report's sections in page order (default SECTIONS). With a series and ParaView's pvpython
    installed, the ParaView scene bearing.pvsm (flexbearing.analysis.paraview_state) and, with `movie`,
    bearing.avi; with `pdf`, report.pdf printed by headless Chromium (flexbearing.analysis.pdf).
    fatigue: a flexbearing.analysis.cage_fatigue.FatigueSettings adds the cage's fatigue section
    (flexbearing.analysis.fatigue_report). Returns {"report", "html", "json", "plots", "xdmf",
    "stress_picture", "series", "paraview", "pdf", "fatigue"} (None where not written)."""

    t_start = time.perf_counter()
    if movie and series is None:
        raise InputError("--movie needs --series T0:T1[:N] (the window the movie shows)")
    if movie and pvpython_command() is None:
        raise InputError(f"--movie needs {NEEDS}")
    if pdf:
        from flexbearing.analysis.pdf import require_chromium
        require_chromium()
    with ExitStack() as stack:
        run = stack.enter_context(Run(run_h5))
        cmp = stack.enter_context(Run(compare)) if compare is not None else None
        _check_frames(run, frames)                  # a bad --frames stops the report before any file
        final_dir = Path(out_dir)
        # every file the report writes, checked before any work (the one output rule), then
        # written into a staging folder beside them and renamed into place when whole
        plan = report_outputs(run.path, final_dir, cmp.path if cmp is not None else None,
                              reduced_cage).check()
        stack.callback(plan.discard)                # an exception: nothing half-written lands
        out_dir = plan.staging(final_dir)
        say = (lambda *a: None) if quiet else (lambda *a: print(*a, file=sys.stderr))
        todo = {k: w for k, w in REPORT_STAGES.items()
                if (k not in SERIES_STAGES or series is not None) and (run.flexible or k not in FLEXIBLE_STAGES)
                and (k != "pdf" or pdf) and (k != "fatigue" or fatigue is not None)}
        step = stack.enter_context(Stages(f"report of {run.path.name}", todo, quiet))
        series_out = None
        if series is not None:
            step("series")
            series_out = field_export.write_series(run, out_dir, series, reduced_cage=reduced_cage,
                                                   displacement_scale=displacement_scale)
            step("ParaView scene")
            if pvpython_command() is not None:
                plan.commit()               # the state names the series files where they stay
                series_out = _final_paths(series_out, out_dir, final_dir)
                out_dir = plan.staging(final_dir)
            series_out["paraview"] = paraview = {"note": None}
            if pvpython_command() is None:
                paraview["note"] = f"bearing.pvsm not written: it needs {NEEDS}"
            else:
                paraview.update(write_paraview_scene(final_dir, movie=movie, out=out_dir))
        step("tables")
        data = read_run(run)
        rows = phase_rows(*data, True, settle)
        # settled before statistics: each uniform-speed phase tested (flexbearing.analysis.settling)
        t_run, _, scene_run, dt_run = data
        attach_settling(rows, [m for _, m in report_windows(t_run, scene_run, dt_run, True, settle)], t_run,
                        settling_signals(run.outputs), len(speed_phases(scene_run)) if scene_run is not None else 1)
        strength_rows = cage_strength_rows(*data, True, settle)
        r = Report(run=run, compare=cmp, out_dir=out_dir, settle=settle, series_spec=series, rows=rows,
                   cmp_rows=phase_table(cmp, settle=settle) if cmp is not None else None,
                   keys=[q.key for q in QUANTITIES if rows and f"{q.key}_mean" in rows[0]],
                   amplification=_impact_amplification(*data),
                   motion_rows=cage_motion_rows(*read_motion(run), True, settle),
                   power_rows=power_loss_rows(*read_power(run), True, settle),
                   strength_rows=strength_rows, plots=[], series=series_out)
        step("plots")
        r.plots = write_plots(run, out_dir, compare=cmp)
        orbit_png = write_orbit_plot(run, out_dir, settle=settle) if r.motion_rows else None
        if orbit_png is not None:
            r.plots.append(orbit_png)
        if run.flexible:
            step("von Mises frames")
            try:
                r.xdmf = field_export.write_von_mises_xdmf(run, out_dir, frames, reduced_cage=reduced_cage)
                r.xdmf_note = (f"`{r.xdmf.name}` (+ `{r.xdmf.with_suffix('.h5').name}`; frames in "
                               f"`{r.xdmf.with_suffix('.json').name}`)")
            except InputError as exc:
                r.xdmf_note = f"not written: {exc}"
                say(f"report: {r.xdmf_note}")
            step("stress picture")
            from flexbearing.analysis.stress_picture import picture_markdown, write_stress_picture
            try:
                r.picture, facts = write_stress_picture(run, out_dir, reduced_cage=reduced_cage, settle=settle,
                                                        yield_strength=strength_rows[0]["yield_strength"]
                                                        if strength_rows else None)
                r.picture_md = picture_markdown(r.picture, facts)
            except InputError as exc:
                r.picture_md = ["## Cage von Mises stress at the run's maximum", "", f"Not drawn: {exc}", ""]
                say(f"report: stress picture not drawn: {exc}")
        fatigue_facts, fatigue_files = None, {}
        if fatigue is not None:
            step("fatigue")
            from flexbearing.analysis.fatigue_report import fatigue_section
            r.fatigue_md, fatigue_facts, fatigue_files = fatigue_section(run.path, out_dir, fatigue, reduced_cage,
                                                                         quiet)
        step("page")
        md = []
        for section in (SECTIONS if sections is None else sections):
            md += section(r)
        report = out_dir / "report.md"
        report.write_text("\n".join(md))
        page = write_html(report)
        js = out_dir / "report.json"
        js.write_text(json.dumps({"run": str(run.path), "scene": run.name, "status": run.status, "units": {
            q.key: q.unit for q in QUANTITIES}, "phases": rows, "compare": str(cmp.path) if cmp else None,
            "compare_phases": r.cmp_rows, "impact_amplification": r.amplification, "cage_motion": r.motion_rows,
            "power_loss": r.power_rows, "cage_strength": strength_rows, "cage_fatigue": fatigue_facts,
            "report_wall_time_s": time.perf_counter() - t_start}, indent=1, allow_nan=False,
            default=float) + "\n")
        pdf_path = None
        if pdf:
            step("pdf")
            from flexbearing.analysis.pdf import print_pdf
            pdf_path = print_pdf(page)
        plan.commit()
        step(None)
    return _final_paths({"report": report, "html": page, "json": js, "plots": r.plots, "xdmf": r.xdmf,
                         "stress_picture": r.picture, "series": series_out,
                         "paraview": None if series_out is None else series_out["paraview"], "pdf": pdf_path,
                         "fatigue": fatigue_files or None}, out_dir, final_dir)


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
