"""The report's figures: time histories of the quantities, the speed, an overview, the cage's orbit.

Read from the run's results file; each figure marks the phases of the speed profile and the impacts
(flexbearing.analysis.windows), SI values drawn in the engineer's units (MPa, N, µm, rpm, %) that the axes name.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from flexbearing.simulation.results import Run, opened
from flexbearing.analysis.windows import (QUANTITIES, QUANTITY, RPM_PER_RAD_S, envelope, impact_windows, quantity_arrays,
                              read_motion, report_windows, speed_phases, window_title)
from flexbearing.analysis.cage_motion import normalised_orbit


def _run_data(run: Run) -> dict:
    speed = {k: run.outputs[k][...] for k in ("inner_ring_speed", "cage_speed", "nominal_cage_speed")
             if k in run}
    scene = run.scene
    phases = speed_phases(scene) if scene is not None else []
    impacts = impact_windows(scene) if scene is not None else []
    return {"t": run.t, "arrays": quantity_arrays(run.outputs), "speed": speed, "phases": phases,
            "impacts": impacts, "name": run.name, "status": run.status, "cage_model": run.cage_model,
            "path": run.path}


PHASE_MARKS = ("phases of the speed profile shaded and labelled with their speeds; impacts marked "
               "at their load peaks (red dashed, I1, I2, ...)")


def caption(png: Path) -> str:
    """What a figure of `write_plots` / `write_orbit_plot` draws, by its file name (the report's
    figure captions)."""
    key = Path(png).stem
    if key == "speed":
        return ("Speeds against time, rpm: the inner ring (prescribed profile), the cage and the cage's "
                f"no-slip (epicyclic) speed n_m; {PHASE_MARKS}.")
    if key == "overview":
        return f"Overview: the speeds and every reported quantity against time, one panel each; {PHASE_MARKS}."
    if key == "cage_orbit":
        return ("Cage-centre orbit in the guide clearance, one panel per phase of the speed profile: the "
                "centre's offset from the guiding ring's centre (named in the report's cage-motion section) over the radial guide clearance Cg (the dashed "
                "circle is the guide rim, e = Cg), samples inside impact windows in red; below, the "
                "eccentricity ratio e/Cg against time.")
    if key in QUANTITY:
        qd = QUANTITY[key]
        which = ("the worst ball at each sample (blue: "
                 + ("the smallest over the balls" if qd.extreme == "min" else "the largest over the balls")
                 + ") and ball 1 (orange)") if qd.per_ball else "one value per sample"
        return f"{qd.label} against time, {qd.display_unit}: {which}; {PHASE_MARKS}."
    return key


def plot_style():
    """matplotlib (Agg) with the report's style."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({"font.size": 9, "axes.titlesize": 10, "axes.labelsize": 9,
                         "legend.fontsize": 7.5, "xtick.direction": "in", "ytick.direction": "in",
                         "xtick.top": True, "ytick.right": True, "axes.grid": True,
                         "grid.alpha": 0.25, "grid.linewidth": 0.5, "savefig.dpi": 150,
                         "lines.linewidth": 0.9})
    return plt


def _decorate(ax, data, small=False):
    """Shade and label the phases of the speed profile, mark the impact instants."""
    import matplotlib.transforms as mtransforms
    trans = mtransforms.blended_transform_factory(ax.transData, ax.transAxes)
    fs = 6 if small else 7
    for i, ph in enumerate(data["phases"]):
        if len(data["phases"]) > 1 and i % 2 == 0:
            ax.axvspan(ph["t_start"], ph["t_end"], color="0.5", alpha=0.08, lw=0, zorder=0)
        if len(data["phases"]) > 1 or not small:
            kind = ph["kind"].replace("uniform speed", "uniform")
            rpm = (f"{ph['speed_start_rpm']:,.0f} rpm" if ph["kind"] == "uniform speed" else
                   f"{ph['speed_start_rpm']:,.0f}→{ph['speed_end_rpm']:,.0f} rpm")
            ax.text(0.5 * (ph["t_start"] + ph["t_end"]), 0.985, f"{kind}\n{rpm}", transform=trans,
                    ha="center", va="top", fontsize=fs, color="0.25", zorder=5,
                    bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none", alpha=0.7))
        if i > 0:
            ax.axvline(ph["t_start"], color="0.55", lw=0.6, ls="-", zorder=1)
    for j, imp in enumerate(data["impacts"]):
        ax.axvline(imp["t_peak"], color="tab:red", lw=0.8, ls=(0, (3, 2)), zorder=1,
                   label="impact (load peak)" if j == 0 else None)
        ax.text(imp["t_peak"], 0.02, f" I{j + 1}", transform=trans, color="tab:red", fontsize=fs,
                ha="left", va="bottom")
    if data["t"].size:
        ax.set_xlim(float(data["t"][0]), float(data["t"][-1]))


def _plot_quantity(ax, key, data, compare, small=False):
    qd = QUANTITY[key]
    a = data["arrays"][key]
    t = data["t"]
    if compare is not None and key in compare["arrays"]:
        ax.plot(compare["t"], envelope(key, compare["arrays"][key]) * qd.scale, color="0.6", lw=0.7,
                label=f"{compare['name']}: worst ball" if qd.per_ball else compare["name"], zorder=2)
    if qd.per_ball:
        # ball 1 on top: the paper's curves follow one ball (its contact stress oscillates as it
        # orbits through the load zone), the envelope is the worst ball at each instant
        ax.plot(t, a[:, 0] * qd.scale, color="tab:orange", lw=0.5, alpha=0.85, label=f"{data['name']}: ball 1",
                zorder=5)
        ax.plot(t, envelope(key, a) * qd.scale, color="tab:blue", lw=0.9, zorder=4,
                label=f"{data['name']}: worst ball")
    else:
        ax.plot(t, a[:, 0] * qd.scale, color="tab:blue", lw=0.9, label=data["name"], zorder=4)
    _decorate(ax, data, small)
    ax.set_ylabel(f"{qd.label} ({qd.display_unit})" if not small else f"{qd.label}\n({qd.display_unit})")
    # headroom for the phase labels
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo, hi + 0.22 * (hi - lo))


def _plot_speed(ax, data, compare, small=False):
    sp = data["speed"]
    if compare is not None and "inner_ring_speed" in compare["speed"]:
        ax.plot(compare["t"], compare["speed"]["inner_ring_speed"] * RPM_PER_RAD_S, color="0.6", lw=0.7,
                label=f"{compare['name']}: inner ring")
    if "inner_ring_speed" in sp:
        ax.plot(data["t"], sp["inner_ring_speed"] * RPM_PER_RAD_S, color="k", lw=1.0, label="inner ring")
    if "cage_speed" in sp:
        ax.plot(data["t"], sp["cage_speed"] * RPM_PER_RAD_S, color="tab:blue", lw=0.8, label="cage")
    if "nominal_cage_speed" in sp:
        ax.plot(data["t"], sp["nominal_cage_speed"] * RPM_PER_RAD_S, color="tab:blue", lw=0.8,
                ls="--", label="cage, no slip (n_m)")
    _decorate(ax, data, small)
    ax.set_ylabel("Speed (rpm)")
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo, hi + 0.22 * (hi - lo))


def write_plots(run: Run | str, out_dir, compare: Run | str | None = None) -> list[Path]:
    """One PNG per recorded quantity (time history, phases shaded and labelled, impacts marked;
    the `compare` run overlaid in grey), speed.png, and overview.png with all of them (`caption`
    says what each draws). run, compare: open Runs or paths."""
    with opened(run) as r:
        data = _run_data(r)
    cmp_data = None
    if compare is not None:
        with opened(compare) as c:
            cmp_data = _run_data(c)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    plt = plot_style()
    keys = [q.key for q in QUANTITIES if q.key in data["arrays"]]
    written = []
    title = f"{data['name']} ({data['cage_model']} cage)" + (f" vs {cmp_data['name']}" if cmp_data else "")
    if data["status"] and data["status"] != "complete":
        title += f" — run status: {data['status']}"
    if data["speed"]:
        fig, ax = plt.subplots(figsize=(7.0, 3.6), layout="constrained")
        _plot_speed(ax, data, cmp_data)
        ax.set_xlabel("Time (s)")
        ax.set_title(title)
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False)
        written.append(out_dir / "speed.png")
        fig.savefig(written[-1])
        plt.close(fig)
    for key in keys:
        fig, ax = plt.subplots(figsize=(7.0, 3.6), layout="constrained")
        _plot_quantity(ax, key, data, cmp_data)
        ax.set_xlabel("Time (s)")
        ax.set_title(title)
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False)
        written.append(out_dir / f"{key}.png")
        fig.savefig(written[-1])
        plt.close(fig)
    panels = (["speed"] if data["speed"] else []) + keys
    if panels:
        ncol = 2 if len(panels) > 3 else 1
        nrow = math.ceil(len(panels) / ncol)
        height = 2.3 * nrow + 1.1
        fig, axes = plt.subplots(nrow, ncol, figsize=(11.0, height), sharex=True, squeeze=False)
        for ax, key in zip(axes.flat, panels):
            if key == "speed":
                _plot_speed(ax, data, cmp_data, small=True)
            else:
                _plot_quantity(ax, key, data, cmp_data, small=True)
        for ax in axes.flat[len(panels):]:
            ax.set_visible(False)
        for ax in axes[-1]:
            ax.set_xlabel("Time (s)")
        if len(panels) % ncol:
            axes[-2, -1].xaxis.set_tick_params(labelbottom=True)
            axes[-2, -1].set_xlabel("Time (s)")
        handles, labels = [], []
        for ax in axes.flat[:len(panels)]:
            for h, lab in zip(*ax.get_legend_handles_labels()):
                if lab not in labels:
                    handles.append(h)
                    labels.append(lab)
        fig.suptitle(title)
        # matplotlib 3.6: constrained layout ignores figure legends, so reserve the strip by hand
        fig.tight_layout(rect=(0.0, 0.65 / height, 1.0, 1.0 - 0.1 / height))
        fig.legend(handles, labels, loc="lower center", ncol=min(len(labels), 4), fontsize=7.5,
                   frameon=False)
        written.append(out_dir / "overview.png")
        fig.savefig(written[-1])
        plt.close(fig)
    return written


def write_orbit_plot(run: Run | str, out_dir, settle: float = 0.0) -> Path | None:
    """cage_orbit.png: the cage centre in units of the guide clearance (the rim is the unit circle),
    one panel per phase of the speed profile, samples inside impact windows in red; below, the
    eccentricity ratio against time. None when the run did not record the cage orbit."""
    motion, scene, dt = read_motion(run)
    if motion is None or motion["t"].size == 0:
        return None
    t = motion["t"]
    xy = normalised_orbit(motion["centre_yz"], motion["eccentricity_ratio"])
    windows = report_windows(t, scene, dt, True, settle)
    panels = [w for w in windows if w[0]["kind"] not in ("run", "impact")] or windows[:1]
    in_impact = np.zeros(t.size, dtype=bool)
    for head, mask in windows:
        if head["kind"] == "impact":
            in_impact |= mask
    plt = plot_style()
    n = len(panels)
    fig = plt.figure(figsize=(max(3.3 * n, 6.0), 5.6), layout="constrained")
    grid = fig.add_gridspec(2, n, height_ratios=(3.0, 1.3))
    circle = np.linspace(0.0, 2.0 * np.pi, 361)
    lim = max(1.05, float(np.nanmax(np.abs(xy))) * 1.05 if xy.size else 1.05)
    for i, (head, mask) in enumerate(panels):
        ax = fig.add_subplot(grid[0, i])
        ax.plot(np.cos(circle), np.sin(circle), color="0.3", lw=0.8, ls="--", label="guide rim (e = Cg)")
        ax.plot(xy[mask, 0], xy[mask, 1], color="tab:blue", lw=0.5, label="cage centre")
        hit = mask & in_impact
        if hit.any():
            ax.plot(xy[hit, 0], xy[hit, 1], ".", color="tab:red", ms=1.5, label="during an impact")
        ax.set_aspect("equal")
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_xlabel("y / Cg")
        if i == 0:
            ax.set_ylabel("z / Cg")
        ax.set_title(window_title(head), fontsize=8)
    ax = fig.add_subplot(grid[1, :])
    ax.plot(t, motion["eccentricity_ratio"], color="tab:blue", lw=0.7)
    ax.axhline(1.0, color="0.3", lw=0.8, ls="--")
    ax.set_xlabel("Time (s)")
    ax.set_ylabel("e / Cg")
    ax.set_xlim(float(t[0]), float(t[-1]))
    fig.axes[0].legend(loc="lower left", fontsize=6, framealpha=0.8)
    out = Path(out_dir) / "cage_orbit.png"
    fig.savefig(out)
    plt.close(fig)
    return out
