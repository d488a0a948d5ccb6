"""The race-control brackets of a test series' points, and the bracket tables of
docs/validation_sources.md (`python3 -m flexbearing.studies.validation.brackets` prints them).

A point's brackets are the cage speeds under pure inner- and pure outer-race control
(flexbearing.studies.validation.kinematics) at the free contact angle, or at the measured operating
angles where the source gives them; the series' geometry unknowns are swept over the corners of
their box, so each bracket is a range.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexbearing.common.validation import InputError
from flexbearing.studies.validation.kinematics import CONTROLS, brackets, split_for_slip
from flexbearing.studies.validation.series_file import Point, ValidationSeries, load_all

@dataclass(frozen=True)
class BracketRange:
    """Brackets of one point over the box of the geometry unknowns (min, max of each)."""
    point_id: str
    speed_rpm: float
    angle_case: str                      # "free" or "measured"
    inner_rpm: tuple[float, float]
    outer_rpm: tuple[float, float]
    epicyclic_rpm: tuple[float, float]   # at the free contact angle
    inner_slip_percent: tuple[float, float]
    outer_slip_percent: tuple[float, float]
    geometry_known: bool                 # False: the ranges span the declared unknowns


def _span(vs: ValidationSeries, key: str) -> tuple[float, float]:
    q = vs.bearing.get(key)
    if q is not None and q.value is not None:
        return (q.value, q.value)
    u = vs.unknown(key)
    if u is not None:
        return (u.low, u.high)
    if q is not None:
        return q.span()
    raise InputError(f"{vs.path.name}: bearing.{key} = None: neither given nor declared in [[unknowns]]")


def point_brackets(vs: ValidationSeries, point: Point, angle_case: str = "free") -> BracketRange | None:
    """Inner-/outer-control cage speeds of a point at the free contact angle (both contacts), or
    at the measured operating angles (``angle_case = "measured"``: needs measured inner and
    outer contact angles, else None). Geometry unknowns are swept over their corners."""
    if angle_case not in ("free", "measured"):
        raise InputError(f"angle_case = {angle_case!r}: allowed values ('free', 'measured')")
    speed_lo, speed_hi = point.conditions["speed_rpm"].span()
    if speed_lo != speed_hi:
        return None
    n = speed_lo
    dms, ds, a0s = _span(vs, "pitch_diameter"), _span(vs, "ball_diameter"), _span(vs, "free_contact_angle_deg")
    if angle_case == "measured":
        mi, mo = point.measured.get("measured_inner_contact_angle_deg"), point.measured.get(
            "measured_outer_contact_angle_deg")
        if mi is None or mo is None or mi.value is None or mo.value is None:
            return None
    res = {"i": [], "o": [], "e": [], "si": [], "so": []}
    for dm in sorted(set(dms)):
        for d in sorted(set(ds)):
            for a0 in sorted(set(a0s)):
                ai, ao = (a0, a0) if angle_case == "free" else (mi.value, mo.value)
                br = brackets(n, d, dm, ai, ao, reference_angle_deg=a0)
                res["i"].append(br.inner.cage_speed_rpm)
                res["o"].append(br.outer.cage_speed_rpm)
                res["e"].append(br.epicyclic_rpm)
                res["si"].append(br.inner_slip_percent)
                res["so"].append(br.outer_slip_percent)
    mm = {k: (float(np.min(v)), float(np.max(v))) for k, v in res.items()}
    known = len(set(dms)) == len(set(ds)) == len(set(a0s)) == 1
    return BracketRange(point.id, n, angle_case, mm["i"], mm["o"], mm["e"], mm["si"], mm["so"], known)


def _fmt_span(lo_hi: tuple[float, float], digits: int = 0) -> str:
    lo, hi = (0.0 if abs(v) < 0.5 * 10 ** (-digits) else v for v in lo_hi)
    if abs(hi - lo) <= 10 ** (-digits) / 2:
        return f"{lo:.{digits}f}"
    return f"{lo:.{digits}f}–{hi:.{digits}f}"


def bracket_table(vs: ValidationSeries) -> str:
    """Markdown table: per point the measured cage speed/slip and the two brackets at the free
    contact angle (and at measured operating angles where the source gives them), plus the
    symmetric contact-angle split each bracket would need to reproduce a measured slip."""
    head = ("| point | speed, rpm | measured | inner-control n_c, rpm (slip %) | "
            "outer-control n_c, rpm (slip %) | split for inner / outer control, deg |\n"
            "|---|---|---|---|---|---|\n")
    rows = []
    for p in vs.points:
        meas = []
        for key, q in p.measured.items():
            meas.append(f"{key.removeprefix('measured_')} = {q.value if q.value is not None else q.span()}")
        meas_s = "; ".join(meas) if meas else "not readable"
        br = point_brackets(vs, p, "free")
        slip = p.measured.get("measured_cage_slip_percent")
        if br is not None and slip is not None and slip.value is not None:
            n_r = tuple(e * (1.0 - slip.value / 100.0) for e in br.epicyclic_rpm)
            meas_s += f" (n_c = {_fmt_span(n_r)} rpm over the unknowns)"
        if br is None:
            rows.append(f"| {p.id} | {_fmt_span(p.conditions['speed_rpm'].span())} | {meas_s} | "
                        "— (speed only bounded) | — | — |")
            continue
        split = "—"
        if slip is not None and slip.value is not None:
            res = {}
            for control in CONTROLS:
                vals = []
                for dm in sorted(set(_span(vs, "pitch_diameter"))):
                    for d in sorted(set(_span(vs, "ball_diameter"))):
                        for a0 in sorted(set(_span(vs, "free_contact_angle_deg"))):
                            vals.append(split_for_slip(br.speed_rpm, d, dm, a0, slip.value, control))
                ok = [v for v in vals if v is not None]
                res[control] = ("none" if not ok else _fmt_span((min(ok), max(ok)), 1)
                                + ("" if len(ok) == len(vals) else " (not everywhere)"))
            split = f"{res['inner']} / {res['outer']}"
        rows.append(f"| {p.id} | {br.speed_rpm:.0f} | {meas_s} | {_fmt_span(br.inner_rpm)} "
                    f"({_fmt_span(br.inner_slip_percent, 2)}) | {_fmt_span(br.outer_rpm)} "
                    f"({_fmt_span(br.outer_slip_percent, 2)}) | {split} |")
        brm = point_brackets(vs, p, "measured")
        if brm is not None:
            rows.append(f"| {p.id} (measured angles) | {brm.speed_rpm:.0f} | | {_fmt_span(brm.inner_rpm)} "
                        f"({_fmt_span(brm.inner_slip_percent, 2)}) | {_fmt_span(brm.outer_rpm)} "
                        f"({_fmt_span(brm.outer_slip_percent, 2)}) | |")
    return head + "\n".join(rows) + "\n"


if __name__ == "__main__":  # python3 -m flexbearing.studies.validation.brackets: the docs' bracket tables
    for _vs in load_all():
        print(f"### {_vs.series.id}\n")
        print(bracket_table(_vs))
