"""Trends of the paper's §4.4 parameter studies: ours against the directions the paper states.

Reads the study.json files that `flexbearing study scenes/study_<name>.toml -o out/study` wrote
and prints, per study and quantity, the whole-run peak, p99 and mean at each value, their change
from the first to the last value, the signs of the steps between values, and the direction the
paper's text gives (Yang, Liu & Deng 2025, §4.4.1–4.4.4; its figures' numbers are not available
here, so only directions are compared).

Verdict: a statistic has a trend when its Spearman rank correlation with the parameter is
|rho| >= 0.9 (rho = 1 - 6 sum d^2 / (n (n^2 - 1)), d the rank differences; Spearman 1904). With
five values and no ties that is a monotone sequence or one adjacent swap from it: 10 of the 120
orders, so a trendless statistic (every order equally likely) passes with probability 8.3 %,
4.2 % in each direction (counted in tests/test_study.py). It then agrees with the paper when it
has the paper's sign. "~flat" in the paper agrees with a change under 2 % first to
last; "rises, then falls" agrees when an inner value exceeds both ends by more than 1 %.

Noise: when out/study/tolerance_scatter/study.json exists (scenes/study_tolerance_scatter.toml:
the unsteady case at five integrator tolerances, each an equally valid solution), the spread of
each statistic over those runs, (max - min) / |mean|, is its numerical noise, shown in the column
"noise". A trend whose change first to last is not larger than that spread is "within noise",
whatever its rank correlation: the studies' statistics that depend on single ball–cage collisions
move that much between two correct integrations of the same scene.

    .venv/bin/python -m benchmarks.study_trends [--out out/study] [--md FILE]
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

# direction stated in the paper's text for each study: +1 rises, -1 falls, 0 "only slight
# variations", 2 "first increases and then decreases"
PAPER = {
    "axial_load": {"outer_contact_stress": +1, "inner_contact_stress": +1, "pocket_force": -1,
                   "guiding_force": -1, "von_mises_max": -1, "film_thickness_min": -1},
    "radial_load": {"outer_contact_stress": +1, "inner_contact_stress": +1, "pocket_force": +1,
                    "guiding_force": +1, "von_mises_max": +1, "film_thickness_min": 0},
    "speed": {"outer_contact_stress": +1, "inner_contact_stress": -1, "pocket_force": +1,
              "guiding_force": +1, "von_mises_max": +1, "film_thickness_min": +1},
    "groove_curvature": {"outer_contact_stress": +1, "inner_contact_stress": +1, "pocket_force": +1,
                         "guiding_force": +1, "von_mises_max": +1, "film_thickness_min": 2},
}
SECTION = {"axial_load": "§4.4.1, Figs. 23–25", "radial_load": "§4.4.2, Figs. 26–28",
           "speed": "§4.4.3, Figs. 29–31", "groove_curvature": "§4.4.4, Figs. 32–34"}
ARROW = {+1: "rises", -1: "falls", 0: "~flat", 2: "rises, then falls"}


def noise_levels(result: dict) -> dict:
    """Spread of every whole-run statistic over the runs of the tolerance-scatter study (module doc):
    {column: (max - min) / |mean|}, and for the cage motion {cage_<key>_abs: max - min}."""
    out = {}
    first = result["runs"][0]["windows"][0]
    for col in first:
        vals = [r["windows"][0].get(col) for r in result["runs"]]
        if col in ("window", "label", "kind") or any(not isinstance(v, (int, float)) for v in vals):
            continue
        if col.startswith("cage_"):
            out[f"{col}_abs"] = max(vals) - min(vals)
        elif np.mean(vals) != 0.0:
            out[col] = (max(vals) - min(vals)) / abs(float(np.mean(vals)))
    return out


def trend_lines(result: dict, name: str, noise: dict | None = None) -> list[str]:
    from flexbearing.analysis.windows import MOTION_ROWS, QUANTITY
    study = result["study"]
    runs = result["runs"]
    x = [r["parameter"] for r in runs]
    lines = [f"## {name} ({SECTION.get(name, '')}): {study['description']}", "",
             f"{study['label']}: {', '.join(f'{v:g}' for v in x)} {study['unit']}".rstrip(), "",
             "| quantity | statistic | values (whole run, after the settle time) | first → last | steps "
             "| noise | paper | verdict |",
             "|---|---|---|---:|---|---:|---|---|"]
    for key, paper in PAPER.get(name, {}).items():
        q = QUANTITY[key]
        for stat in q.stats:
            col = f"{key}_{stat}"
            vals = [r["windows"][0].get(col) for r in runs]
            if any(v is None for v in vals):
                continue
            change = (vals[-1] - vals[0]) / abs(vals[0]) * 100.0 if vals[0] else float("nan")
            cells = ", ".join(f"{v * q.scale:.4g}" for v in vals)
            steps = " ".join("+" if b > a else "−" if b < a else "0" for a, b in zip(vals, vals[1:]))
            spread = (noise or {}).get(col)
            v = verdict(x, vals, paper)
            if spread is not None and paper != 0 and abs(change) <= 100.0 * spread:
                v = "within noise"
            lines.append(f"| {q.label} [{q.display_unit}] | {stat} | {cells} | {change:+.1f} % | {steps} | "
                         f"{'–' if spread is None else f'{100 * spread:.1f} %'} | {ARROW[paper]} | {v} |")
    # the cage's motion, which the paper does not state: what explains the cage-force trends
    for label, key, scale, fmt in MOTION_ROWS:
        if key not in ("eps_mean", "whirl_ratio", "velocity_dispersion", "held_fraction"):
            continue
        vals = [r["windows"][0].get(f"cage_{key}") for r in runs]
        if any(v is None for v in vals):
            continue
        steps = " ".join("+" if b > a else "−" if b < a else "0" for a, b in zip(vals, vals[1:]))
        spread = (noise or {}).get(f"cage_{key}_abs")
        lines.append(f"| Cage motion: {label} | whole run | {', '.join(fmt.format(v * scale) for v in vals)} | "
                     f"{fmt.format((vals[-1] - vals[0]) * scale)} (difference) | {steps} | "
                     f"{'–' if spread is None else fmt.format(spread * scale) + ' (range)'} | – | – |")
    lines.append("")
    return lines


def verdict(x, vals, paper: int) -> str:
    """"agrees" / "disagrees" / "no trend" of a statistic against the paper's direction (module doc)."""
    from scipy.stats import spearmanr
    change = (vals[-1] - vals[0]) / abs(vals[0]) if vals[0] else float("nan")
    if paper == 0:
        return "agrees" if abs(change) < 0.02 else "disagrees"
    if paper == 2:
        inner = max(vals[1:-1])
        return "agrees" if inner > max(vals[0], vals[-1]) * 1.01 else "disagrees"
    rho = float(spearmanr(x, vals)[0])
    if not abs(rho) >= 0.9 - 1e-9:        # one adjacent swap of five gives rho = 0.9 to rounding
        return "no trend"
    return "agrees" if (rho > 0) == (paper > 0) else "disagrees"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="out/study", help="folder the studies were written to")
    ap.add_argument("--md", help="also write the tables to this Markdown file")
    a = ap.parse_args(argv)
    lines = []
    scatter = Path(a.out) / "tolerance_scatter" / "study.json"
    noise = noise_levels(json.loads(scatter.read_text())) if scatter.is_file() else None
    for name in PAPER:
        f = Path(a.out) / name / "study.json"
        if f.is_file():
            lines += trend_lines(json.loads(f.read_text()), name, noise)
    text = "\n".join(lines)
    print(text)
    if a.md:
        Path(a.md).write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
