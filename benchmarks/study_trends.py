"""Trends of the paper's §4.4 parameter studies: ours against the directions the paper states.

Reads the study.json files that `flexbearing study scenes/study_<name>.toml -o out/study` wrote
and prints, per study and quantity, the whole-run peak and mean at each value, their change from
the first to the last value, and the direction the paper's text gives (Yang, Liu & Deng 2025,
§4.4.1–4.4.4; its figures' numbers are not available here, so only directions are compared).

    .venv/bin/python -m benchmarks.study_trends [--out out/study] [--md FILE]
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

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


def trend_lines(result: dict, name: str) -> list[str]:
    from coupling.report import QUANTITY
    study = result["study"]
    runs = result["runs"]
    x = [r["parameter"] for r in runs]
    lines = [f"## {name} ({SECTION.get(name, '')}): {study['description']}", "",
             f"{study['label']}: {', '.join(f'{v:g}' for v in x)} {study['unit']}".rstrip(), "",
             "| quantity | statistic | values (whole run, after the settle time) | first → last | paper |",
             "|---|---|---|---:|---|"]
    for key, paper in PAPER.get(name, {}).items():
        q = QUANTITY[key]
        for stat in (q.extreme_stat, "mean"):
            col = f"{key}_{stat}"
            vals = [r["windows"][0].get(col) for r in runs]
            if any(v is None for v in vals):
                continue
            change = (vals[-1] - vals[0]) / abs(vals[0]) * 100.0 if vals[0] else float("nan")
            cells = ", ".join(f"{v * q.scale:.4g}" for v in vals)
            lines.append(f"| {q.label} [{q.display_unit}] | {stat} | {cells} | {change:+.1f} % | "
                         f"{ARROW[paper]} |")
    lines.append("")
    return lines


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="out/study", help="folder the studies were written to")
    ap.add_argument("--md", help="also write the tables to this Markdown file")
    a = ap.parse_args(argv)
    lines = []
    for name in PAPER:
        f = Path(a.out) / name / "study.json"
        if f.is_file():
            lines += trend_lines(json.loads(f.read_text()), name)
    text = "\n".join(lines)
    print(text)
    if a.md:
        Path(a.md).write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
