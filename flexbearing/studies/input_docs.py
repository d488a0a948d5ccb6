"""docs/scene.md, generated: every key of every scene, study and unknowns-file table with its unit,
meaning, default (or derivation rule) and allowed range.

    python -m flexbearing.studies.input_docs > docs/scene.md

The keys come from the tables the validation itself checks against
(flexbearing.simulation.scene.SCENE_TABLES, flexbearing.studies.study.STUDY_KEYS,
flexbearing.studies.uncertainty.UNKNOWNS_HEAD_KEYS / UNKNOWN_KEYS / UNKNOWN_LIMITS); the words from
flexbearing.simulation.scene_keys.SPEC and the tables below. A key without its line is an error here,
and tests/test_scene_docs.py compares the page with a fresh generation, so the page cannot fall
behind the code.
"""
from __future__ import annotations

import sys

from flexbearing.simulation.derived import FIT_TEMPERATURE_WINDOW_C, LAND_CLEARANCE_RATIO
from flexbearing.simulation.scene import SCENE_TABLES
from flexbearing.simulation.scene_keys import SPEC, KeySpec as K
from flexbearing.studies.study import STUDY_KEYS
from flexbearing.studies.uncertainty import MIN_POINTS, UNKNOWN_KEYS, UNKNOWN_LIMITS, UNKNOWNS_HEAD_KEYS

STUDY_SPEC = {
    "name": K("", "the study's name (its folder under -o)", "required", "a file name"),
    "description": K("", "free text", '""', "a string"),
    "scene": K("", "the base scene, relative to the study file", "required", "an existing scene file"),
    "keys": K("", 'dotted scene keys to set ("operation.load.axial_load"; [i] indexes a list)', "required",
              "keys of the scene tables above"),
    "values": K("", "one run each: a scalar (every key takes it) or a list with one value per key", "required",
                "values each key accepts"),
    "label": K("", "the parameter's name in tables and plots", "the first key", "a string"),
    "unit": K("", "SI unit of the values", '""', "a string"),
    "display_unit": K("", "printed unit", "= unit", "a string"),
    "display_scale": K("", "factor from SI to display_unit", "1", "> 0"),
    "settle": K("s", "start-up left out of every statistic", "0", "[0, each run's duration)"),
}
UNKNOWNS_HEAD_SPEC = {
    "name": K("", "the study's name", "the file's stem", "a string"),
    "description": K("", "free text", '""', "a string"),
    "points": K("", "sample points", str(MIN_POINTS), f"integer >= {MIN_POINTS}"),
    "seed": K("", "random seed", "0", "integer >= 0"),
}
UNKNOWN_SPEC = {
    "kind": K("", "the distribution", "required", '"uniform" | "log_uniform" | "choice"'),
    "lo": K("the unknown's", "lower end", "required (not for choice)", "inside the unknown's limits"),
    "hi": K("the unknown's", "upper end", "required (not for choice)", ">= lo, inside the limits"),
    "values": K("", "choice: the values", "required for choice", "distinct allowed names"),
    "nominal": K("the unknown's", "the nominal value", "the range's middle", "inside [lo, hi]"),
    "unit": K("", "must be the model's unit (below)", "the model's", "the model's unit"),
    "reason": K("", "why this range (paper, assumption, practice)", "required", "a non-empty string"),
}

HEAD = f"""# Scene, study and unknowns files: every key

Generated from the code by `python -m flexbearing.studies.input_docs > docs/scene.md` (do not edit
by hand: tests/test_scene_docs.py regenerates it and fails when it differs). SI units throughout
except inner-ring speeds (rpm, in the key's name) and temperatures (°C, `_c`).

**Given, derived or refused.** A value a scene does not give is *derived* by the stated rule from
the bearing's own geometry (or measured from a CAD cage's faces), a dimensionless paper ratio is
kept as a *default*, or the scene is *refused* in one line naming the key to give
(flexbearing.simulation.derived). Every derived and default value is printed at run start and in
the report's summary as `derived: <key> = <value> from <rule>`. The land the cage does not ride on is
not checked against the cage. Land clearance rule: {100 * LAND_CLEARANCE_RATIO:.4f} % of the cage
diameter it guides (the paper's assumed 0.75 mm on 178.45 mm). The traction law follows the oil: the
paper's 4106 fit for the 4106 oil at {FIT_TEMPERATURE_WINDOW_C[0]:g}–{FIT_TEMPERATURE_WINDOW_C[1]:g} °C,
the EHL film-shear law otherwise; choosing the fit elsewhere gives one warning (log and report).

A bearing other than the paper's gives at least `bore_diameter`, `outside_diameter`, `width`,
`ball_diameter`, `n_balls` and its contact angle (`free_contact_angle`, or the clearance); see
`scenes/catalogue_7014_rigid.toml`. What it did not give, as `flexbearing run` prints it:

```python
from flexbearing.simulation.scene import load_scene
from flexbearing.simulation.derived import run_start_lines

scene = load_scene("scenes/catalogue_7014_rigid.toml")
print("\\n".join(run_start_lines(scene)))
c = scene.bearing.cage
assert abs(c.land_width - c.width / 2) < 1e-15          # the cage's own land width, not the paper's 14.15 mm
assert abs(scene.bearing.pitch_diameter - 0.5 * (70e-3 + 110e-3)) < 1e-15
assert scene.model_options["traction_law"] == "ehl"      # the 4106 oil at 100 °C: outside the fit's 15–25 °C
```
"""


def _table(title: str, keys, spec: dict, note: str = "") -> list[str]:
    missing = [k for k in keys if k not in spec]
    if missing:
        raise KeyError(f"[{title}]: keys {missing} have no line in the key table "
                       f"(flexbearing.simulation.scene_keys.SPEC or flexbearing.studies.input_docs)")
    out = [f"## [{title}]", ""] + ([note, ""] if note else [])
    out += ["| key | unit | meaning | default or rule | allowed |", "|---|---|---|---|---|"]
    for k in keys:
        s = spec[k]
        out.append("| `" + k + "` | " + " | ".join(x.replace("|", "\\|") for x in (s.unit, s.meaning, s.default,
                                                                                   s.allowed)) + " |")
    return out + [""]


SCENE_TITLES = {"scene": ("top level of a scene file", ""),
                "material": ("bearing.ball_material], [bearing.ring_material], [cage.material",
                             "A material table (replaces the named preset's constants key by key).")}


def markdown() -> str:
    lines = [HEAD, "# Scene files (`flexbearing run SCENE.toml`)", ""]
    for table, keys in SCENE_TABLES.items():
        title, note = SCENE_TITLES.get(table, (table, ""))
        lines += _table(title, keys, SPEC.get(table, {}), note)
    lines += ["# Study files (`flexbearing study STUDY.toml`)", ""]
    lines += _table("study", STUDY_KEYS, STUDY_SPEC)
    lines += ["# Unknowns files (`flexbearing uncertainty UNKNOWNS.toml`)", ""]
    lines += _table("study", UNKNOWNS_HEAD_KEYS, UNKNOWNS_HEAD_SPEC)
    names = ", ".join(f"`{n}` ({u}" + (f", [{lo:g}, {hi:g}])" if lo is not None else ")")
                      for n, (lo, hi, u) in UNKNOWN_LIMITS.items())
    lines += _table("unknowns.NAME", UNKNOWN_KEYS, UNKNOWN_SPEC,
                    f"One table per unknown of the model, every one required: {names}.")
    return "\n".join(lines).rstrip() + "\n"


if __name__ == "__main__":
    sys.stdout.write(markdown())
